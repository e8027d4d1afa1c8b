// Phong and Blinn-Phong: a Lambert diffuse term plus a cosine-power highlight, in three forms each:
//   <model>            the reference: the seed's expression with the highlight gated to NoL > 0
//   <model>_seed001    seed 001's code as written: highlight NOT gated (light from behind the surface
//                      still produces one), exponent from _SpecularGloss (Phong: gloss / 4)
//   <model>_normalized an energy-normalised BRDF, value = pi * f_r * NoL, with the diffuse weighted by
//                      (1 - ks) so that albedo, specular <= 1 conserve energy for every ks in [0, 1]
// Value convention of common.cl. docs/models/phong.md: formulas, sources, ranges, measured errors.
//
// Notation: NoL, NoV, LoV, NoH dot products; R = reflect(-L, N) = 2 NoL N - L; RoV = sl_dot(R, V);
// H = normalize(L + V); n = exponent; ks = specular weight; albedo, specular colour from the constants
// (common.cl's sl_diffuse_specular: value = albedo * d + specular * s, per channel).
//
// Exponent conventions: pow(0, 0) = 1 in C/OpenCL, which would light every direction at n = 0 even
// where RoV (NoH) <= 0. Here the power is x^n for x > 0 and 0 for x <= 0 at every n, so n = 0 is the
// limit n -> 0+ (1 over the hemisphere around R or N, 0 outside), continuous in n.
#ifndef SHADELAB_MODEL_PHONG_CL
#define SHADELAB_MODEL_PHONG_CL
#include "common.cl"
#include "lambert.cl"   // Fd_Lambert_cos: max(0, NoL)
#include "consts/phong.h"

// ---- terms ----------------------------------------------------------------------------------------

// RoV with R = reflect(-L, N) = 2 NoL N - L, written from the dot products:
//   RoV = 2 NoL NoV - LoV,
// exactly equal to sl_dot(reflect(-L, N), V), cheaper, and symmetric in L and V by construction
// (R(L).V == R(V).L, Phong's lobe is reciprocal).
SL_INLINE float Phong_RoV(float NoL, float NoV, float LoV) { return 2.0f * NoL * NoV - LoV; }

// NoH with H = normalize(L + V). L = -V leaves H undefined (L + V = 0; the limit depends on the
// direction of approach, NoH anywhere in [-sqrt(1 - NoL^2), sqrt(1 - NoL^2)]): there NoH is taken as 0,
// so the highlight is 0 (the sum L + V of nearly opposite float vectors is exact, so any pair that
// is not opposite within float resolution has |L + V| far above the 1e-10 cut and a well-defined H).
SL_INLINE float BlinnPhong_NoH(sl_v3 N, sl_v3 L, sl_v3 V) {
    const sl_v3 h = sl_add(L, V);
    const float hh = sl_dot(h, h);
    return hh > 1e-20f ? sl_dot(N, h) * rsqrt(hh) : 0.0f;
}

// The cosine power x^n of both lobes (x = RoV or NoH), 0 for x <= 0 at every n including n = 0
// (see the exponent conventions above). Guard: float rounding of unit float vectors gives x up to
// 1 + ~3e-7 where mathematically x <= 1; x^10000 would then exceed the lobe's peak by ~0.3%, so x is
// clamped to 1.
SL_INLINE float Spec_Power(float x, float n) { return x > 0.0f ? pow_nonneg(fmin(x, 1.0f), n) : 0.0f; }

// The highlight only where the light is in front of the surface (the reference forms): 1 for NoL > 0.
SL_INLINE float Spec_Gate(float NoL) { return NoL > 0.0f ? 1.0f : 0.0f; }

// ---- Phong (Phong 1975, "Illumination for computer generated pictures", CACM 18(6)) ----------------

// phong: value = albedo * max(0, NoL) + ks * specular * [NoL > 0] * max(0, RoV)^n
// PhongConsts: n in [0, 10000], ks in [0, 10]. Leaves out: energy conservation (the lobe is not
// normalised and carries no NoL), reciprocity, Fresnel. Not reciprocal: value / NoL has RoV^n / NoL.
SL_INLINE sl_rgb phong_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const float RoV = Phong_RoV(NoL, sl_dot(N, V), sl_dot(L, V));
    const PhongConsts* k = SL_CONSTS(PhongConsts, mc);
    const float spec = k->ks * Spec_Gate(NoL) * Spec_Power(RoV, k->n);
    return sl_diffuse_specular(mc, Fd_Lambert_cos(NoL), spec);
}

// phong_seed001: value = albedo * max(0, NoL) + specular_power * specular * max(0, RoV)^(gloss / 4)
// Seed 001 exactly: the highlight is not gated, so a light below the horizon lights up points where
// RoV > 0. PhongConsts: n = gloss / 4 (host), ks = specular_power.
SL_INLINE sl_rgb phong_seed001_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const float RoV = Phong_RoV(NoL, sl_dot(N, V), sl_dot(L, V));
    const PhongConsts* k = SL_CONSTS(PhongConsts, mc);
    return sl_diffuse_specular(mc, Fd_Lambert_cos(NoL), k->ks * Spec_Power(RoV, k->n));
}

