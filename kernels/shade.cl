// The shading kernels. The host builds this file with the model chosen by defines:
//   SL_MODEL_HEADER  e.g. <models/lambert.cl>   the file that defines the model's eval function
//   SL_EVAL          e.g. lambert_eval          sl_rgb f(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, consts*)
//   SL_NUM_LIGHTS    number of lights (the loop is unrolled for it)
//   SL_ALL_DIRECTIONAL  1 when every light is directional (optional)
//   SL_TABLE         1 when the model reads a per-material table (the empirical family, kernels/consts/empirical.h):
//                    its eval takes the kernels' `tab` argument as a sixth argument (optional)
//   SL_TABLE_KNOTS   with SL_TABLE: the most knots the material's table may have in this program (4, 8, 16, 32)
// so each program holds only the model and options a scene uses.
#include "common.cl"
#include SL_MODEL_HEADER

#ifndef SL_NUM_LIGHTS
#define SL_NUM_LIGHTS 1
#endif
// SL_ALL_DIRECTIONAL=1 (set by Shader::shade when no light is a point light) removes the point-light arithmetic:
// the vectorised work-item loop cannot branch on the light type, it computes both and selects (with the point
// path's sqrt and three divisions Lambert ran 330-440 Mfrag/s, without 550-710: 4M fragments, one directional
// light, two alternating runs).
#ifndef SL_ALL_DIRECTIONAL
#define SL_ALL_DIRECTIONAL 0
#endif

// Every kernel below takes the material's table buffer `tab` as its last argument (a 1-float buffer, never read,
// for the models without a table); only a table model's eval is handed it.
#if defined(SL_TABLE) && SL_TABLE
#define SL_EVAL_AT(N, L, V, P, mc) SL_EVAL(N, L, V, P, mc, tab)
#else
#define SL_EVAL_AT(N, L, V, P, mc) SL_EVAL(N, L, V, P, mc)
#endif

// A non-finite channel (only from invalid input: a NaN normal, a zero light vector) is written as 0, so no
// image or table ever holds NaN/Inf. Without a comparison: exponent field 255 (Inf, NaN) gives the mask 0, any
// other exponent all ones. Three comparisons in a row (one per channel) are what LLVM's SLP vectoriser starts
// from to pack the channels into a <2 x float>, and one packed instruction stops PoCL's loop vectoriser.
SL_INLINE float sl_finite_or_zero(float v) {
    const uint u = as_uint(v);
    const uint nonfinite = (((u >> 23) & 0xffu) + 1u) >> 8;   // 1 iff the exponent field is all ones
    return as_float(u & (nonfinite - 1u));
}

// Every model's eval is written float3-free (common.cl's sl_v3 / sl_rgb), so the whole kernel is scalar code
// and PoCL's loop vectoriser runs 8 fragments per instruction ("vectorized loop (vectorization width: 8)" with
// POCL_VECTORIZER_REMARKS=1; docs/precision.md, "Vectorised kernels", lists what it took and what is not).

// Irradiance-like factor and direction of light `li` at P, in scalars: returns the factor that scales the
// light's radiance and sets *L to the unit direction to it. Directional lights are unattenuated (factor 1);
// point lights fall off with the inverse square of distance, optionally windowed to zero at `range` with
// (1 - (d/range)^4)^2 (Karis 2013, "Real Shading in Unreal Engine 4") so they can be culled.
SL_INLINE float light_incident_v3(__constant const DeviceLight* li, sl_v3 P, sl_v3* L) {
    const sl_v3 pos = sl_v3_make(li->pos_or_dir[0], li->pos_or_dir[1], li->pos_or_dir[2]);
    const float range = li->range;   // read before the branch: a load under it would not be hoisted (a gather)
    if (SL_ALL_DIRECTIONAL || li->type == 0.0f) {
        *L = pos;
        return 1.0f;
    }
    const sl_v3 d = sl_sub(pos, P);
    const float d2 = fmax(sl_dot(d, d), 1e-12f);   // a light exactly at the surface point: no direction
    *L = sl_scale(d, rsqrt(d2));
    float window = 1.0f;
    if (range > 0.0f) {
        const float q = d2 / (range * range);
        window = sl_saturate(1.0f - q * q);
        window *= window;
    }
    return window / d2;
}

// The unit vector to the viewer at P: perspective: view.pos_or_dir is the camera position; orthographic: it is
// the unit direction to the viewer, the same for every fragment (used for the moon disc).
SL_INLINE sl_v3 view_dir_v3(DeviceView view, sl_v3 P) {
    const sl_v3 eye = sl_v3_make(view.pos_or_dir[0], view.pos_or_dir[1], view.pos_or_dir[2]);
    return view.perspective != 0.0f ? sl_normalize(sl_sub(eye, P)) : eye;
}

