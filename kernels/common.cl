// shadelab kernels: notation and the helpers shared by every model.
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

// PoCL's work-item vectoriser stops at calls it cannot inline: every helper is forced inline. Static, so that a
// program holds only the helpers its kernels call: an external one is kept in the program's bitcode whether
// called or not, and PoCL parses that whole bitcode again each time a process loads the program from a binary
// (two thirds of a single-model program's bitcode were unused helpers; docs/speed.md, "A warm batch").
#define SL_INLINE static inline __attribute__((always_inline))

#define SL_PI 3.14159265358979323846f
#define SL_INV_PI 0.31830988618379067154f

// The constant block of every model (ModelConsts: albedo, specular and the model's own struct in `block`) and
// the light and view structs: declared once, for the kernels and the host alike, in consts/ (the host checks
// their layout at compile time, tests/test_layout.cpp on the device).
#include "consts/model_consts.h"
#include "consts/scene.h"

// A model's own constants as its named struct (consts/<family>.h), e.g. SL_CONSTS(OrenNayarConsts, mc)->A.
// The models read their constants from a private copy that each kernel makes on entry (SL_PRIVATE_CONSTS), not
// from __constant memory: a load from a kernel argument under a condition (x > 0 ? pow(x, k->n) : 0) cannot be
// hoisted out of PoCL's work-item loop, and on AVX2 the loop vectoriser's cost model then rejects the whole loop
// (a gather per fragment; "the cost-model indicates that vectorization is not beneficial" for 40 of 46 models on
// pthread-haswell). The copy's loads are unconditional, at the top, and hoisted; SROA removes the copy.
#define SL_CONSTS(T, mc) ((const T*)(mc)->block)

// How many ModelConsts a kernel's model reads: its own, then one per child (gradient: mc + 1, mc + 2), copied
// one by one (a copy loop stays a memcpy call in the work-item loop, which the vectoriser refuses).
#if defined(SL_CHILD1_EVAL)
#define SL_CONSTS_COUNT 3
#define SL_COPY_CONSTS(d, s) d[0] = (s)[0], d[1] = (s)[1], d[2] = (s)[2]
#elif defined(SL_CHILD0_EVAL)
#define SL_CONSTS_COUNT 2
#define SL_COPY_CONSTS(d, s) d[0] = (s)[0], d[1] = (s)[1]
#else
#define SL_CONSTS_COUNT 1
#define SL_COPY_CONSTS(d, s) d[0] = (s)[0]
#endif

// Declares `name`, a private copy of the SL_CONSTS_COUNT ModelConsts at the __constant pointer `src`.
#define SL_PRIVATE_CONSTS(name, src) \
    ModelConsts name[SL_CONSTS_COUNT]; \
    SL_COPY_CONSTS(name, src)

SL_INLINE float sl_saturate(float x) { return clamp(x, 0.0f, 1.0f); }

// ---- float3-free vector algebra ----------------------------------------------------------------------------
// PoCL 3.1's work-item loop vectoriser (LLVM 15) gives up on any vector-typed instruction ("instruction return
// type cannot be vectorized"), so a model written with float3 runs one fragment at a time. The model files
// therefore use a struct of three scalars and these helpers: every operation stays scalar, and the loop over
// work-items is vectorised (8 fragments per instruction on this device). Results are per-channel scalars (sl_rgb).
// Both structs are padded past 16 bytes on purpose: the x86-64 ABI passes and returns a struct of three floats
// as a <2 x float> register plus a float, and those <2 x float> pieces survive inlining as vector
// instructions, which stop the loop vectoriser. A struct over 16 bytes goes through memory and is split into
// scalars once inlined. The padding is never read or written.
typedef struct { float x, y, z, pad_[2]; } sl_v3;
typedef struct { float r, g, b, pad_[2]; } sl_rgb;

