// The shading kernels. The host builds this file with the model chosen by defines:
//   SL_MODEL_HEADER  e.g. <models/lambert.cl>   the file that defines the model's eval function
//   SL_EVAL          e.g. lambert_eval          float3 f(float3 N, float3 L, float3 V, float3 P, consts*)
//   SL_NUM_LIGHTS    number of lights (the loop is unrolled for it)
// so each program holds only the model and options a scene uses.
#include "common.cl"
#include SL_MODEL_HEADER

#ifndef SL_NUM_LIGHTS
#define SL_NUM_LIGHTS 1
#endif

// Light `li`'s position (or direction) and radiance, from scalar loads.
SL_INLINE float3 light_vec(__constant const Light* li) {
    return (float3)(li->pos_or_dir.x, li->pos_or_dir.y, li->pos_or_dir.z);
}
SL_INLINE float3 light_radiance(__constant const Light* li) {
    return (float3)(li->radiance.x, li->radiance.y, li->radiance.z);
}

// Irradiance-like factor and direction of light `li` at P: directional lights are unattenuated;
// point lights fall off with the inverse square of distance, optionally windowed to zero at `range`
// with (1 - (d/range)^4)^2 (Karis 2013, "Real Shading in Unreal Engine 4") so they can be culled.
SL_INLINE float3 light_incident(__constant const Light* li, float3 P, float3* L) {
    if (li->params.x == 0.0f) {
        *L = light_vec(li);
        return light_radiance(li);
    }
    const float3 d = light_vec(li) - P;
    const float d2 = fmax(dot(d, d), 1e-12f);   // a light exactly at the surface point: no direction
    *L = d * rsqrt(d2);
    float window = 1.0f;
    const float range = li->params.y;
    if (range > 0.0f) {
        const float q = d2 / (range * range);
        window = sl_saturate(1.0f - q * q);
        window *= window;
    }
    return light_radiance(li) * (window / d2);
}

// The unit vector to the viewer at P: view.w == 1: view.xyz is the camera position (perspective);
// view.w == 0: view.xyz is the unit direction to the viewer, the same for every fragment (orthographic,
// used for the moon disc).
SL_INLINE float3 view_dir(float4 view, float3 P) {
    const float3 eye = (float3)(view.x, view.y, view.z);
    return view.w != 0.0f ? normalize(eye - P) : eye;
}

// A non-finite channel (only from invalid input: a NaN normal, a zero light vector) is written as 0, so no
// image or table ever holds NaN/Inf. v - v is 0 for finite v and NaN for NaN and +-Inf (the kernels are not
// built with -cl-finite-math-only, so it is not folded away). Per channel, not as a float3 select.
SL_INLINE float sl_finite_or_zero1(float v) { return v - v == 0.0f ? v : 0.0f; }

// Models of N.L alone (value = albedo * factor(NoL); the model file defines SL_HAS_NOL_<eval> and
// SL_NOL_<eval>, and builds its eval from the same factor) are shaded in scalars, without the float3 packing
// and shuffling of the general path below (5-20% faster: three alternating A/B runs at 4M fragments). Neither
// path is vectorised across work-items: PoCL's loop vectoriser (LLVM 15) rejects any vector-typed instruction
// ("instruction return type cannot be vectorized"), which every float3 eval has, and here the SLP vectoriser
// packs the three channels' finite checks into one. A variant without the checks did vectorise (width 8) and
// was slower. Same operations per channel as the general path.
#define SL_CAT_(a, b) a##b
#define SL_CAT(a, b) SL_CAT_(a, b)
#if SL_CAT(SL_HAS_NOL_, SL_EVAL)
#define SL_NOL_EVAL SL_CAT(SL_NOL_, SL_EVAL)

