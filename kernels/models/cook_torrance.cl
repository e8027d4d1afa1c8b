// Cook-Torrance (Cook & Torrance 1982, "A Reflectance Model for Computer Graphics", ACM ToG 1(1); seed 004):
//   f_r   = kd albedo / pi  +  ks specular * F D G / (pi NoL NoV)
//   value = pi f_r NoL = kd albedo NoL + ks specular * F D G / NoV
// with D the Beckmann distribution (or GGX), F Schlick's Fresnel (or the exact dielectric Fresnel), and G the
// V-groove masking-shadowing G = min(1, 2 NoH NoV / VoH, 2 NoH NoL / VoH) (Blinn 1977 / Cook-Torrance 1982).
// The slides' denominator pi NoL NoV is the 1982 paper's; today's microfacet BRDFs use 4 NoL NoV (documented).
// Parameters (c[]): c0 = m (roughness, RMS slope), c1 = f0, c2 = kd, c3 = ks, c4 = 1/m^2, c5 = 1/(pi m^2).
#ifndef SHADELAB_MODEL_COOK_TORRANCE_CL
#define SHADELAB_MODEL_COOK_TORRANCE_CL
#include "common.cl"

// Beckmann (1963): D = exp((NoH^2 - 1) / (m^2 NoH^2)) / (pi m^2 NoH^4); normalised: integral of D NoH = 1.
SL_INLINE float D_Beckmann(float NoH, float inv_m2, float inv_pi_m2) {
    const float c2 = NoH * NoH;
    // Half vector at the horizon (NoH rounds to ~0 at grazing L and V): D is exp(-huge) = 0 there for every
    // m <= 1, but the formula would compute 0/0. Below NoH^2 = 1e-4 the exact value is already 0 in float.
    if (c2 < 1e-4f) return 0.0f;
    return exp((c2 - 1.0f) * inv_m2 / c2) * inv_pi_m2 / (c2 * c2);
}

// GGX / Trowbridge-Reitz (Walter et al. 2007) with alpha = m: D = m^2 / (pi (NoH^2 (m^2 - 1) + 1)^2).
SL_INLINE float D_GGX(float NoH, float m) {
    const float a2 = m * m;
    const float d = NoH * NoH * (a2 - 1.0f) + 1.0f;
    return a2 * SL_INV_PI / (d * d);
}

// Schlick (1994): F = f0 + (1 - f0) (1 - VoH)^5.
SL_INLINE float F_Schlick(float VoH, float f0) {
    const float x = 1.0f - VoH;
    const float x2 = x * x;
    return f0 + (1.0f - f0) * x2 * x2 * x;
}

// Seed 004's wording read literally: theta is "the angle between half and view vectors", (1 - theta)^5 with
// theta in radians. (1 - theta) turns negative past 1 rad (57 deg), so F falls below f0 and can go negative:
// kept as a named variant to show the slip, not for use.
// The angle is computed as 2 asin(|V - H| / 2), which equals acos(VoH) for unit vectors but is well conditioned
// near VoH = 1, where float acos turns a 1e-7 rounding of VoH into a 5e-4 error in the angle.
SL_INLINE float F_SchlickSeedAngle(float half_chord, float f0) {
    const float x = 1.0f - 2.0f * asin(fmin(half_chord, 1.0f));
    const float x2 = x * x;
    return f0 + (1.0f - f0) * x2 * x2 * x;
}

// Exact Fresnel reflectance of unpolarised light at a dielectric (Cook & Torrance 1982, eq. for F), with the
// index eta from f0 = ((eta - 1) / (eta + 1))^2: eta = (1 + sqrt f0) / (1 - sqrt f0), computed on the host (c6).
SL_INLINE float F_Dielectric(float VoH, float eta) {
    const float c = VoH;
    const float g2 = eta * eta - 1.0f + c * c;
    if (g2 <= 0.0f) return 1.0f;   // total internal reflection (eta < 1 only; not reachable for f0 in range)
    const float g = sqrt(g2);
    const float a = (g - c) / (g + c);
    const float b = (c * (g + c) - 1.0f) / (c * (g - c) + 1.0f);
    return 0.5f * a * a * (1.0f + b * b);
}

