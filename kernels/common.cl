// shadelab kernels: notation, the model constant block and light layout shared by every model.
//
// Notation (docs/notation.md): all vectors are world-space and unit length.
//   N  surface normal          L  direction from the surface to the light
//   V  direction to the viewer H  half vector normalize(L + V)
//   NoL = dot(N, L), NoV = dot(N, V), NoH = dot(N, H), VoH = dot(V, H), LoV = dot(L, V)
//
// Convention: a model's eval function returns the outgoing radiance per unit light radiance, WITH the
// incident cosine, and scaled so that a white Lambert surface lit head-on returns 1:
//   value = pi * f_r(L, V) * NoL   for physically based BRDFs f_r,
//   the seeds' own expressions for the artist models (which already include NoL and no 1/pi).
#ifndef SHADELAB_COMMON_CL
#define SHADELAB_COMMON_CL

// PoCL's work-item vectoriser stops at calls it cannot inline: every helper is forced inline.
#define SL_INLINE inline __attribute__((always_inline))

#define SL_PI 3.14159265358979323846f
#define SL_INV_PI 0.31830988618379067154f

// Must match kModelConstCount in host/models/catalogue.hpp.
#define SL_MAX_CONSTS 24

// Per-model constants, filled once on the host from the user's parameters (derived constants such as
// Oren-Nayar's A and B are computed there, not per fragment). Gradient uses an array of three:
// [0] itself, [1] model A, [2] model B.
typedef struct {
    float albedo[4];     // diffuse colour (rgb, linear)
    float specular[4];   // specular colour (rgb, linear)
    float c[SL_MAX_CONSTS];
} ModelConsts;

// One light. Must match struct LightGPU in host/shade/shader.cpp.
typedef struct {
    float4 pos_or_dir;   // directional: unit direction TO the light; point: world position
    float4 radiance;     // rgb = colour * intensity
    float4 params;       // x: type (0 directional, 1 point); y: range (0 = unbounded)
} Light;

SL_INLINE float sl_saturate(float x) { return clamp(x, 0.0f, 1.0f); }
SL_INLINE float3 sl_albedo(__constant const ModelConsts* mc) { return vload3(0, mc->albedo); }
SL_INLINE float3 sl_specular(__constant const ModelConsts* mc) { return vload3(0, mc->specular); }

// Non-finite values can only come from invalid input (a NaN normal, a zero light vector); they are
// written as 0 so no image or table ever holds NaN/Inf. The host validates inputs and reports them.
SL_INLINE float3 sl_finite_or_zero(float3 v) { return select(v, (float3)(0.0f), isnan(v) | isinf(v)); }

// Precision modes. The default ("precise") uses the OpenCL built-ins as written in the models (PoCL's
// implementations, ~1-4 ulp). SL_FAST ("fast") maps them to the hardware-speed native_ forms and to an
// exp2/log2 pow, accepting larger error; the error of every model in fast mode is measured against the
// double reference and documented in docs/precision.md (and bounded by tests/test_precision.cpp).
// The mapping is done with function-like macros so that the model files stay written in plain OpenCL C.
#ifdef SL_FAST
SL_INLINE float sl_fast_pow(float x, float y) {
    // pow(0, y) is 0 for y > 0, 1 for y == 0, inf for y < 0; negative bases are invalid input (NaN).
    const float r = native_exp2(y * native_log2(x));
    return x == 0.0f ? (y == 0.0f ? 1.0f : (y > 0.0f ? 0.0f : INFINITY)) : r;
}
// PoCL's native_sin/cos/tan lose their argument reduction past about 5e4 rad (measured: cos off by 0.023 in
// [1e5, 1e6]); only a gradient blend with a tiny period reaches there. Large arguments take the full functions.
SL_INLINE float sl_fast_sin(float x) { return fabs(x) < 3.0e4f ? native_sin(x) : sin(x); }
SL_INLINE float sl_fast_cos(float x) { return fabs(x) < 3.0e4f ? native_cos(x) : cos(x); }
SL_INLINE float sl_fast_tan(float x) { return fabs(x) < 3.0e4f ? native_tan(x) : tan(x); }
// PoCL's own headers already define most built-ins as macros: undefine them first (no redefinition warnings).
#undef pow
#undef powr
#undef exp
#undef exp2
#undef log
#undef log2
#undef sqrt
#undef rsqrt
#undef sin
#undef cos
#undef tan
#define pow(x, y) sl_fast_pow((x), (y))
#define powr(x, y) sl_fast_pow((x), (y))
#define exp(x) native_exp(x)
#define exp2(x) native_exp2(x)
#define log(x) native_log(x)
#define log2(x) native_log2(x)
#define sqrt(x) native_sqrt(x)
#define rsqrt(x) native_rsqrt(x)
#define sin(x) sl_fast_sin(x)
#define cos(x) sl_fast_cos(x)
#define tan(x) sl_fast_tan(x)
#define divide(x, y) native_divide((x), (y))
#endif

#endif
