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

// Irradiance-like factor and direction of light `li` at P: directional lights are unattenuated;
// point lights fall off with the inverse square of distance, optionally windowed to zero at `range`
// with (1 - (d/range)^4)^2 (Karis 2013, "Real Shading in Unreal Engine 4") so they can be culled.
SL_INLINE float3 light_incident(__constant const Light* li, float3 P, float3* L) {
    const float4 pd = li->pos_or_dir;
    if (li->params.x == 0.0f) {
        *L = pd.xyz;
        return li->radiance.xyz;
    }
    const float3 d = pd.xyz - P;
    const float d2 = fmax(dot(d, d), 1e-12f);   // a light exactly at the surface point: no direction
    *L = d * rsqrt(d2);
    float window = 1.0f;
    const float range = li->params.y;
    if (range > 0.0f) {
        const float q = d2 / (range * range);
        window = sl_saturate(1.0f - q * q);
        window *= window;
    }
    return li->radiance.xyz * (window / d2);
}

// One fragment: sum over lights of incident * model, plus ambient * albedo.
// view.w == 1: view.xyz is the camera position (perspective); view.w == 0: view.xyz is the unit
// direction to the viewer, the same for every fragment (orthographic, used for the moon disc).
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
    const float3 V = view.w != 0.0f ? normalize(view.xyz - P) : view.xyz;
    float3 sum = ambient.xyz * sl_albedo(mc);
#pragma unroll
    for (int l = 0; l < SL_NUM_LIGHTS; ++l) {
        float3 L;
        const float3 E = light_incident(&lights[l], P, &L);
        sum += E * SL_EVAL(N, L, V, P, mc);
    }
    sum = sl_finite_or_zero(sum);
    out[i] = sum.x;
    out[n + i] = sum.y;
    out[2 * n + i] = sum.z;
}

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