// V-groove masking-shadowing divided by NoV, written so no division by a vanishing NoV is ever formed:
//   G / NoV = min(1 / NoV, 2 NoH / VoH, 2 NoH NoL / (VoH NoV)), and the middle term bounds it, so near grazing
//   view the result stays finite: min(1, Gb, Gc) / NoV <= 2 NoH / VoH.
SL_INLINE float G_VGroove_over_NoV(float NoL, float NoV, float NoH, float VoH) {
    const float k = 2.0f * NoH / VoH;
    return fmin(fmin(1.0f, k * NoL) / NoV, k);
}

// The shared geometry; returns false where the specular term is 0 (light or view below the surface, or
// L = -V where H is undefined).
SL_INLINE bool CT_Geometry(float3 N, float3 L, float3 V, float* NoL, float* NoV, float* NoH, float* VoH) {
    *NoL = dot(N, L);
    *NoV = dot(N, V);
    const float3 s = L + V;
    const float len2 = dot(s, s);
    if (!(*NoL > 0.0f) || !(*NoV > 0.0f) || !(len2 > 1e-12f)) return false;
    const float3 H = s * rsqrt(len2);
    *NoH = fmax(dot(N, H), 0.0f);
    *VoH = fmax(dot(V, H), 1e-8f);   // VoH > 0 whenever NoL, NoV > 0; the floor only guards rounding
    return true;
}

SL_INLINE float3 CT_Value(float NoL, float spec, __constant const ModelConsts* mc) {
    return mc->c[2] * sl_albedo(mc) * fmax(NoL, 0.0f) + mc->c[3] * sl_specular(mc) * spec;
}

SL_INLINE float3 cook_torrance_eval(float3 N, float3 L, float3 V, float3 P, __constant const ModelConsts* mc) {
    (void)P;
    float NoL, NoV, NoH, VoH;
    float spec = 0.0f;
    if (CT_Geometry(N, L, V, &NoL, &NoV, &NoH, &VoH))
        spec = F_Schlick(VoH, mc->c[1]) * D_Beckmann(NoH, mc->c[4], mc->c[5]) * G_VGroove_over_NoV(NoL, NoV, NoH, VoH);
    return CT_Value(NoL, spec, mc);
}

SL_INLINE float3 cook_torrance_ggx_eval(float3 N, float3 L, float3 V, float3 P, __constant const ModelConsts* mc) {
    (void)P;
    float NoL, NoV, NoH, VoH;
    float spec = 0.0f;
    if (CT_Geometry(N, L, V, &NoL, &NoV, &NoH, &VoH))
        spec = F_Schlick(VoH, mc->c[1]) * D_GGX(NoH, mc->c[0]) * G_VGroove_over_NoV(NoL, NoV, NoH, VoH);
    return CT_Value(NoL, spec, mc);
}

SL_INLINE float3 cook_torrance_exact_fresnel_eval(float3 N, float3 L, float3 V, float3 P, __constant const ModelConsts* mc) {
    (void)P;
    float NoL, NoV, NoH, VoH;
    float spec = 0.0f;
    if (CT_Geometry(N, L, V, &NoL, &NoV, &NoH, &VoH))
        spec = F_Dielectric(VoH, mc->c[6]) * D_Beckmann(NoH, mc->c[4], mc->c[5]) * G_VGroove_over_NoV(NoL, NoV, NoH, VoH);
    return CT_Value(NoL, spec, mc);
}

SL_INLINE float3 cook_torrance_seed004_eval(float3 N, float3 L, float3 V, float3 P, __constant const ModelConsts* mc) {
    (void)P;
    float NoL, NoV, NoH, VoH;
    float spec = 0.0f;
    if (CT_Geometry(N, L, V, &NoL, &NoV, &NoH, &VoH)) {
        const float3 H = normalize(L + V);
        spec = F_SchlickSeedAngle(0.5f * length(V - H), mc->c[1]) * D_Beckmann(NoH, mc->c[4], mc->c[5]) *
               G_VGroove_over_NoV(NoL, NoV, NoH, VoH);
    }
    return CT_Value(NoL, spec, mc);
}
#endif