SL_INLINE sl_v3 sl_v3_make(float x, float y, float z) { sl_v3 v; v.x = x; v.y = y; v.z = z; return v; }
SL_INLINE sl_v3 sl_add(sl_v3 a, sl_v3 b) { return sl_v3_make(a.x + b.x, a.y + b.y, a.z + b.z); }
SL_INLINE sl_v3 sl_sub(sl_v3 a, sl_v3 b) { return sl_v3_make(a.x - b.x, a.y - b.y, a.z - b.z); }
SL_INLINE sl_v3 sl_scale(sl_v3 a, float s) { return sl_v3_make(a.x * s, a.y * s, a.z * s); }
// a . b
SL_INLINE float sl_dot(sl_v3 a, sl_v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
// a x b
SL_INLINE sl_v3 sl_cross(sl_v3 a, sl_v3 b) {
    return sl_v3_make(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
// |a|
SL_INLINE float sl_length(sl_v3 a) { return sqrt(sl_dot(a, a)); }
// a / |a| (a != 0)
SL_INLINE sl_v3 sl_normalize(sl_v3 a) { return sl_scale(a, rsqrt(sl_dot(a, a))); }

// Per-channel results: the common "albedo * d + specular * s" shape of the models.
SL_INLINE sl_rgb sl_rgb_make(float r, float g, float b) { sl_rgb v; v.r = r; v.g = g; v.b = b; return v; }
// albedo * d
SL_INLINE sl_rgb sl_albedo_times(const ModelConsts* mc, float d) {
    return sl_rgb_make(mc->albedo[0] * d, mc->albedo[1] * d, mc->albedo[2] * d);
}
// albedo * d + specular * s
SL_INLINE sl_rgb sl_diffuse_specular(const ModelConsts* mc, float d, float s) {
    return sl_rgb_make(mc->albedo[0] * d + mc->specular[0] * s, mc->albedo[1] * d + mc->specular[1] * s,
                       mc->albedo[2] * d + mc->specular[2] * s);
}
// (1 - t) a + t b, per channel (OpenCL's mix)
SL_INLINE sl_rgb sl_rgb_mix(sl_rgb a, sl_rgb b, float t) {
    return sl_rgb_make(mix(a.r, b.r, t), mix(a.g, b.g, t), mix(a.b, b.b, t));
}



// ---- non-finite results ------------------------------------------------------------------------------------
// A non-finite channel (only from invalid input: a NaN normal, a zero light vector) is written as 0, so no image
// or table ever holds NaN/Inf (the photometric kernels and eval_directions; the shade kernel writes the whole
// fragment black, sl_finite_mask3 below). Without a comparison: three comparisons in a row (one per channel) are
// what LLVM's SLP vectoriser starts from to pack the channels into a <2 x float>, and one packed instruction stops
// PoCL's loop vectoriser. Adding 1 to the exponent field carries into the sign bit exactly when the field is 255
// (Inf, NaN), and an arithmetic shift spreads that bit into the mask that clears the value: four vector
// operations, where the former shift-mask-add-shift form took six (docs/speed.md, "A store path from registers").
SL_INLINE float sl_finite_or_zero(float v) {
    const uint u = as_uint(v);
    const int nonfinite = (int)((u & 0x7f800000u) + 0x00800000u) >> 31;   // -1 iff the exponent field is all ones
    return as_float(u & ~(uint)nonfinite);
}

// All ones when r, g and b are all finite, else 0: the shade kernels write a fragment with a non-finite channel
// as black. 0 v is +-0 for every finite v and NaN for an infinite or NaN one (IEEE 754; no fast-math flag lets
// LLVM fold it, in either mode), so the sum is +-0 exactly when all three are finite: three operations, one
// comparison and an and a channel, where a test per channel (sl_finite_or_zero) took four a channel.
SL_INLINE uint sl_finite_mask3(float r, float g, float b) {
    const float z = fma(0.0f, b, fma(0.0f, g, 0.0f * r));
    return z == 0.0f ? 0xffffffffu : 0u;
}

// floor(x) for x >= 0 (and NaN), four lane-wise operations where PoCL 3.1's floor vectorises to about twelve (a
// truncation, a correction for negative x, and tests for large and special values; perf annotate of banded).
// Below 2^23 truncation toward zero is floor for x >= 0, and the conversion to int and back is exact; from 2^23
// on every float is a whole number, so x is its own floor (+inf and NaN too, which the comparison sends there:
// the conversion's value for them is not used).
SL_INLINE float sl_floor_nonneg(float x) { return x < 8388608.0f ? convert_float(convert_int(x)) : x; }

// ---- several fragments a work-item: SL_VECTOR_WIDTH ----------------------------------------------------------
// The fragments (or photometric rows) one work-item evaluates, in one loop that clang's loop vectoriser widens to
// that many lanes (kernels/shade_fragments.cl, kernels/photometry.cl): SL_VECTOR_WIDTH, which the host's Runtime
// passes to every program (the device's native float vector width: 16 on AVX-512, 8 on AVX2; 1 when a program is
// built without it), and the host launches n / SL_FRAGS_PER_ITEM work-items. Why not one fragment a work-item,
// as PoCL's own work-item loop vectoriser would widen it: that vectoriser keeps to 8 lanes on AVX-512 hosts
// (LLVM's 256-bit preference for skylake-avx512) and never interleaves, and the transcendental models are
// latency-bound chains (Hapke: ~550 cycles an iteration against a throughput bound of 244, llvm-mca): 16 lanes in
// 512-bit registers carry twice the work through the same chain (docs/speed.md, "Sixteen lanes"). The
// dispatching kernel (SL_DISPATCH) cannot be vectorised at all (its switch): the same loop, no request.
// clang may not widen the loop when it first optimises the program (clBuildProgram); it is widened later, in
// PoCL's work-group compilation (bench_models prints the width), so clang's "loop not vectorized" warning of
// the first stage (-Wpass-failed), which would be noise on the user's stderr, is silenced below.
#ifndef SL_VECTOR_WIDTH
#define SL_VECTOR_WIDTH 1
#endif
// SL_MAX_LANES caps it for one program: the host builds the shade programs of the models that read normals only
// with SL_MAX_LANES=8 (host/shade/shader.hpp, Shader::lanes_for, says why) and launches them accordingly.
// SL_MODEL_LANES sets it for one program: on an 8-lane device the host builds the models measured faster at 16
// lanes (two 256-bit registers a step; ModelInfo::lanes_avx2) with SL_MODEL_LANES=16.
#if defined(SL_MODEL_LANES)
#define SL_LANES SL_MODEL_LANES
#elif defined(SL_MAX_LANES) && SL_MAX_LANES < SL_VECTOR_WIDTH
#define SL_LANES SL_MAX_LANES
#else
#define SL_LANES SL_VECTOR_WIDTH
#endif
// SL_CHAINS=2: the loop is also interleaved twice, two independent chains of SL_LANES lanes through the model, so
// that one chain's instructions fill the other's latency; a work-item then shades 2 SL_LANES fragments. The host
// asks for it for the models whose arithmetic is a long latency-bound chain (ModelInfo::chains, measured per
// model: docs/speed.md; Shader::frags_per_item). With one lane there is no fragment loop, and no second chain.
#if defined(SL_CHAINS) && SL_CHAINS > 1 && SL_LANES > 1
#define SL_CHAINS_PER_ITEM SL_CHAINS
#else
#define SL_CHAINS_PER_ITEM 1
#endif
#define SL_FRAGS_PER_ITEM (SL_LANES * SL_CHAINS_PER_ITEM)
#define SL_PRAGMA_(x) _Pragma(#x)
#define SL_PRAGMA(x) SL_PRAGMA_(x)
#if SL_LANES > 1 && !(defined(SL_DISPATCH) && SL_DISPATCH)
#define SL_FRAGMENT_LOOP SL_PRAGMA(clang loop vectorize_width(SL_LANES) interleave_count(SL_CHAINS_PER_ITEM))
#else
#define SL_FRAGMENT_LOOP
#endif
// Silenced once here for every kernel after common.cl in the program (see above for why).
#pragma clang diagnostic ignored "-Wpass-failed"

// ---- keeping LLVM's SLP vectoriser away, where it matters -------------------------------------------------------
// Before PoCL builds its work-item loop, LLVM's SLP vectoriser packs two isomorphic, independent scalar
// computations of one fragment (the same function of NoL and of NoV, the same step at two thresholds) into one
// <2 x float> computation, and a single such instruction stops the work-item loop vectoriser ("instruction return
// type cannot be vectorized"): the whole model then runs one fragment at a time. sl_after(x, dep) is x, made to
// depend on dep, so that a computation started from it cannot be bundled with the one that produced dep (a
// bundle's members must be independent). x + 0 * dep cannot be folded under IEEE rules (0 * dep is NaN for an
// infinite or NaN dep, -0 for a negative one), costs one fma, and is x itself for every finite dep (up to the sign
// of a zero x).
// That dependence has a price: the models' isomorphic chains (Hapke's terms of i and of e, Oren-Nayar's two
// angles, one light after another) then run one after the other, and these loops are latency-bound. Where the
// program's kernels widen the explicit fragment loop above (SL_LANES > 1, not the dispatching kernel), every
// model vectorises without it, as measured (bench_models --require-vectorised and its tests, AVX-512 and
// AVX2 targets, one light and two): there sl_after is x itself. Alternated in one process (bench_models, 1M to
// 16M, 2026-12-06): the Hapke laws 1.04-1.25x, oren_nayar_full 1.11-1.25x, oren_nayar_seed003 1.19-1.24x, eon
// 1.10-1.15x, minnaert_b 1.10-1.24x; the median of all rows 1.01x (docs/speed.md, "In order only where it matters").
#if SL_LANES > 1 && !(defined(SL_DISPATCH) && SL_DISPATCH)
SL_INLINE float sl_after(float x, float dep) { (void)dep; return x; }
#else
SL_INLINE float sl_after(float x, float dep) { return fma(0.0f, dep, x); }
#endif

// ---- streaming stores: a work-item's outputs written past the cache -------------------------------------------
// A plain store to a line that is not in the cache first reads the line from memory (write-allocate), so an
// output plane larger than the cache costs its bytes twice; a non-temporal store (x86 MOVNTPS) writes whole lines
// straight to memory. The shade kernels collect a work-item's SL_FRAGS_PER_ITEM results of a plane in a private
// block and write it with sl_store_block: non-temporal when the host says so for that plane (`streamed`: the
// plane's bit of the kernel's `stream` mask, Shader::streams_output, set only where the plane starts on a 64-byte
// line, so that every work-item's block does: MOVNTPS faults on a misaligned address), a plain vector store
// otherwise. The block, not the loop's scalar stores: LLVM's loop vectoriser will not widen a non-temporal store
// of a float (its alignment is below the vector's). It is stored one vector of SL_LANES a time, as the loop's
// chains computed it: a 16-float load from a block that two 8-lane chains wrote as two halves waits for both
// stores to leave the core (a failed store-to-load forward), and a load that is not known to be aligned was
// split into 16-byte pieces. The mask is decided on the host, once a launch, not from the address in every
// work-item: the address test and a `stream` flag together made LLVM keep the block on the stack and move it
// in pieces. docs/speed.md, "Streaming stores" and "A store path from registers", has the measurements.
#if SL_LANES % 16 == 0
#define SL_STORE_LINE 16
#define SL_STORE_VEC float16
typedef float sl_float16_u __attribute__((ext_vector_type(16), aligned(4)));   // a float16 at any float's address
#define SL_STORE_VEC_U sl_float16_u
#elif SL_LANES % 8 == 0
#define SL_STORE_LINE 8
#define SL_STORE_VEC float8
typedef float sl_float8_u __attribute__((ext_vector_type(8), aligned(4)));
#define SL_STORE_VEC_U sl_float8_u
#endif
#define SL_STREAM_PLANE(c) (1u << (c))   // the bit of output plane c (0 r, 1 g, 2 b) in `stream`
#ifdef SL_STORE_LINE
#define SL_BLOCK_ALIGN __attribute__((aligned(SL_STORE_LINE * 4)))
SL_INLINE void sl_store_block(__global float* restrict dst, const float* restrict block, bool streamed) {
    __global SL_STORE_VEC* line = (__global SL_STORE_VEC*)dst;
    const SL_STORE_VEC* from = (const SL_STORE_VEC*)block;   // SL_BLOCK_ALIGN: an aligned vector load
    if (streamed) {
        for (uint j = 0; j < SL_FRAGS_PER_ITEM / SL_STORE_LINE; ++j) __builtin_nontemporal_store(from[j], line + j);
    } else {
        // unrolled, through a vector type of a float's alignment: vstore8 / vstore16 in a loop of two were kept as
        // a loop that reloaded the block from the stack and stored it in 16-byte pieces (objdump, AVX2 code), 47
        // of lambert's 113 loop instructions at two chains; this is one unaligned vector store a vector
        // (docs/speed.md#plain-store-path)
#pragma unroll
        for (uint j = 0; j < SL_FRAGS_PER_ITEM / SL_STORE_LINE; ++j) *((__global SL_STORE_VEC_U*)dst + j) = from[j];
    }
}
#else
#define SL_BLOCK_ALIGN
SL_INLINE void sl_store_block(__global float* restrict dst, const float* restrict block, bool streamed) {
    (void)streamed;
    for (uint j = 0; j < SL_FRAGS_PER_ITEM; ++j) dst[j] = block[j];
}
#endif

// ---- trigonometry: own, vectorisable ----------------------------------------------------------------------
// PoCL 3.1's sin, cos, tan, asin, acos, atan and atan2 are library calls that its work-item loop vectoriser
// cannot widen ("call instruction cannot be vectorized"): one call and the whole model runs one fragment at a
// time (oren_nayar_full ran 25 Mfrag/s against 471 for oren_nayar). These are written in float arithmetic with
// fma, integer bit operations and selects only: no tables, no data-dependent branches, no calls, so they are
// widened with the model. Both precision modes map the built-in names to them (the macro blocks below), so a
// model file writes plain OpenCL C (`acos(mu)`) and gets these. Measured error in ulps against double over
// millions of arguments: docs/precision.md ("Own trigonometry") and tests/test_mathfn.cpp (asserted bounds).
// Polynomials: the single-precision minimax coefficients of the Cephes library (S. L. Moshier, Cephes Math
// Library 2.8: sinf.c, tanf.c, atanf.c, asinf.c), evaluated by Horner's scheme with fma.

// x = k pi/2 + r, |r| <= pi/4 (a hair more at rounding ties), k returned as an int. Cody-Waite reduction with pi/2
// in three floats (C1 + C2 + C3 = pi/2 to 1e-23): with fma, x - k C1 is exact (both are multiples of ulp(C1) and
// the difference is below 2, so it fits 24 bits), and k (C2 + C3) is applied in two more fma steps. The error of
// r is then about 2^-24 |r| + |k| 1e-23: below an ulp of r for |x| up to ~1e7 (asserted to 1e6, the largest a
// catalogue model reaches: the gradient at its shortest period). k = rint(x 2/pi) by the 1.5 * 2^23 shift,
// exact for |x 2/pi| < 2^22; beyond |x| ~ 6.6e6 the reduction loses accuracy and the callers only keep their
// result inside the function's range (no bound is claimed there). Not finite x gives NaN.
SL_INLINE float sl_reduce_pio2(float x, int* k) {
    const float kf = (x * 0.636619772f + 12582912.0f) - 12582912.0f;   // rint(x * 2/pi)
    *k = (int)kf;
    float r = fma(-kf, 1.57079637f, x);        // C1 = float(pi/2), exact step
    r = fma(-kf, -4.37113883e-8f, r);          // C2 = float(pi/2 - C1)
    return fma(-kf, -1.71512451e-15f, r);      // C3 = float(pi/2 - C1 - C2)
}

// sin r and cos r for |r| <= pi/4 (Cephes sinf.c / cosf.c minimax polynomials in z = r^2).
SL_INLINE float sl_sin_poly(float r) {
    const float z = r * r;
    return fma(fma(fma(-1.9515295891e-4f, z, 8.3321608736e-3f), z, -1.6666654611e-1f) * z, r, r);
}
SL_INLINE float sl_cos_poly(float r) {
    const float z = r * r;
    const float p = fma(fma(2.443315711809948e-5f, z, -1.388731625493765e-3f), z, 4.166664568298827e-2f);
    return fma(p * z, z, fma(-0.5f, z, 1.0f));
}

// The sign bit set when bit 1 of q is set: the quadrant's sign as a mask to XOR into a float.
SL_INLINE uint sl_quadrant_sign(int q) { return ((uint)q & 2u) << 30; }

// sin x = (sin r, cos r, -sin r, -cos r) for k mod 4 = 0, 1, 2, 3. Both polynomials are evaluated and one is
// selected: a branch on the quadrant would split the vectorised loop. The clamp to [-1, 1] only matters past
// |x| ~ 6.6e6 (see sl_reduce_pio2), where it keeps the value a sine's.
SL_INLINE float sl_sin(float x) {
    int k;
    const float r = sl_reduce_pio2(x, &k);
    const float v = (k & 1) ? sl_cos_poly(r) : sl_sin_poly(r);
    return clamp(as_float(as_uint(v) ^ sl_quadrant_sign(k)), -1.0f, 1.0f);
}

// cos x = (cos r, -sin r, -cos r, sin r) for k mod 4 = 0, 1, 2, 3: the sign of quadrant k + 1.
SL_INLINE float sl_cos(float x) {
    int k;
    const float r = sl_reduce_pio2(x, &k);
    const float v = (k & 1) ? sl_sin_poly(r) : sl_cos_poly(r);
    return clamp(as_float(as_uint(v) ^ sl_quadrant_sign(k + 1)), -1.0f, 1.0f);
}

// tan x = tan r for even k, -1 / tan r for odd k (Cephes tanf.c polynomial, |r| <= pi/4). At a pole of tan
// (x the float nearest an odd multiple of pi/2) r is a few 1e-8, never 0, so -1/tan r is large and finite.
SL_INLINE float sl_tan(float x) {
    int k;
    const float r = sl_reduce_pio2(x, &k);
    const float z = r * r;
    const float p = fma(fma(fma(fma(fma(9.38540185543e-3f, z, 3.11992232697e-3f), z, 2.44301354525e-2f), z,
                                5.34112807005e-2f), z, 1.33387994085e-1f), z, 3.33331568548e-1f);
    const float t = fma(p * z, r, r);
    return (k & 1) ? -1.0f / t : t;
}

// atan u for |u| <= tan(pi/8) = 0.4142 (Cephes atanf.c polynomial in z = u^2).
SL_INLINE float sl_atan_poly(float u) {
    const float z = u * u;
    return fma(fma(fma(fma(8.05374449538e-2f, z, -1.38776856032e-1f), z, 1.99777106478e-1f), z,
                   -3.33329491539e-1f) * z, u, u);
}

// atan(lo / hi) for 0 <= lo <= hi (an angle in [0, pi/4]) with one division: for lo / hi > tan(pi/8),
//   atan(lo / hi) = pi/4 + atan((lo - hi) / (lo + hi))    (Cephes' reduction, atan t = pi/4 + atan((t-1)/(t+1)))
// with the quotient formed from lo and hi directly. hi = 0 (lo = 0 too) gives 0, not 0/0: the denominator is
// floored at the smallest denormal, which changes no other quotient. (A select "den > 0 ? num / den : 0"
// becomes a branch around the division, and LLVM's SLP vectoriser packs the phis of two such branches side by
// side, e.g. two atan2 in one model, into <2 x float>, which stops PoCL's loop vectoriser.)
SL_INLINE float sl_atan_ratio(float lo, float hi) {
    const int big = lo > 0.41421356f * hi;
    const float num = big ? lo - hi : lo;
    const float den = big ? lo + hi : hi;
    const float u = num / fmax(den, 1.40129846e-45f);
    return (big ? 0.785398163f : 0.0f) + sl_atan_poly(u);
}

// pi/2 - a and pi - a with pi/2 and pi in two floats (hi + lo), so that the constant adds no rounding of its own.
SL_INLINE float sl_pio2_minus(float a) { return (1.57079637f - a) + -4.37113883e-8f; }
SL_INLINE float sl_pi_minus(float a) { return (3.14159274f - a) + -8.74227766e-8f; }

// atan2(y, x): the angle of (x, y) in [-pi, pi]. From a = atan(min / max) of |x| and |y|: pi/2 - a when |y| >
// |x|, pi - that when x < 0, with the sign of y. atan2(+-0, x) = +-0 for x >= 0 (including -0: OpenCL gives pi
// for x = -0; no model passes a signed zero that way) and +-pi for x < 0; atan2(0, 0) = 0.
SL_INLINE float sl_atan2(float y, float x) {
    // |y| as fmax(y, -y), not fabs: two fabs side by side are what LLVM's SLP vectoriser packs into one
    // <2 x float> operation, which stops PoCL's loop vectoriser (fmax(y, -y) = |y|; a NaN y gives -y, a NaN).
    const float ax = fabs(x), ay = fmax(y, -y);
    float a = sl_atan_ratio(fmin(ax, ay), fmax(ax, ay));
    a = ay > ax ? sl_pio2_minus(a) : a;
    a = x < 0.0f ? sl_pi_minus(a) : a;
    return copysign(a, y);
}

// atan x = atan2(x, 1).
SL_INLINE float sl_atan(float x) { return sl_atan2(x, 1.0f); }

// asin x for |x| <= 1 (Cephes asinf.c): |x| <= 1/2: the polynomial in z = x^2; |x| > 1/2:
//   asin |x| = pi/2 - 2 asin(s),  s = sqrt((1 - |x|) / 2) <= 1/2
// (1 - |x| is exact there, so the result keeps its accuracy as |x| -> 1). Both inputs go through the same
// polynomial; |x| > 1 gives NaN (sqrt of a negative), as asin does.
SL_INLINE float sl_asin_poly(float s) {
    const float z = s * s;
    const float p = fma(fma(fma(fma(4.2163199048e-2f, z, 2.4181311049e-2f), z, 4.5470025998e-2f), z,
                            7.4953002686e-2f), z, 1.6666752422e-1f);
    return fma(p * z, s, s);
}
// Both forms' inputs are computed, then one is selected: "big ? sqrt(.) : x" would be compiled as a branch
// around the sqrt, whose phi LLVM's SLP vectoriser pairs with the phi of a second call (see sl_atan_ratio).
SL_INLINE float sl_asin(float x) {
    const float ax = fabs(x);
    const int big = ax > 0.5f;
    const float s_big = sqrt(fmax(0.5f * (1.0f - ax), 0.0f));   // fmax: |x| > 1 gives asin's NaN below
    const float s = big ? s_big : ax;
    const float p = sl_asin_poly(s);
    return copysign(big ? sl_pio2_minus(2.0f * p) : p, x);
}

// acos x for |x| <= 1: pi/2 - asin x for |x| <= 1/2; for |x| > 1/2 from s = sqrt((1 - |x|) / 2),
//   acos x = 2 asin(s) (x > 0),  pi - 2 asin(s) (x < 0),
// which keeps acos accurate near x = 1, where pi/2 - asin x would cancel (acos(1 - d) ~ sqrt(2 d)).
SL_INLINE float sl_acos(float x) {
    const float ax = fabs(x);
    const int big = ax > 0.5f;
    const float s_big = sqrt(fmax(0.5f * (1.0f - ax), 0.0f));   // as in sl_asin
    const float s = big ? s_big : x;
    const float p = sl_asin_poly(s);
    const float near_one = x > 0.0f ? 2.0f * p : sl_pi_minus(2.0f * p);
    return big ? near_one : sl_pio2_minus(p);
}

// ---- pow: three forms --------------------------------------------------------------------------------------
// PoCL 3.1's built-in pow is very slow on the CPU driver (3.4 M/s against 1700 M/s for a copy, measured with a
// micro-kernel; docs/precision.md), and so are its float exp2 and log2 (47 and 85 M/s): they are calls the work-
// item loop vectoriser cannot widen. All three forms here compute
//   x^y = 2^(y log2 x),  x = 2^e m,  m in [sqrt(1/2), sqrt(2)),
//   log2 m = (2 / ln 2) atanh(s) = (2 / ln 2) (s + s^3/3 + s^5/5 + ...),  s = (m - 1) / (m + 1),  |s| <= 0.1716
// (Abramowitz & Stegun 4.1.27), 2^t = 2^k 2^f with k = rint(t) (sl_pow_cr: e^(f ln 2) by Taylor series; the float
// forms: a polynomial fitted to 2^f), with no tables, no data-dependent branches and no calls, so they vectorise
// with the model (sl_fast_pow: m in [2/3, 4/3), and a fitted polynomial for log2 too). They differ in how much of
// y log2 x they keep, which sets the error: a rounding dt of t = y log2 x is a relative error ln 2 dt of the
// result, and a float t is rounded to 2^-24 |t|, |t| = -log2(result) (up to 126 for results near 2^-126).
//   sl_pow      precise mode: float arithmetic, t carried as a float-float pair (hi + lo): 1.3 ulp for results
//               >= 2^-10, 4.1 ulp below (measured and asserted: docs/precision.md, tests/test_precision.cpp)
//   sl_fast_pow fast mode: plain float, t rounded to one float: error growing with |t| (stated and asserted there);
//               finite x >= 0 and finite y only (-ffinite-math-only's contract: every model's base is such a value)
//   sl_pow_cr   double arithmetic, correctly rounded over the whole sweep (0.5 ulp)
// Precise mode uses sl_pow, fast mode sl_fast_pow, by measurement in the models (bench_models, 1M fragments,
// three alternating runs on this project's AVX-512 host, medians): precise Mfrag/s with sl_pow / sl_pow_cr:
// minnaert_1941 245 / 219, phong 233 / 219, blinn_phong 199 / 192, minnaert_b 162 / 150, toon 324 / 143; fast
// mode's sl_fast_pow: 262, 247, 219, 385, 184 (docs/precision.md, "pow"). -DSL_POW_CR makes precise mode use
// sl_pow_cr, for a model whose conditioning needs a correctly rounded power; none in the catalogue does (every
// model's error bound holds with sl_pow). -DSL_BUILTIN_POW keeps PoCL's pow.

// Results below 2^-126 (denormal floats, under 1.2e-38) are 0 in all three forms (flush to zero, which OpenCL 1.2
// allows for single precision: CL_FP_DENORM is optional). Why: on x86 an operation that produces or reads a
// denormal takes a microcode assist (of the order of 100 cycles for the whole vector), and a highlight's NoH^n
// is that small for a band of fragments: with denormal powers blinn_phong ran 77-80 Mfrag/s, flushed 180-191
// (bench_models, 1M fragments, three alternating runs). No pixel can show such a value.

// Special cases, as OpenCL's pow for every base the models pass (x >= 0, finite y): pow(x, 0) = 1 (any x),
// pow(1, y) = 1, pow(0, y) = 0 for y > 0 and +inf for y < 0, pow(+inf, y) = +inf / 0 for y > 0 / < 0. A negative
// base gives NaN (the models never use one: they clamp bases, or select the value away where the base is
// negative), and so does a NaN argument. r is the value of the formula for the other (finite, positive) bases.
// sl_pow and sl_pow_cr use this; fast mode's sl_fast_pow keeps only the cases of finite x >= 0 (see there).
SL_INLINE float sl_pow_special(float x, float y, float r) {
    const float at_zero = y > 0.0f ? 0.0f : INFINITY;   // x == 0 (y != 0)
    const float at_inf = y > 0.0f ? INFINITY : 0.0f;    // x == +inf (y != 0)
    float v = x == 0.0f ? at_zero : (x == INFINITY ? at_inf : r);
    v = (x < 0.0f || x != x || y != y) ? NAN : v;   // x != x: NaN; one unordered compare, not 2 isnan
    return (y == 0.0f || x == 1.0f) ? 1.0f : v;
}

// x = 2^e m with m in (lo, 2 lo] for a normal float x > 0 (x >= 2^-126), where lo_bits is bits(lo) + 1 for a
// float lo in [1/2, 1): e is the exponent field of bits(x) - lo_bits, which crosses into the next binade exactly
// where x's significand exceeds 2 lo, so m = x / 2^e by subtracting e from the exponent field: 3 integer
// operations and a conversion, no compare and select. Returns m and sets *e. For 0 and the denormals the values
// have no meaning, but m is a normal float in [1/2, 2) (no operation on it meets a denormal).
SL_INLINE float sl_split_normal_at(float x, uint lo_bits, float* e) {
    const uint bits = as_uint(x);
    const int ei = (int)(bits - lo_bits) >> 23;
    *e = (float)ei;
    return as_float(bits - ((uint)ei << 23));   // unsigned: ei < 0 for x < 1
}

// The same for finite x >= 0, denormals included (scaled by 2^24 first). Returns m and sets *e (for x = 0, values
// of no meaning). Precise pow splits this way (sl_split_log2, at lo = sqrt(1/2)); fast pow takes the denormals
// as 0 (sl_fast_pow) and splits normal floats only (sl_log2_f, sl_split_normal_at at lo = 2/3).
SL_INLINE float sl_split_at(float x, uint lo_bits, float* e) {
    const int sub = x < 1.17549435e-38f;
    const float m = sl_split_normal_at(sub ? x * 16777216.0f : x, lo_bits, e);
    *e -= sub ? 24.0f : 0.0f;   // exact: |e| < 2^8
    return m;
}

// x = 2^e m with m in (c / 2, c] for finite x > 0, c = 1.41421354f (sqrt 2 in float, c / 2 exact): sl_split_at at
// bits(c / 2) + 1. The same m and e, bit for bit, as the former "m0 > c ? m0 / 2 : m0" of the significand m0 in
// [1, 2), in 4 integer operations for 9 (tests/test_precision.cpp sweeps x == m 2^e, m in (c / 2, c]): precise
// pow 1.00-1.06x (median 1.02x) in the pow models at 1M and 4M, alternated in one process, where the same code
// against itself gave 0.97-1.07x (2026-12-05; docs/precision.md, "Precise-mode pow").
SL_INLINE float sl_split_log2(float x, float* e) { return sl_split_at(x, 0x3f3504f4u, e); }   // c / 2: 0x3f3504f3

// Q(f) = (2^f - 1) / f for |f| <= 1/2 (and the few ulps of a float-float low part beyond): degree 5, fitted for
// the relative error of 2^f = 1 + f Q(f) (Lawson-weighted least squares: 1.1e-8; 1.6e-7 for f Q(f) evaluated in
// float), by Estrin's scheme (the three pairs are independent: 4 operations deep where Horner's is 6).
// kernels/models/planetary.cl's exponentials use it too.
SL_INLINE float sl_exp2_q(float f) {
    const float f2 = f * f;
    const float q01 = fma(2.402264923e-1f, f, 6.931471825e-1f), q23 = fma(9.618237615e-3f, f, 5.550357327e-2f);
    const float q45 = fma(1.540348021e-4f, f, 1.339071780e-3f);
    return fma(f2 * f2, q45, fma(f2, q23, q01));
}

// 2^f for |f| <= 1/2 as 1 + f Q(f): no multiplication by ln 2 (the Taylor series of e^(f ln 2) to degree 7 it
// replaces took one, and 6e-9).
SL_INLINE float sl_exp2_poly(float f) { return fma(f, sl_exp2_q(f), 1.0f); }

// ---- sl_pow (precise mode): float, the exponent as a float-float pair

// log2 x = hi + lo for finite x > 0, the atanh series to s^9/9 (first omitted term, s^10/11 relative, < 2.1e-9
// of the sum). The leading term (2 / ln 2) s is formed in float-float: s from the division's fma residual (its
// low part s_lo = residual / b, with 1 / b = (1 - s) / 2 exactly for s = (m - 1)/(m + 1), so no second division;
// s_lo is 2^-24 of s, so the rounding of (1 - s) / 2 does not matter), 2 / ln 2 as two floats. The tail of the
// series (below 1% of the sum) in float; lo carries the roundings of hi.
SL_INLINE float sl_log2_ff(float x, float* lo) {
    float e;
    const float m = sl_split_log2(x, &e);
    const float a = m - 1.0f;                                   // exact
    const float b = m + 1.0f, b_lo = m - (b - 1.0f);            // m + 1 = b + b_lo exactly
    const float s = a / b;
    const float s_lo = (fma(-s, b, a) - s * b_lo) * fma(-0.5f, s, 0.5f);   // a / (b + b_lo) - s
    const float s2 = s * s, s4 = s2 * s2;
    // Estrin: s^2/3 + s^4 (1/5 + s^2/7 + s^4/9)
    const float tail = s2 * (1.0f / 3.0f) + s4 * (fma(s2, 1.0f / 7.0f, 0.2f) + s4 * (1.0f / 9.0f));
    const float c_hi = 2.88539004f, c_lo = 3.85192598e-8f;      // 2 / ln 2 = c_hi + c_lo
    const float p = c_hi * s, p_lo = fma(c_hi, s, -p);        // c_hi s = p + p_lo exactly
    const float tail_p = p * tail;                              // below 1% of p
    const float l_hi = p + tail_p;
    const float l_lo = ((p - l_hi) + tail_p) + (p_lo + c_lo * s + c_hi * s_lo);
    const float hi = e + l_hi;                                  // |e| >= 1 > |l_hi| or e = 0: exact remainder
    *lo = (l_hi - (hi - e)) + l_lo;
    return hi;
}

// 2^(t + t_lo) for t in [-126, 128) (0 below: flush to zero; +inf from 128 on, beyond the float range):
// k = rint(t) by the 1.5 * 2^23 shift, f = (t - k) + t_lo (t - k exact), 2^f by sl_exp2_poly, and k added to its
// exponent field: the shifted sum's low bits are k in two's complement, so shifting them up by 23 and adding
// (modulo 2^32) scales by 2^k with no conversion and no multiplication. 2^f is in [2^-1/2, 2^1/2], so the sum is
// a normal float for k in [-126, 127]; k = 128 comes with f < 0 for t in [127.5, 128) (|t_lo| is below 2^-16),
// which gives at most 2^128 (1 - 2^-24), the largest float.
SL_INLINE float sl_exp2_ff(float t, float t_lo) {
    // Clamped at -126: below it the result is flushed to zero (above), and clamping there (not lower), with the
    // low part dropped in the clamped lanes, keeps every lane's scaled value a normal float (a clamped lane
    // computes exactly 2^-126), so no lane computes a denormal it then throws away. (With the low part kept, a
    // clamped lane's 2^(t_lo) < 1 times 2^-126 was a denormal: on the code PoCL generates for AVX2 hosts each such
    // vector multiply took a microcode assist, and phong and blinn_phong ran precise mode at 0.4x: docs/speed.md,
    // "The AVX2 check".)
    const float tc = fmin(fmax(t, -126.0f), 128.0f);
    const float shifted = tc + 12582912.0f, k = shifted - 12582912.0f;
    const float lo = t < -126.0f ? 0.0f : t_lo;
    const float r = as_float(as_uint(sl_exp2_poly((tc - k) + lo)) + (as_uint(shifted) << 23));
    return t < -126.0f ? 0.0f : (t >= 128.0f ? INFINITY : r);
}

// x^y by the formula, for finite x > 0 and finite y (any other x: a finite value of no meaning).
SL_INLINE float sl_pow_formula(float x, float y) {
    float l_lo;
    const float l = sl_log2_ff(x, &l_lo);
    const float t = y * l;
    return sl_exp2_ff(t, fma(y, l, -t) + y * l_lo);   // t + t_lo = y (l + l_lo)
}

SL_INLINE float sl_pow(float x, float y) { return sl_pow_special(x, y, sl_pow_formula(x, y)); }

// sl_pow for a base the model has already made finite and >= 0 (a max with a constant, a clamp, a select), with
// finite y: the same value bit for bit (for x > 0 the formula itself gives sl_pow_special's 1 at y = 0 and at
// x = 1: log2 1 is exactly 0 and 2^0 exactly 1; tests/test_precision.cpp checks this over a sweep), without
// the tests for x < 0, NaN and infinity: 6 lane-wise operations where sl_pow_special takes about 14.
// The models reach it as pow_nonneg (below), which fast mode maps to sl_fast_pow (whose contract this is).
SL_INLINE float sl_pow_nonneg(float x, float y) {
    const float at_zero = y > 0.0f ? 0.0f : (y == 0.0f ? 1.0f : INFINITY);
    return x == 0.0f ? at_zero : sl_pow_formula(x, y);
}

// x1^y1 x2^y2 for finite x1, x2 >= 0 and finite y1, y2 >= 0, as one exponential: 2^(y1 log2 x1 + y2 log2 x2),
// the two logarithms and the sum of the two products in float-float (TwoSum, Knuth: t + t_lo exactly t1 + t2 plus
// both products' low parts), then sl_exp2_ff once: one exponential fewer than two sl_pow_nonneg and a product, and
// one rounding instead of three. A zero base gives 0 when its exponent is > 0 (the product is 0) and adds nothing
// when it is 0 (its log2 is taken of 1, exactly 0): pow(0, 0) = 1 as sl_pow_nonneg. The second logarithm after the
// first (sl_after): the two are what LLVM's SLP vectoriser would pair into one <2 x float> computation, which stops
// the loop vectoriser (MinnaertB_factor_times). A product below 2^-126 is 0 (sl_exp2_ff's flush), as each power's is.
SL_INLINE float sl_pow2_nonneg(float x1, float y1, float x2, float y2) {
    const int zero = (x1 == 0.0f && y1 > 0.0f) || (x2 == 0.0f && y2 > 0.0f);
    float l1_lo, l2_lo;
    const float l1 = sl_log2_ff(x1 == 0.0f ? 1.0f : x1, &l1_lo);
    const float l2 = sl_log2_ff(sl_after(x2 == 0.0f ? 1.0f : x2, l1), &l2_lo);
    const float t1 = y1 * l1, t2 = y2 * l2;
    const float t = t1 + t2, t2v = t - t1;                      // TwoSum: t + ((t1 - (t - t2v)) + (t2 - t2v)) = t1 + t2
    const float sum_lo = (t1 - (t - t2v)) + (t2 - t2v);
    const float t_lo = sum_lo + ((fma(y1, l1, -t1) + y1 * l1_lo) + (fma(y2, l2, -t2) + y2 * l2_lo));
    return zero ? 0.0f : sl_exp2_ff(t, t_lo);
}

// ---- sl_fast_pow (fast mode): plain float

// Fast mode's pow is precise mode's less what a picture cannot show: no float-float product, no division and no
// conversion, and polynomials of the lowest degree that keeps the error bound of results >= 2^-10 (the values a
// pixel shows: 250 ulp, tests/test_precision.cpp) that the former form (a degree-3-in-s^2 log2 after a division,
// a degree-5 exp2) kept. 2026-12-05: the same number of operations in log2 with an fma for the division, two
// fewer in exp2, and 0.97-1.11x (median 1.08x) the former fast pow in the pow models at 1M and 4M fragments
// (docs/precision.md, "Fast-mode pow"); results below 2^-10 lose the most (|t| up to 126 multiplies log2's
// error: 1.6e3 ulp, 1e-4 relative, where the former form had 158 ulp).

// log2 x for a normal float x > 0 (finite for 0 and the denormals too, with no meaning: sl_fast_pow selects those
// away). x = 2^e m with m in (2/3, 4/3] (to float rounding) by sl_split_normal_at at 0x3f2aaaab, the bits of 2/3
// rounded up to float. Then
// log2 m = a P(a), a = m - 1 in [-1/3, 1/3) (exact), P of degree 6 fitted to log2(1 + a) / a for relative error
// (Lawson-weighted least squares, coefficients rounded to float): 1.2e-6 relative evaluated in float, six fmas and
// no division (the atanh form s = (m - 1) / (m + 1) needs one: the costliest instruction of the loop).
// m = 1 gives a = 0 and log2 x = e exactly.
SL_INLINE float sl_log2_f(float x) {
    float e;
    const float a = sl_split_normal_at(x, 0x3f2aaaabu, &e) - 1.0f;
    const float hi = fma(fma(2.46199399e-1f, a, -2.79993892e-1f), a, 2.85692483e-1f);   // Horner, highest first
    const float p = fma(fma(fma(fma(hi, a, -3.58389348e-1f), a, 4.80960906e-1f), a, -7.21379876e-1f), a, 1.44269478f);
    return fma(a, p, e);
}

// 2^t for t in [-126, 128] (0 below, +inf above), without sl_exp2_ff's low part: k = rint(t), f = t - k, and 2^f
// for |f| <= 1/2 by a polynomial of degree 4 in f itself, 1 + f Q(f), Q fitted to (2^f - 1) / f for the relative
// error of 2^f (Lawson-weighted least squares, coefficients rounded to float: 6.2e-6 evaluated in float): no
// multiplication by ln 2. p(0) = 1, so an integer t gives 2^t exactly. k and 2^k come from the one sum
// tc + 1.5 * 2^23 as in sl_exp2_ff (its low bits are k in two's complement, shifted into p's exponent field by one
// integer add: no conversion): p is in [2^-1/2, 2^1/2], so the sum stays a normal float for k in [-126, 127],
// and k = 128 with f <= 0 gives at most 2^128 = +inf.
SL_INLINE float sl_exp2_f(float t) {
    const float tc = fmin(fmax(t, -126.0f), 128.0f);
    const float shifted = tc + 12582912.0f, k = shifted - 12582912.0f;
    const float f = tc - k;
    const float q = fma(fma(fma(9.61811095e-3f, f, 5.58372885e-2f), f, 2.40232527e-1f), f, 6.93136871e-1f);
    const float r = as_float(as_uint(fma(f, q, 1.0f)) + (as_uint(shifted) << 23));
    return t < -126.0f ? 0.0f : r;
}

// x^y = 2^(y log2 x) for finite x >= 0 and finite y: fast mode's contract is -ffinite-math-only's. A negative,
// infinite or NaN x or y gives an unspecified value (a shading kernel writes any non-finite channel as 0, and
// no model passes such an x: they clamp first), which saves the five lane-wise tests of sl_pow_special.
// A denormal x (below 2^-126) is taken as 0, as OpenCL's -cl-denorms-are-zero takes it: x^y is then pow(0, y)
// (0 for y > 0, 1 for y = 0, +inf for y < 0), where a model's base that small is a cosine at the edge of its
// range. That saves splitting denormals (precise pow scales them by 2^24 first) and a test for y = 0: for a
// normal x, y = 0 gives 2^0 = 1 exactly. 2026-12-06: the pow models in fast mode 0.98-1.45x (median 1.16x of 84 rows)
// as fast as with the former split, alternated in one process (docs/precision.md, "Fast-mode pow").
// Exact as pow: x = 0 (0 for y > 0, +inf for y < 0), y = 0 (1) and x = 1 (log2 1 = 0 exactly).
SL_INLINE float sl_fast_pow(float x, float y) {
    const float r = sl_exp2_f(y * sl_log2_f(x));
    const float at_zero = y > 0.0f ? 0.0f : (y == 0.0f ? 1.0f : INFINITY);
    return x < 1.17549435e-38f ? at_zero : r;
}

// x1^y1 x2^y2 for finite x1, x2 >= 0 and finite y1, y2 >= 0 in fast mode: 2^(y1 log2 x1 + y2 log2 x2) in plain
// float, one exponential (sl_pow2_nonneg's form without the low parts). A denormal base is taken as 0, as
// sl_fast_pow takes it: the product is 0 when its exponent is > 0, and it adds nothing when that is 0.
SL_INLINE float sl_fast_pow2(float x1, float y1, float x2, float y2) {
    const int small1 = x1 < 1.17549435e-38f, small2 = x2 < 1.17549435e-38f;
    const int zero = (small1 && y1 > 0.0f) || (small2 && y2 > 0.0f);
    const float l1 = sl_log2_f(small1 ? 1.0f : x1);
    const float l2 = sl_log2_f(sl_after(small2 ? 1.0f : x2, l1));
    return zero ? 0.0f : sl_exp2_f(fma(y1, l1, y2 * l2));
}

// ---- sl_pow_cr: double, correctly rounded over the sweep in docs/precision.md
// log2 x in double, y log2 x rounded in double (|t| <= 200 is kept to ~1e-14 absolute), 2^t by Taylor series:
// every step is accurate to ~1e-11 relative, so the float result is the correctly rounded x^y except within
// ~1e-11 of a rounding boundary.
#if defined(cl_khr_fp64)
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#define SL_HAVE_POW_CR 1

// log2 x for finite x > 0 (float denormals are normal doubles). x = 2^e m with m in [sqrt(1/2), sqrt(2)),
//   log2 m = (2 / ln 2) atanh(s) = (2 / ln 2) (s + s^3/3 + ... + s^13/13),  s = (m - 1) / (m + 1),
// |s| <= 0.1716; the first omitted term, s^15/15, is < 2e-12 of the sum (Abramowitz & Stegun 4.1.27). The
// polynomial in s^2 is evaluated by Estrin's scheme (shorter dependency chains than Horner: measured 1.8x
// faster; both were correctly rounded, max 0.5 ulp, over the sweep in docs/precision.md).
SL_INLINE double sl_log2_d(double x) {
    const long bits = as_long(x);
    const double m0 = as_double((bits & 0x000fffffffffffffL) | 0x3ff0000000000000L);   // [1, 2)
    const int big = m0 > 1.41421356237309505;
    const double m = big ? 0.5 * m0 : m0;
    const double e = (double)((int)(bits >> 52) - 1023 + big);
    const double s = (m - 1.0) / (m + 1.0), s2 = s * s, s4 = s2 * s2;
    // Estrin: (1 + s2/3) + s4 ((1/5 + s2/7) + s4 (1/9 + s2/11 + s4/13))
    const double p = fma(s2, 1.0 / 3.0, 1.0) +
                     s4 * (fma(s2, 1.0 / 7.0, 1.0 / 5.0) + s4 * fma(s4, 1.0 / 13.0, fma(s2, 1.0 / 11.0, 1.0 / 9.0)));
    return e + (2.0 * 1.44269504088896340736) * s * p;
}

// 2^t for t clamped to [-200, 200] (beyond the float range either way): t = k + f, k = rint(t), |f| <= 1/2,
//   2^f = e^g, g = f ln 2, |g| <= 0.347, by its Taylor series to g^9/9! (remainder < 7e-12 relative, Estrin),
// then scaled by 2^k built in the exponent field. rint by the 1.5 * 2^52 shift (a micro-kernel of this
// function ran 10x faster than with PoCL's rint on double).
SL_INLINE double sl_exp2_d(double t) {
    t = fmin(fmax(t, -200.0), 200.0);
    const double shifted = t + 6755399441055744.0;   // 1.5 * 2^52: k in the low mantissa bits
    const double k = shifted - 6755399441055744.0;
    const double g = (t - k) * 0.69314718055994530942, g2 = g * g, g4 = g2 * g2;
    // Estrin over the Taylor coefficients 1/i!, i = 0..9
    const double p01 = 1.0 + g, p23 = fma(g, 1.0 / 6.0, 0.5), p45 = fma(g, 1.0 / 120.0, 1.0 / 24.0);
    const double p67 = fma(g, 1.0 / 5040.0, 1.0 / 720.0), p89 = fma(g, 1.0 / 362880.0, 1.0 / 40320.0);
    const double p = fma(g2, p23, p01) + g4 * (fma(g2, p67, p45) + g4 * p89);
    return p * as_double((as_long(shifted) + 1023L) << 52);
}

SL_INLINE float sl_pow_cr(float x, float y) {
    const double t = (double)y * sl_log2_d((double)x);
    // flush to zero (see above), selected in double: converting a double below 2^-126 would itself take the assist
    return sl_pow_special(x, y, (float)(t < -126.0 ? 0.0 : sl_exp2_d(t)));
}
#endif

// Both modes: the trigonometric built-ins are the own functions above (vectorisable; PoCL's are calls). Fast mode
// has no cheaper trigonometry of its own: it is the same code as precise mode here (PoCL's native_sin/cos/tan
// are calls as well, and lose their argument reduction past 5e4 rad). SL_BUILTIN_TRIG keeps PoCL's.
#ifndef SL_BUILTIN_TRIG
#undef sin
#undef cos
#undef tan
#undef asin
#undef acos
#undef atan
#undef atan2
#define sin(x) sl_sin(x)
#define cos(x) sl_cos(x)
#define tan(x) sl_tan(x)
#define asin(x) sl_asin(x)
#define acos(x) sl_acos(x)
#define atan(x) sl_atan(x)
#define atan2(y, x) sl_atan2((y), (x))
#endif

// Precision modes. The default ("precise") uses the OpenCL built-ins as written in the models (PoCL's
// implementations, ~1-4 ulp), except the trigonometry (above) and pow and powr (sl_pow, above; PoCL's pow is
// a call, 100x slower). SL_FAST ("fast") maps exp, log, sqrt and rsqrt to the native_ forms (the same code as
// the full ones on PoCL's CPU driver) and pow to sl_fast_pow (plain float),
// accepting larger error; the error of every model in fast mode is measured against the double reference and
// documented in docs/precision.md (and bounded by tests/test_precision.cpp).
// The mapping is done with function-like macros so that the model files stay written in plain OpenCL C.
#ifdef SL_FAST
#undef exp
#undef exp2
#undef log
#undef log2
#undef sqrt
#undef rsqrt
#define exp(x) native_exp(x)
#define exp2(x) native_exp2(x)
#define log(x) native_log(x)
#define log2(x) native_log2(x)
#define sqrt(x) native_sqrt(x)
#define rsqrt(x) native_rsqrt(x)
#define divide(x, y) native_divide((x), (y))
#endif

// pow in each mode (see "pow: three forms" above), and pow_nonneg: pow where the model guarantees a finite base
// >= 0 and a finite exponent (the same value; precise mode skips the special cases that cannot occur);
// pow2_nonneg(x1, y1, x2, y2): x1^y1 x2^y2 with finite bases >= 0 and finite exponents >= 0, one exponential in
// precise and fast mode (sl_pow2_nonneg, sl_fast_pow2), the product of two pows in the others.
#if defined(SL_BUILTIN_POW)
// PoCL's own pow and powr
#define pow_nonneg(x, y) pow((x), (y))
#define pow2_nonneg(x1, y1, x2, y2) (pow((x1), (y1)) * pow((x2), (y2)))
#elif defined(SL_FAST)
#undef pow
#undef powr
#define pow(x, y) sl_fast_pow((x), (y))
#define powr(x, y) sl_fast_pow((x), (y))
#define pow_nonneg(x, y) sl_fast_pow((x), (y))
#define pow2_nonneg(x1, y1, x2, y2) sl_fast_pow2((x1), (y1), (x2), (y2))
#elif defined(SL_POW_CR) && defined(SL_HAVE_POW_CR)
#undef pow
#undef powr
#define pow(x, y) sl_pow_cr((x), (y))
#define powr(x, y) sl_pow_cr((x), (y))
#define pow_nonneg(x, y) sl_pow_cr((x), (y))
#define pow2_nonneg(x1, y1, x2, y2) (sl_pow_cr((x1), (y1)) * sl_pow_cr((x2), (y2)))
#else
#undef pow
#undef powr
#define pow(x, y) sl_pow((x), (y))
#define powr(x, y) sl_pow((x), (y))
#define pow_nonneg(x, y) sl_pow_nonneg((x), (y))
#define pow2_nonneg(x1, y1, x2, y2) sl_pow2_nonneg((x1), (y1), (x2), (y2))
#endif

#endif