// phong_normalized: the modified Phong BRDF (Lewis 1994, "Making shaders more physically plausible";
// Lafortune & Willems 1994) f_r = (1 - ks) albedo / pi + ks specular (n + 2) / (2 pi) RoV^n, so
//   value = (1 - ks) * albedo * max(0, NoL) + ks * specular * (n + 2) / 2 * max(0, RoV)^n * max(0, NoL).
// The lobe's directional albedo is exactly 1 at V = N and less elsewhere, so the model conserves
// energy for albedo, specular <= 1 and any ks in [0, 1] (Lafortune's kd + ks <= 1 built in).
// Reciprocal (value / NoL is symmetric). PhongNormalizedConsts: n, kd = 1 - ks, lobe_scale = ks (n + 2) / 2 (host).
SL_INLINE sl_rgb phong_normalized_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const float RoV = Phong_RoV(NoL, sl_dot(N, V), sl_dot(L, V));
    const float cosine = Fd_Lambert_cos(NoL);
    const PhongNormalizedConsts* k = SL_CONSTS(PhongNormalizedConsts, mc);
    return sl_diffuse_specular(mc, k->kd * cosine, k->lobe_scale * Spec_Power(RoV, k->n) * cosine);
}

// ---- Blinn-Phong (Blinn 1977, "Models of light reflection for computer synthesized pictures") ------

// blinn_phong: value = albedo * max(0, NoL) + ks * specular * [NoL > 0] * max(0, NoH)^n
// PhongConsts: n in [0, 10000], ks in [0, 10]. (Seed 001 names the N.H variable "NdotV".)
// NoH^(4n) has about the width of RoV^n near the peak, hence the seed's gloss vs gloss / 4.
SL_INLINE sl_rgb blinn_phong_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const PhongConsts* k = SL_CONSTS(PhongConsts, mc);
    const float spec = k->ks * Spec_Gate(NoL) * Spec_Power(BlinnPhong_NoH(N, L, V), k->n);
    return sl_diffuse_specular(mc, Fd_Lambert_cos(NoL), spec);
}

// blinn_phong_seed001: value = albedo * max(0, NoL) + specular_power * specular * max(0, NoH)^gloss
// Seed 001 exactly (ungated). PhongConsts: n = gloss, ks = specular_power.
SL_INLINE sl_rgb blinn_phong_seed001_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P,
                                          const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const PhongConsts* k = SL_CONSTS(PhongConsts, mc);
    const float spec = k->ks * Spec_Power(BlinnPhong_NoH(N, L, V), k->n);
    return sl_diffuse_specular(mc, Fd_Lambert_cos(NoL), spec);
}

// blinn_phong_normalized: f_r = (1 - ks) albedo / pi + ks specular K_n / pi NoH^n with the exact
// normalisation of Giesen 2009 ("Derivation of Phong and Blinn-Phong BRDF normalization factors"):
//   K_n = (n + 2)(n + 4) / (8 (2^(-n/2) + n)),
// which makes the lobe's directional albedo exactly 1 at V = N (less elsewhere):
//   value = (1 - ks) * albedo * max(0, NoL) + ks * specular * K_n * max(0, NoH)^n * max(0, NoL).
// PhongNormalizedConsts: n, kd = 1 - ks, lobe_scale = ks K_n (host). Reciprocal (H is symmetric in L, V).
SL_INLINE sl_rgb blinn_phong_normalized_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P,
                                             const ModelConsts* mc) {
    (void)P;
    const float cosine = Fd_Lambert_cos(sl_dot(N, L));
    const PhongNormalizedConsts* k = SL_CONSTS(PhongNormalizedConsts, mc);
    const float lobe = Spec_Power(BlinnPhong_NoH(N, L, V), k->n);
    return sl_diffuse_specular(mc, k->kd * cosine, k->lobe_scale * lobe * cosine);
}

// blinn_phong_normalized_approx: the same with the common approximation K_n = (n + 8) / 8 (the
// (n + 8) / (8 pi) factor of Akenine-Moller, Haines, Hoffman, Real-Time Rendering 3rd ed., 2008).
// It is NOT energy conserving: it exceeds the exact K_n for every n > 0 and the lobe's directional
// albedo at V = N reaches 1.074 at n = 11 (measured in tests/test_phong.cpp). lobe_scale = ks (n + 8) / 8.
SL_INLINE sl_rgb blinn_phong_normalized_approx_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P,
                                                    const ModelConsts* mc) {
    return blinn_phong_normalized_eval(N, L, V, P, mc);   // same form; only the host's lobe_scale differs
}

#endif
