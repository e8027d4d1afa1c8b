// The Cook-Torrance family: specular reflection from a microfacet surface (Cook & Torrance 1982, "A Reflectance
// Model for Computer Graphics", ACM ToG 1(1) 7-24; seed 004 slide "Cook Torrance Shader") plus a Lambert base.
// docs/models/cook_torrance.md has the formulas, the sources, the slides' slips and the measured errors.
//
//   f_r   = kd albedo / pi  +  ks specular F D G / (pi NoL NoV)        (the 1982 paper's specular BRDF)
//   value = pi f_r NoL      =  kd albedo NoL  +  ks specular F D G / NoV
//
//   cook_torrance                D_Beckmann, F_Schlick,    G_VGroove   the reference combination
//   cook_torrance_ggx            D_GGX,      F_Schlick,    G_VGroove
//   cook_torrance_exact_fresnel  D_Beckmann, F_Dielectric, G_VGroove
//   cook_torrance_seed004        D_Beckmann, F_SchlickSeedAngle (the slides' "(1 - theta)^5", theta the angle)
//
// Parameters: m (roughness: Beckmann RMS slope; GGX alpha), f0 (Fresnel reflectance at normal incidence),
// kd, ks (weights of the diffuse and specular parts). Constants packed once on the host
// (host/models/cook_torrance.cpp) as CookTorranceConsts (consts/cook_torrance.h): m, f0, kd, ks, 1/m^2,
// 1/(pi m^2), m^2, 1/eta and 1 - 1/eta^2, with eta = (1 + sqrt f0) / (1 - sqrt f0) the dielectric's index
// (1/eta = 0 at f0 = 1).
//
// Leaves out: the paper's ambient term and its wavelength-dependent F (one f0 for all channels; colour comes
// from the specular colour); multiple scattering between facets (V-groove G only removes light). The paper's
// pi in the denominator is kept; today's microfacet BRDF has 4 there (Walter et al. 2007): ks = pi/4 gives that
// normalisation exactly (docs).
//
// Angles: theta_h is the angle between N and H. tan^2(theta_h) = |N x H|^2 / NoH^2 is formed from the cross
// product, not from 1 - NoH^2: near the peak (H ~ N) the float rounding of NoH (~6e-8) would be an absolute
// error of 1.2e-7 in 1 - NoH^2, i.e. 1.2e-7 / m^2 = 3e-4 in Beckmann's exponent at m = 0.02; |N x H|^2 keeps
// its relative accuracy down to theta_h = 0, and the ratio is also exact for slightly non-unit float N and H.
#ifndef SHADELAB_MODEL_COOK_TORRANCE_CL
#define SHADELAB_MODEL_COOK_TORRANCE_CL
#include "common.cl"
#include "consts/cook_torrance.h"

// ---- the terms ------------------------------------------------------------------------------------------

// Beckmann (1963), as in Cook & Torrance 1982 eq. for D and the slides:
//   D = exp(-tan^2(theta_h) / m^2) / (pi m^2 cos^4(theta_h)),  normalised: integral of D NoH over the hemisphere = 1.
// NoH2 = NoH^2, NxH2 = |N x H|^2 (= sin^2 theta_h).
SL_INLINE float D_Beckmann(float NoH2, float NxH2, float inv_m2, float inv_pi_m2) {
    // Half vector at the horizon: the formula is exp(-inf) / 0 there. The limit is 0 (the exponential wins),
    // and below NoH^2 = 1e-4 the value is already exactly 0 in float for every m <= 1 (exp(-9999) underflows),
    // so the cut changes no result.
    if (NoH2 < 1e-4f) return 0.0f;
    // exp(-a) for a > 87 is below 2^-126 (1.6e-38): a denormal, and every instruction that makes or reads one
    // takes a microcode assist on x86 (common.cl, pow). It is 0 here, as pow flushes such values; the
    // exponent is capped so that no lane computes the denormal and throws it away.
    const float a = NxH2 * inv_m2 / NoH2;
    return a > 87.0f ? 0.0f : exp(-fmin(a, 87.0f)) * inv_pi_m2 / (NoH2 * NoH2);
}

// GGX / Trowbridge-Reitz (Walter et al. 2007, eq. 33) with alpha = m:
//   D = m^2 / (pi cos^4(theta_h) (m^2 + tan^2(theta_h))^2) = m^2 / (pi (m^2 NoH^2 + |N x H|^2)^2).
// The second form has no cancellation (two non-negative terms; the usual NoH^2 (m^2 - 1) + 1 loses ~6e-8/m^2
// relative near the peak) and its denominator is >= min(m^2, 1)^2 > 0: no guard needed.
SL_INLINE float D_GGX(float NoH2, float NxH2, float m2) {
    const float d = m2 * NoH2 + NxH2;
    return m2 * SL_INV_PI / (d * d);
}

// Schlick (1994): F = f0 + (1 - f0) (1 - VoH)^5. (The slides write (1 - theta)^5 with "theta = h . v": the
// cosine is meant; the angle reading is F_SchlickSeedAngle.)
SL_INLINE float F_Schlick(float VoH, float f0) {
    const float x = 1.0f - VoH;
    const float x2 = x * x;
    return f0 + (1.0f - f0) * x2 * x2 * x;
}