// Scalar light_incident for the N.L path: returns NoL and the factor that scales the light's radiance
// (1 for a directional light; window / d^2 for a point light). Reads the Light through a float pointer: a
// float4 load would be a vector instruction.
SL_INLINE float light_nol(__constant const Light* li, float px, float py, float pz, float nx, float ny, float nz,
                          float* NoL) {
    __constant const float* f = (__constant const float*)li;   // pos_or_dir[0..3], radiance[4..7], params[8..11]
    if (f[8] == 0.0f) {
        *NoL = nx * f[0] + ny * f[1] + nz * f[2];
        return 1.0f;
    }
    const float dx = f[0] - px, dy = f[1] - py, dz = f[2] - pz;
    const float d2 = fmax(dx * dx + dy * dy + dz * dz, 1e-12f);
    const float inv = rsqrt(d2);
    *NoL = nx * (dx * inv) + ny * (dy * inv) + nz * (dz * inv);
    float window = 1.0f;
    const float range = f[9];
    if (range > 0.0f) {
        const float q = d2 / (range * range);
        window = sl_saturate(1.0f - q * q);
        window *= window;
    }
    return window / d2;
}

__kernel void shade_fragments(__global const float* restrict px, __global const float* restrict py,
                              __global const float* restrict pz, __global const float* restrict nx,
                              __global const float* restrict ny, __global const float* restrict nz,
                              __global float* restrict out, const uint n, const float4 view,
                              __constant const ModelConsts* mc, __constant const Light* lights,
                              const float4 ambient) {
    (void)view;
    const uint i = get_global_id(0);
    if (i >= n) return;
    const float x = px[i], y = py[i], z = pz[i], a = nx[i], b = ny[i], c = nz[i];
    const float ar = mc->albedo[0], ag = mc->albedo[1], ab = mc->albedo[2];
    float r = ambient.x * ar, g = ambient.y * ag, bl = ambient.z * ab;
#pragma unroll
    for (int l = 0; l < SL_NUM_LIGHTS; ++l) {
        float NoL;
        const float e = light_nol(&lights[l], x, y, z, a, b, c, &NoL);
        const float f = SL_NOL_EVAL(NoL, mc);
        __constant const float* rad = (__constant const float*)&lights[l] + 4;
        r += (rad[0] * e) * (ar * f);
        g += (rad[1] * e) * (ag * f);
        bl += (rad[2] * e) * (ab * f);
    }
    out[i] = sl_finite_or_zero1(r);
    out[n + i] = sl_finite_or_zero1(g);
    out[2 * n + i] = sl_finite_or_zero1(bl);
}

#else
// One fragment: sum over lights of incident * model, plus ambient * albedo.
__kernel void shade_fragments(__global const float* restrict px, __global const float* restrict py,
                              __global const float* restrict pz, __global const float* restrict nx,
                              __global const float* restrict ny, __global const float* restrict nz,
                              __global float* restrict out, const uint n, const float4 view,
                              __constant const ModelConsts* mc, __constant const Light* lights,
                              const float4 ambient) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    const float3 P = (float3)(px[i], py[i], pz[i]);
    const float3 N = (float3)(nx[i], ny[i], nz[i]);
    const float3 V = view_dir(view, P);
    float3 sum = (float3)(ambient.x, ambient.y, ambient.z) * sl_albedo(mc);
#pragma unroll
    for (int l = 0; l < SL_NUM_LIGHTS; ++l) {
        float3 L;
        const float3 E = light_incident(&lights[l], P, &L);
        sum += E * SL_EVAL(N, L, V, P, mc);
    }
    out[i] = sl_finite_or_zero1(sum.x);
    out[n + i] = sl_finite_or_zero1(sum.y);
    out[2 * n + i] = sl_finite_or_zero1(sum.z);
}
#endif

// The model alone for given unit directions (no lights, no attenuation): what the tests sweep.
__kernel void eval_directions(__global const float* restrict N_, __global const float* restrict L_,
                              __global const float* restrict V_, __global const float* restrict P_,
                              __global float* restrict out, const uint n, __constant const ModelConsts* mc) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    const float3 N = vload3(i, N_);
    const float3 L = vload3(i, L_);
    const float3 V = vload3(i, V_);
    const float3 P = vload3(i, P_);
    const float3 r = sl_finite_or_zero(SL_EVAL(N, L, V, P, mc));
    vstore3(r, i, out);
}