// One fragment: sum over lights of incident * model, plus ambient * albedo.
__kernel void shade_fragments(__global const float* restrict px, __global const float* restrict py,
                              __global const float* restrict pz, __global const float* restrict nx,
                              __global const float* restrict ny, __global const float* restrict nz,
                              __global float* restrict out, const uint stride, const DeviceView view,
                              __constant const ModelConsts* mc, __constant const DeviceLight* lights,
                              const float4 ambient, __global const float* restrict tab) {
    (void)tab;
    // No bounds check: Shader::shade pads every buffer to the launch size (n rounded up to the work-group
    // size), and `stride` is that padded length. A check here would put the loads of the constants (albedo,
    // lights, the model's c[]) under a condition, where PoCL's work-item loop cannot hoist them: vectorised,
    // each became a gather per fragment. size_t, not uint: a 32-bit index that may wrap makes px[i] a gather.
    const size_t i = get_global_id(0);
    const sl_v3 P = sl_v3_make(px[i], py[i], pz[i]);
    const sl_v3 N = sl_v3_make(nx[i], ny[i], nz[i]);
    const sl_v3 V = view_dir_v3(view, P);
    float r = ambient.x * mc->albedo[0], g = ambient.y * mc->albedo[1], b = ambient.z * mc->albedo[2];
#pragma unroll
    for (int l = 0; l < SL_NUM_LIGHTS; ++l) {
        sl_v3 L;
        const float e = light_incident_v3(&lights[l], P, &L);
        // Each light's evaluation after the previous light's (common.cl's sl_after): the unrolled loop makes the
        // model's code once per light, and LLVM's SLP vectoriser packs two such copies into <2 x float>, which
        // stops the loop vectoriser (minnaert_1941 and oren_nayar_full with two lights did).
        L.x = sl_after(L.x, r);
        const sl_rgb v = SL_EVAL_AT(N, L, V, P, mc);
        __constant const float* rad = lights[l].radiance;
        r += (rad[0] * e) * v.r;
        g += (rad[1] * e) * v.g;
        b += (rad[2] * e) * v.b;
    }
    out[i] = sl_finite_or_zero(r);
    out[stride + i] = sl_finite_or_zero(g);
    out[2 * stride + i] = sl_finite_or_zero(b);
}

// The model alone at triple i of xyz-interleaved N, L, V, P (unmasked: tests/test_precision.cpp counts its NaN/Inf).
SL_INLINE sl_rgb eval_direction_at(uint i, __global const float* N_, __global const float* L_,
                                   __global const float* V_, __global const float* P_,
                                   __constant const ModelConsts* mc, __global const float* restrict tab) {
    (void)tab;
    const sl_v3 N = sl_v3_make(N_[3 * i], N_[3 * i + 1], N_[3 * i + 2]);
    const sl_v3 L = sl_v3_make(L_[3 * i], L_[3 * i + 1], L_[3 * i + 2]);
    const sl_v3 V = sl_v3_make(V_[3 * i], V_[3 * i + 1], V_[3 * i + 2]);
    const sl_v3 P = sl_v3_make(P_[3 * i], P_[3 * i + 1], P_[3 * i + 2]);
    return SL_EVAL_AT(N, L, V, P, mc);
}

// The model alone for given unit directions (no lights, no attenuation): what the tests sweep.
__kernel void eval_directions(__global const float* restrict N_, __global const float* restrict L_,
                              __global const float* restrict V_, __global const float* restrict P_,
                              __global float* restrict out, const uint n, __constant const ModelConsts* mc,
                              __global const float* restrict tab) {
    const size_t i = get_global_id(0);   // size_t, not uint: a 32-bit index that may wrap makes px[i] a gather
    if (i >= n) return;
    const sl_rgb r = eval_direction_at(i, N_, L_, V_, P_, mc, tab);
    out[3 * i] = sl_finite_or_zero(r.r);
    out[3 * i + 1] = sl_finite_or_zero(r.g);
    out[3 * i + 2] = sl_finite_or_zero(r.b);
}

// ---- Batched evaluation for fitting (host/fit/) ----------------------------------------------------------------
// Many parameter sets x many samples in one launch: work item (i, s) evaluates the model alone (no lights, no
// ambient, as eval_directions) at sample i with constant set s. The parameters live in the __constant block,
// not in the program, so every set shares this one build. Dimension 0 runs over the samples, so the set (and
// with it every constant load) is the same for a whole work-group and hoisted out of the vectorised loop.
//   dirs:  12 planes of `stride` floats: N.x N.y N.z L.x L.y L.z V.x V.y V.z P.x P.y P.z
//   out:   3 planes (r, g, b) of `stride` floats per set: out[(3 s + c) stride + i]
//   sets:  consts_per_set ModelConsts per set (the model's own, then its children's: gradient reads mc[1], mc[2])
// No bounds check: the host pads the samples to the launch size (zero directions, whose values are never read).
__kernel void eval_batch(__global const float* restrict dirs, __global float* restrict out, const uint stride,
                         const uint consts_per_set, __constant const ModelConsts* sets,
                         __global const float* restrict tab) {
    (void)tab;
    const size_t i = get_global_id(0);   // size_t, not uint: a 32-bit index that may wrap makes dirs[i] a gather
    const size_t s = get_global_id(1);
    const size_t st = stride;
    __constant const ModelConsts* mc = sets + s * consts_per_set;
    const sl_v3 N = sl_v3_make(dirs[i], dirs[st + i], dirs[2 * st + i]);
    const sl_v3 L = sl_v3_make(dirs[3 * st + i], dirs[4 * st + i], dirs[5 * st + i]);
    const sl_v3 V = sl_v3_make(dirs[6 * st + i], dirs[7 * st + i], dirs[8 * st + i]);
    const sl_v3 P = sl_v3_make(dirs[9 * st + i], dirs[10 * st + i], dirs[11 * st + i]);
    const sl_rgb r = SL_EVAL_AT(N, L, V, P, mc);
    __global float* o = out + 3 * s * st;
    o[i] = sl_finite_or_zero(r.r);
    o[st + i] = sl_finite_or_zero(r.g);
    o[2 * st + i] = sl_finite_or_zero(r.b);
}