// Seed 004 read literally: theta is "the angle between half and view vectors", (1 - theta)^5 with theta in
// radians. F = 1 at normal incidence (not f0), and (1 - theta) turns negative past 1 rad (57 deg), so F falls
// below f0 and below 0 there: kept as a named variant to measure the slip, not for use.
// theta is half the angle between L and V: for unit vectors |L + V| = 2 cos theta and |L - V| = 2 sin theta, so
// theta = atan2(|L - V|, |L + V|). Unlike acos(VoH) it is well conditioned at theta = 0 (float acos turns a 6e-8
// rounding of VoH into 3.5e-4 rad there), and unlike the angle between V and H it does not depend on the inputs'
// lengths (1 +- 6e-8): H tilts by (|L| - |V|) / |L + V| when L ~ -V, 5e-7 rad at |L + V| = 0.08 (seen in the
// sweep), which matters where F crosses 0, at theta = 1 + (f0 / (1 - f0))^(1/5) (1.53 rad for f0 = 0.04).
SL_INLINE float F_SchlickSeedAngle(float theta, float f0) {
    const float x = 1.0f - theta;
    const float x2 = x * x;
    return f0 + (1.0f - f0) * x2 * x2 * x;
}

// Exact Fresnel reflectance of unpolarised light at a dielectric (Cook & Torrance 1982, the F equation, from
// Sparrow & Cess), c = VoH, eta the relative index:
//   g = sqrt(eta^2 + c^2 - 1),  F = 1/2 (g - c)^2 / (g + c)^2 (1 + (c (g + c) - 1)^2 / (c (g - c) + 1)^2)
// evaluated with every length divided by eta (gamma = g / eta), so f0 = 1 (eta = infinity, a perfect mirror)
// is in range: 1/eta = 0 gives gamma = 1 and F = 1 exactly. gamma^2 = (1 - 1/eta^2) + c^2 / eta^2 is a sum of
// two non-negative terms (1 - 1/eta^2 packed on the host): no cancellation, and eta >= 1 (f0 >= 0) means no
// total internal reflection. gamma >= c / eta, so both denominators are > 0 wherever c > 0 (CT_frame floors VoH):
// gamma + c / eta >= 2 c / eta, and gamma = 1 at 1/eta = 0; c (gamma - c / eta) + 1 / eta would be 0 only at
// 1/eta = 0, where it is c.
SL_INLINE float F_Dielectric(float c, float inv_eta, float one_minus_inv_eta2) {
    const float ce = c * inv_eta;
    const float gamma = sqrt(one_minus_inv_eta2 + ce * ce);
    const float a = (gamma - ce) / (gamma + ce);
    const float b = (c * (gamma + ce) - inv_eta) / (c * (gamma - ce) + inv_eta);
    return 0.5f * a * a * (1.0f + b * b);
}

// V-groove masking and shadowing (Torrance & Sparrow 1967, Blinn 1977, Cook & Torrance 1982):
//   G = min(1, Gb, Gc),  Gb = 2 NoH NoV / VoH (masking),  Gc = 2 NoH NoL / VoH (shadowing; the paper and the
//   slides write LoH in Gc, equal to VoH since H bisects L and V).
// Returned divided by NoV, the only place the model divides by a cosine (the NoL of pi f_r NoL cancels the one
// of f_s): with k = 2 NoH / VoH,
//   G / NoV = min(1 / NoV, k, k NoL / NoV) = min(min(1, k NoL) / NoV, k),
// bounded by k wherever masking is active, so a vanishing NoV cannot blow it up; min(1, k NoL) / NoV may
// overflow to +inf for NoV ~ 1e-38, and fmin returns k then. What stays unbounded is k = 2 NoH / VoH itself,
// as VoH -> 0: light and view both grazing from opposite sides, the mirror configuration at the horizon,
// where G = 1 and value ~ F D / NoV. That is the published model's own singularity (docs); CT_Frame cuts
// it at |L + V| <= 1e-6, i.e. NoV < 1e-6, where the value is ~1e6 / (pi m^2).
SL_INLINE float G_VGroove_over_NoV(float NoL, float NoV, float NoH, float VoH) {
    const float k = 2.0f * NoH / VoH;
    return fmin(fmin(1.0f, k * NoL) / NoV, k);
}

// ---- the shared frame -----------------------------------------------------------------------------------

typedef struct {
    float NoL, NoV, NoH, VoH;
    float NoH2, NxH2;   // cos^2 and sin^2 of theta_h (both scaled by |N|^2 |H|^2, which tan^2 cancels)
    bool specular;      // false: no specular term (light or view below the surface, or H undefined)
} CT_Frame;

SL_INLINE CT_Frame CT_frame(sl_v3 N, sl_v3 L, sl_v3 V) {
    CT_Frame f;
    f.NoL = sl_dot(N, L);
    f.NoV = sl_dot(N, V);
    const sl_v3 s = sl_add(L, V);
    const float len2 = sl_dot(s, s);
    // L = -V: H is undefined. With NoL, NoV > 0 that can only happen at the horizon (NoL + NoV = N.(L + V)
    // <= |L + V|), so the cut at |L + V|^2 <= 1e-12 removes only NoV, NoL < 1e-6 (see G_VGroove_over_NoV).
    // Comparisons with NaN are false: NaN input gets no specular term.
    f.specular = f.NoL > 0.0f && f.NoV > 0.0f && len2 > 1e-12f;
    const float inv_len = rsqrt(fmax(len2, 1e-30f));
    const sl_v3 H = sl_scale(s, inv_len);
    f.NoH = fmax(sl_dot(N, H), 0.0f);
    // VoH = LoH = |L + V| / 2 for unit L and V. Formed from |L + V| rather than dot(V, H): symmetric in L and V, and
    // free of the cancellation in dot(V, H) when L ~ -V, where the float inputs' lengths (1 +- 6e-8) dominate:
    // dot(V, H) - dot(L, H) = (|V|^2 - |L|^2) / |L + V|, a factor 3 apart at |L + V| = 2e-4 (seen in the sweep).
    // It is > 5e-7 wherever the lobe is evaluated (len2 > 1e-12); the cap at 1 keeps (1 - VoH)^5 >= 0 when the
    // inputs' lengths put |L + V| / 2 a rounding above 1.
    f.VoH = fmin(0.5f * len2 * inv_len, 1.0f);
    const sl_v3 NxH = sl_cross(N, H);
    f.NoH2 = f.NoH * f.NoH;
    f.NxH2 = sl_dot(NxH, NxH);
    return f;
}

// Diffuse base plus the specular part; spec = F D G / NoV (or 0).
SL_INLINE sl_rgb CT_value(float NoL, float spec, const ModelConsts* mc) {
    const CookTorranceConsts* k = SL_CONSTS(CookTorranceConsts, mc);
    return sl_diffuse_specular(mc, k->kd * fmax(NoL, 0.0f), k->ks * spec);
}

// ---- the models -----------------------------------------------------------------------------------------

// cook_torrance: Beckmann D, Schlick F, V-groove G. The reference combination.
SL_INLINE sl_rgb cook_torrance_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const CookTorranceConsts* k = SL_CONSTS(CookTorranceConsts, mc);
    const CT_Frame f = CT_frame(N, L, V);
    const float spec = f.specular ? F_Schlick(f.VoH, k->f0) * D_Beckmann(f.NoH2, f.NxH2, k->inv_m2, k->inv_pi_m2) *
                                        G_VGroove_over_NoV(f.NoL, f.NoV, f.NoH, f.VoH)
                                  : 0.0f;
    return CT_value(f.NoL, spec, mc);
}

// cook_torrance_ggx: GGX (Trowbridge-Reitz) D in place of Beckmann; same F and G.
SL_INLINE sl_rgb cook_torrance_ggx_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const CookTorranceConsts* k = SL_CONSTS(CookTorranceConsts, mc);
    const CT_Frame f = CT_frame(N, L, V);
    const float spec = f.specular ? F_Schlick(f.VoH, k->f0) * D_GGX(f.NoH2, f.NxH2, k->m2) *
                                        G_VGroove_over_NoV(f.NoL, f.NoV, f.NoH, f.VoH)
                                  : 0.0f;
    return CT_value(f.NoL, spec, mc);
}

// cook_torrance_exact_fresnel: the exact dielectric Fresnel term (the 1982 paper's own F) in place of Schlick.
SL_INLINE sl_rgb cook_torrance_exact_fresnel_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P,
                                                  const ModelConsts* mc) {
    (void)P;
    const CookTorranceConsts* k = SL_CONSTS(CookTorranceConsts, mc);
    const CT_Frame f = CT_frame(N, L, V);
    const float spec = f.specular ? F_Dielectric(f.VoH, k->inv_eta, k->one_minus_inv_eta2) *
                                        D_Beckmann(f.NoH2, f.NxH2, k->inv_m2, k->inv_pi_m2) *
                                        G_VGroove_over_NoV(f.NoL, f.NoV, f.NoH, f.VoH)
                                  : 0.0f;
    return CT_value(f.NoL, spec, mc);
}

// cook_torrance_seed004: the slides' Schlick with theta read as the angle between H and V, in radians.
SL_INLINE sl_rgb cook_torrance_seed004_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const CookTorranceConsts* k = SL_CONSTS(CookTorranceConsts, mc);
    const CT_Frame f = CT_frame(N, L, V);
    const float theta = atan2(sl_length(sl_sub(L, V)), sl_length(sl_add(L, V)));   // see F_SchlickSeedAngle
    const float spec = f.specular ? F_SchlickSeedAngle(theta, k->f0) *
                                        D_Beckmann(f.NoH2, f.NxH2, k->inv_m2, k->inv_pi_m2) *
                                        G_VGroove_over_NoV(f.NoL, f.NoV, f.NoH, f.VoH)
                                  : 0.0f;
    return CT_value(f.NoL, spec, mc);
}
#endif
