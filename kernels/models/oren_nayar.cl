// The Oren-Nayar family: rough diffuse reflection from V-cavity microfacets (Oren & Nayar 1994,
// "Generalization of Lambert's Reflectance Model", SIGGRAPH '94) and the forms graphics made of it.
// docs/models/oren_nayar.md has the formulas, the derivations, the sources and the measured errors.
//
//   oren_nayar           paper's qualitative model (QON), trig form: sin(alpha), tan(beta), cos(phi_i - phi_r)
//   oren_nayar_st        the same function, trig-free: max(0, s) / max(NoL, NoV), s = LoV - NoL NoV
//   oren_nayar_full      paper's full model: C1, C2, C3 and the interreflection term (rho^2)
//   oren_nayar_seed001   seed 001 (Unity-style): Fujii's s/t form with the 0.17 rho colour term, saturate(LoV)
//   oren_nayar_seed003   seed 003 (HLSL): "PhiR" = product of tangential lengths instead of cos(phi_i - phi_r)
//   oren_nayar_seed004   seed 004 (slides): A with 0.57 instead of 0.33, unnormalised gamma = s
//   oren_nayar_blender   Blender 2.4x OrenNayar_Diff: the paper's QON with beta scaled by 0.95
//   oren_nayar_fujii     Fujii (2013) "improved" ON with his energy-conserving sigma' in [0, 1] ("FON")
//   oren_nayar_fujii_full Fujii's s/t form with his A, B matched to the full model (A depends on rho)
//   eon                  Portsmouth, Kutz, Hill (2025) energy-preserving Oren-Nayar, analytic E_FON
//   eon_approx           the same with the paper's fitted polynomial E_FON
//
// Value convention (common.cl): value = pi * f_r * NoL; every model here is 0 for NoL <= 0.
// Notation: theta_i, theta_r polar angles of L and V; phi_i - phi_r their azimuth difference around N;
// alpha = max(theta_i, theta_r), beta = min(theta_i, theta_r); Lt = L - N NoL, Vt = V - N NoV (tangential parts).
//
// View below the horizon (NoV < 0; interpolated normals at silhouettes): the paper-based models (QON, st,
// full, Fujii, EON) treat it as a grazing view at the same azimuth: theta_r = 90 deg (NoV := 0,
// sin(theta_r) := 1), phi_r from Vt. This is what Blender 2.4x does (nv = max(NoV, 0), azimuth from the
// normalised projection), keeps the value continuous across NoV = 0, makes sigma = 0 equal to Lambert for
// every V, and keeps the trig and s/t forms equal there too. The seed models keep their seeds' own handling.
//
// Key identity (docs derive it): for unit vectors
//   s = LoV - NoL NoV = sl_dot(Lt, Vt) = sin(theta_i) sin(theta_r) cos(phi_i - phi_r),
//   sin(alpha) tan(beta) = sin(theta_i) sin(theta_r) / cos(beta) = sin(theta_i) sin(theta_r) / max(NoL, NoV),
// hence max(0, cos(phi_i - phi_r)) sin(alpha) tan(beta) = max(0, s) / max(NoL, NoV).
#ifndef SHADELAB_MODEL_OREN_NAYAR_CL
#define SHADELAB_MODEL_OREN_NAYAR_CL
#include "common.cl"
#include "consts/oren_nayar.h"

// ---- shared geometry ------------------------------------------------------------------------------------

// sin(theta) of W from N as |N x W|: exact for unit vectors and, unlike sqrt(1 - NoW^2), without
// cancellation near normal incidence (there a float NoW error of 6e-8 becomes 6e-8 / sin(theta) in
// sqrt(1 - NoW^2), 6% of sin(theta) at theta = 1e-3; the cross product keeps ~1e-7 absolute).
SL_INLINE float ON_sin_theta(sl_v3 N, sl_v3 W) { return sl_length(sl_cross(N, W)); }

// cos(phi_i - phi_r) from the tangential projections. Undefined when either projection vanishes (L or V
// along +-N: no azimuth); 0 is returned there. Every term it multiplies is then 0 as well (tan(beta) = 0
// for L or V = N), except for V = -N below the horizon, where the azimuth-dependent term is dropped.
SL_INLINE float ON_cos_dphi(sl_v3 N, sl_v3 L, sl_v3 V, float NoL, float NoV) {
    const sl_v3 Lt = sl_sub(L, sl_scale(N, NoL));
    const sl_v3 Vt = sl_sub(V, sl_scale(N, NoV));
    // |Lt|^2 |Vt|^2 = |Lt x Vt|^2 + (Lt . Vt)^2 (Lagrange's identity; two non-negative terms). The product of
    // the two squared lengths is what LLVM's SLP vectoriser pairs into <2 x float>, which stops the loop vectoriser.
    const float s = sl_dot(Lt, Vt);
    const sl_v3 c = sl_cross(Lt, Vt);
    const float d2 = fma(s, s, sl_dot(c, c));
    return d2 > 1e-30f ? s * rsqrt(d2) : 0.0f;
}

// s = LoV - NoL NoV = sin(theta_i) sin(theta_r) cos(phi_i - phi_r), with the below-horizon convention:
// for NoV < 0, theta_r := 90 deg, i.e. s = sl_dot(Lt, Vt) / |Vt|, |Vt| = sin_r = |N x V| (from the cross product:
// sqrt(1 - NoV^2) would cost 1/sin^2 conditioning as V -> -N); 0 at V = -N (no azimuth, as in ON_cos_dphi).
SL_INLINE float ON_s(float LoV, float NoL, float NoV, float sin_r) {
    const float s = LoV - NoL * NoV;
    const float s_below = sin_r > 1e-15f ? s / sin_r : 0.0f;
    return NoV >= 0.0f ? s : s_below;
}

// ---- the paper's qualitative model (QON) ------------------------------------------------------------------

// Oren & Nayar 1994, qualitative model (A, B packed on the host from sigma, radians):
//   value = albedo * NoL * (A + B * max(0, cos(phi_i - phi_r)) * sin(alpha) * tan(beta))
//   A = 1 - 0.5 sigma^2 / (sigma^2 + 0.33),  B = 0.45 sigma^2 / (sigma^2 + 0.09)
// Leaves out: the interreflection term and the C3 term of the full model (oren_nayar_full); 1/pi cancels.
// Trig form: the paper's three factors evaluated separately, each from the cosines and |N x W| (as pbrt-v3
// does) instead of acos/sin/tan: equal, and tan(acos(x)) in float loses its sign near x = 0 (docs).
// Constants: OrenNayarConsts (A, B).
SL_INLINE float ON_sin_alpha_tan_beta(float NoL, float NoVc, float sin_i, float sin_r) {
    // alpha = max(theta_i, theta_r) is the angle with the smaller cosine; beta the one with the larger.
    const bool light_is_beta = NoL >= NoVc;
    const float sin_a = light_is_beta ? sin_r : sin_i;
    const float sin_b = light_is_beta ? sin_i : sin_r;
    const float cos_b = fmax(NoL, NoVc);   // >= NoL > 0 wherever the value is used: no division by 0
    return sin_a * (sin_b / cos_b);
}

SL_INLINE float Fd_OrenNayar(float A, float B, float cos_dphi, float sin_alpha_tan_beta) {
    return A + B * fmax(cos_dphi, 0.0f) * sin_alpha_tan_beta;
}

SL_INLINE sl_rgb oren_nayar_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const float NoV = sl_dot(N, V);
    const float NoVc = fmax(NoV, 0.0f);                              // below horizon: grazing view
    const float sin_i = ON_sin_theta(N, L);
    const float sin_r = NoV >= 0.0f ? ON_sin_theta(N, V) : 1.0f;    // below horizon: theta_r = 90 deg
    const OrenNayarConsts* k = SL_CONSTS(OrenNayarConsts, mc);
    const float f = Fd_OrenNayar(k->A, k->B, ON_cos_dphi(N, L, V, NoL, NoV),
                                 ON_sin_alpha_tan_beta(NoL, NoVc, sin_i, sin_r));
    return sl_albedo_times(mc, NoL > 0.0f ? NoL * f : 0.0f);
}

// The same QON, trig-free (the form of Fujii 2013 and of seed 001, with the paper's clamp at 0):
//   value = albedo * NoL * (A + B * max(0, s) / max(NoL, NoV)),  s = LoV - NoL NoV
// Equal to oren_nayar by the identity in the header; no sqrt, no trig (one more sqrt below the horizon).
// Constants: OrenNayarConsts (A, B).
SL_INLINE float Fd_OrenNayar_st(float A, float B, float s, float NoL, float NoVc) {
    return A + B * fmax(s, 0.0f) / fmax(NoL, NoVc);
}

SL_INLINE sl_rgb oren_nayar_st_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const float NoV = sl_dot(N, V);
    const float s = ON_s(sl_dot(L, V), NoL, NoV, ON_sin_theta(N, V));
    const OrenNayarConsts* k = SL_CONSTS(OrenNayarConsts, mc);
    const float f = Fd_OrenNayar_st(k->A, k->B, s, NoL, fmax(NoV, 0.0f));
    return sl_albedo_times(mc, NoL > 0.0f ? NoL * f : 0.0f);
}

// ---- the paper's full model ---------------------------------------------------------------------------------

// Oren & Nayar 1994, the functional approximation of the V-cavity model with interreflections:
//   value = NoL * (albedo * L1 + albedo^2 * L2)
//   L1 = C1 + cos(dphi) C2 tan(beta) + (1 - |cos(dphi)|) C3 tan((alpha + beta) / 2)
//   L2 = 0.17 sigma^2 / (sigma^2 + 0.13) * (1 - cos(dphi) (2 beta / pi)^2)
//   C1 = 1 - 0.5 sigma^2 / (sigma^2 + 0.33)
//   C2 = 0.45 sigma^2 / (sigma^2 + 0.09) * (sin(alpha)                     if cos(dphi) >= 0
//                                           sin(alpha) - (2 beta / pi)^3  otherwise)
//   C3 = 0.125 sigma^2 / (sigma^2 + 0.09) * (4 alpha beta / pi^2)^2
// cos(dphi) is signed here (no clamp). Leaves out nothing of the paper's approximation; 1/pi cancels.
// alpha, beta are needed as angles: atan2(|N x W|, N.W), equal to acos(N.W) but accurate near 0 where
// d acos / dx -> infinity. tan((alpha + beta)/2) = (sin alpha + sin beta) / (cos alpha + cos beta) (half-angle
// identity; the denominator is >= NoL > 0, so no tan near 90 deg). The value can dip slightly below 0 at
// grazing forward scattering for large sigma and small albedo (docs measure it); it is not clamped.
// Constants: OrenNayarFullConsts (C1, C2_scale = 0.45 sigma^2/(sigma^2+0.09), C3_scale = 0.125 sigma^2/(sigma^2+0.09),
// L2_scale = 0.17 sigma^2/(sigma^2+0.13)).
SL_INLINE float ON_C2(float c2, float cos_dphi, float sin_a, float two_beta_over_pi) {
    const float cube = two_beta_over_pi * two_beta_over_pi * two_beta_over_pi;
    return c2 * (cos_dphi >= 0.0f ? sin_a : sin_a - cube);
}

SL_INLINE float ON_C3(float c3, float alpha, float beta) {
    const float q = 4.0f * alpha * beta * (SL_INV_PI * SL_INV_PI);
    return c3 * q * q;
}

SL_INLINE float ON_L2(float c4, float cos_dphi, float two_beta_over_pi) {
    return c4 * (1.0f - cos_dphi * two_beta_over_pi * two_beta_over_pi);
}

// One channel of the full model's value, NoL (rho L1 + rho^2 L2) for albedo rho; 0 for NoL <= 0.
SL_INLINE float ON_full_channel(float rho, float NoL, float L1, float L2) {
    return NoL > 0.0f ? NoL * (rho * L1 + rho * rho * L2) : 0.0f;
}

SL_INLINE sl_rgb oren_nayar_full_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const float NoV = sl_dot(N, V);
    const float NoVc = fmax(NoV, 0.0f);
    const float sin_i = ON_sin_theta(N, L);
    const float sin_r = NoV >= 0.0f ? ON_sin_theta(N, V) : 1.0f;
    // theta_r after theta_i (common.cl's sl_after): two atan2 side by side are what LLVM's SLP vectoriser packs.
    const float theta_i = atan2(sin_i, NoL);
    const float theta_r = atan2(sin_r, sl_after(NoVc, theta_i));
    const bool light_is_beta = NoL >= NoVc;
    const float alpha = light_is_beta ? theta_r : theta_i;
    const float beta = light_is_beta ? theta_i : theta_r;
    const float sin_a = light_is_beta ? sin_r : sin_i;
    const float sin_b = light_is_beta ? sin_i : sin_r;
    const float cos_a = fmin(NoL, NoVc);
    const float cos_b = fmax(NoL, NoVc);
    const float cos_dphi = ON_cos_dphi(N, L, V, NoL, NoV);
    const float tbp = 2.0f * beta * SL_INV_PI;
    const float tan_beta = sin_b / cos_b;
    const float tan_half = (sin_a + sin_b) / (cos_a + cos_b);
    const OrenNayarFullConsts* k = SL_CONSTS(OrenNayarFullConsts, mc);
    const float L1 = k->C1 + cos_dphi * ON_C2(k->C2_scale, cos_dphi, sin_a, tbp) * tan_beta +
                     (1.0f - fabs(cos_dphi)) * ON_C3(k->C3_scale, alpha, beta) * tan_half;
    const float L2 = ON_L2(k->L2_scale, cos_dphi, tbp);
    return sl_rgb_make(ON_full_channel(mc->albedo[0], NoL, L1, L2), ON_full_channel(mc->albedo[1], NoL, L1, L2),
                       ON_full_channel(mc->albedo[2], NoL, L1, L2));
}

// ---- the seeds' forms ---------------------------------------------------------------------------------------

// Seed 001 (Unity-style article), literally:
//   fraction = r^2 / (r^2 + (0.33, 0.13, 0.09));  on = (1, 0, 0) + (-0.5, 0.17, 0.45) * fraction
//   NoL, NoV saturated; s = saturate(LoV) - NoL NoV;  s /= (s <= 0 ? 1 : max(NoL, NoV))
//   value = albedo * NoL * (on.x + albedo * on.y + on.z * s)
// on.x = the paper's A, on.z = its B, on.y = the 0.17 sigma^2/(sigma^2+0.13) factor of the full model's
// interreflection term (without its (1 - cos(dphi)(2 beta/pi)^2)): this is Fujii's form "matched to full O-N"
// (oren_nayar_fujii_full) except for saturate(LoV). Negative s is kept (t = 1), unlike QON's clamp.
// Constants: OrenNayarAlbedoConsts (A = on.x, A_rho = on.y, B = on.z).
// One channel, rho NoL (on.x + rho on.y + on.z s) for albedo rho. Guard: NoL = 0 (saturated) with NoV = 0 and
// LoV > 0 divides by 0; the seed's own factor NoL makes the value 0 there, which is what is returned (without
// 0 * inf).
SL_INLINE float ON_seed001_channel(float rho, float NoL, float s, const OrenNayarAlbedoConsts* k) {
    return NoL > 0.0f ? rho * NoL * (k->A + rho * k->A_rho + k->B * s) : 0.0f;
}

SL_INLINE sl_rgb oren_nayar_seed001_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_saturate(sl_dot(N, L));
    const float NoV = sl_saturate(sl_dot(N, V));
    float s = sl_saturate(sl_dot(L, V)) - NoL * NoV;
    s /= s <= 0.0f ? 1.0f : fmax(NoL, NoV);   // max(NoL, NoV) >= NoL > 0 wherever the value is kept
    const OrenNayarAlbedoConsts* k = SL_CONSTS(OrenNayarAlbedoConsts, mc);
    return sl_rgb_make(ON_seed001_channel(mc->albedo[0], NoL, s, k),
                       ON_seed001_channel(mc->albedo[1], NoL, s, k),
                       ON_seed001_channel(mc->albedo[2], NoL, s, k));
}

// Seed 003 (HLSL notes), literally:
//   NoL, NoV saturated; PhiR = |V - N NoV| * |L - N NoL|            (= sin(theta_r) sin(theta_i))
//   Alpha = max(acos NoV, acos NoL), Beta = min(...);  R = roughness^2
//   A = 1 - 0.5 R / (R + 0.33), B = 0.45 R / (R + 0.09)
//   value = albedo * NoL * (A + B * max(0, PhiR) * sin(Alpha) * tan(Beta))
// With roughness = sigma, A and B are the paper's. The slip: PhiR is the product of the tangential lengths,
// not cos(phi_i - phi_r): the B term has no azimuth dependence and no clamp, so it brightens every direction
// (docs measure it). The snippet's DotDiffValue is multiplied by the albedo, as the seed's Lambert is.
// sin(acos(x)) = sqrt(1 - x^2) and tan(acos(x)) = sqrt(1 - x^2) / x exactly: used instead of the acos/sin/tan
// chain, because in float acos(x) for x < 4e-8 rounds to float(pi/2) > pi/2, whose tan is -2.3e7: NoL * tan
// then turns a grazing light into a large negative value (tests show it). Constants: OrenNayarConsts (A, B).
SL_INLINE sl_rgb oren_nayar_seed003_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_saturate(sl_dot(N, L));
    // NoV after NoL (sl_after): the two clamped dot products side by side are packed into <2 x float> on AVX2
    // hosts (pthread-haswell), which stops the work-item loop vectoriser
    const float NoV = sl_saturate(sl_dot(N, sl_v3_make(sl_after(V.x, NoL), V.y, V.z)));
    // Each second one of the two tangential lengths and of the two sines after the first (sl_after): the pairs
    // are the same computation on two inputs, which LLVM's SLP vectoriser would pack (common.cl says why not).
    const float len_v = sl_length(sl_sub(V, sl_scale(N, NoV)));
    const float PhiR = len_v * sl_length(sl_sub(L, sl_scale(N, sl_after(NoL, len_v))));
    const float cos_a = fmin(NoL, NoV);   // Alpha = max(acos NoV, acos NoL): the smaller cosine
    const float cos_b = fmax(NoL, NoV);   // Beta = min(...): the larger cosine, >= NoL > 0 where used
    const float sin_alpha = sqrt(fmax(1.0f - cos_a * cos_a, 0.0f));
    const float cos_b_after = sl_after(cos_b, sin_alpha);
    const float tan_beta = sqrt(fmax(1.0f - cos_b_after * cos_b_after, 0.0f)) / cos_b;
    const OrenNayarConsts* k = SL_CONSTS(OrenNayarConsts, mc);
    const float f = k->A + k->B * fmax(PhiR, 0.0f) * sin_alpha * tan_beta;
    return sl_albedo_times(mc, NoL > 0.0f ? NoL * f : 0.0f);
}

// Seed 004 (lecture slides), literally:
//   A = 1 - 0.5 r^2 / (r^2 + 0.57), B = 0.45 r^2 / (r^2 + 0.09)
//   alpha = max(angle(N, V), angle(N, L)), beta = min(...), C = sin(alpha) tan(beta)
//   gamma = (V - N (V.N)) . (L - N (L.N))                              (= s, not normalised)
//   value = albedo * max(0, NoL) * (A + B * max(0, gamma) * C)
// Slips against the paper: 0.57 for 0.33 in A (A nearer 1), and gamma = sin(theta_i) sin(theta_r) cos(dphi)
// where the paper has cos(dphi): the B term is scaled by sin(theta_i) sin(theta_r) <= 1. Angles from the raw
// dot products (a view below the horizon gives angle(N, V) > 90 deg, as the slides' formulas do).
// sin(alpha), tan(beta) from the cosines (exact; see seed 003 for why not acos/tan). Constants: OrenNayarConsts.
SL_INLINE sl_rgb oren_nayar_seed004_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const float NoV = sl_dot(N, V);
    const float gamma = sl_dot(sl_sub(V, sl_scale(N, NoV)), sl_sub(L, sl_scale(N, NoL)));
    const float cos_a = fmin(NoL, NoV);
    const float cos_b = fmax(NoL, NoV);   // >= NoL > 0 where used
    const float C = sqrt(fmax(1.0f - cos_a * cos_a, 0.0f)) * (sqrt(fmax(1.0f - cos_b * cos_b, 0.0f)) / cos_b);
    const OrenNayarConsts* k = SL_CONSTS(OrenNayarConsts, mc);
    const float f = k->A + k->B * fmax(gamma, 0.0f) * C;
    return sl_albedo_times(mc, NoL > 0.0f ? NoL * f : 0.0f);
}

// Blender 2.4x OrenNayar_Diff (source/blender/render/intern/source/shadeoutput.c), literally:
//   nv = max(NoV, 0); 0 if NoL <= 0
//   a = max(acos NoL, acos nv), b = 0.95 * min(acos NoL, acos nv)
//   t = max(0, normalize(L - N NoL) . normalize(V - N nv))
//   value = albedo * NoL * (A + B t sin(a) tan(b)),  A, B the paper's (from "rough" = sigma, radians)
// The 0.95 ("prevent tangens from shooting to inf") bounds tan(b) by tan(0.95 pi/2) = 12.7, at the cost of
// a darker B term everywhere. The same value with less trigonometry: sin(a) is the sine |N x W| of the larger
// angle, and only the smaller angle b goes through atan2(|N x W|, N.W) (= acos, accurate near 0): one atan2 and
// no sin where the literal form takes two and a sin (1.10-1.33x: docs/speed.md, "Blender's Oren-Nayar with one
// arctangent"). Blender's normalize_v3 returns a zero vector for a zero input, so t = 0 at L or V = N.
// Constants: OrenNayarConsts.
SL_INLINE sl_v3 ON_normalize_or_zero(sl_v3 v) {
    const float d2 = sl_dot(v, v);
    return sl_scale(v, d2 > 1e-30f ? rsqrt(d2) : 0.0f);
}

SL_INLINE sl_rgb oren_nayar_blender_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const float nv = fmax(sl_dot(N, V), 0.0f);
    const float sin_l = ON_sin_theta(N, L);
    // Blender's 90 deg for a view at or below the horizon: sine 1, cosine nv = 0
    const float sin_v = nv > 0.0f ? ON_sin_theta(N, V) : 1.0f;
    // a = max(lit, view) and b = min of the two angles, both in [0, pi/2] where the value is not 0 (NoL > 0, nv >= 0),
    // so ordered by their cosines: the larger cosine is the smaller angle. sin(a) is then the sine already at hand
    // (|N x W| for unit N and W), and one atan2, of the smaller angle, is left.
    const int lit_smaller = NoL >= nv;
    const float sin_a = lit_smaller ? sin_v : sin_l;
    const float b = 0.95f * atan2(lit_smaller ? sin_l : sin_v, lit_smaller ? NoL : nv);
    const sl_v3 Lt = ON_normalize_or_zero(sl_sub(L, sl_scale(N, NoL)));
    const sl_v3 Vt = ON_normalize_or_zero(sl_sub(V, sl_scale(N, nv)));
    const float t = fmax(sl_dot(Lt, Vt), 0.0f);
    const OrenNayarConsts* k = SL_CONSTS(OrenNayarConsts, mc);
    const float f = k->A + k->B * t * sin_a * tan(b);
    return sl_albedo_times(mc, NoL > 0.0f ? NoL * f : 0.0f);
}

// ---- Fujii's improved Oren-Nayar ------------------------------------------------------------------------------

// Fujii (2013) "A tiny improvement of Oren-Nayar reflectance model":
//   s = LoV - NoL NoV,  t = (s <= 0 ? 1 : max(NoL, NoV)),  f_r = albedo * (A + B s / t)
// Unlike QON, s <= 0 is not clamped (t = 1 keeps it continuous), which removes QON's dark ring and its
// Lambert fallback for LoV <= 0. Fujii's energy-conserving parameterisation by sigma' in [0, 1] (mixing ratio
// of the non-diffuse to the diffuse term), normalised at NoV = 0 (the maximum of the non-diffuse term):
//   A = 1 / (pi + (pi/2 - 2/3) sigma'),  B = sigma' A
// so value = pi f_r NoL = albedo * NoL * (1 + sigma' s/t) / (1 + (1/2 - 2/(3 pi)) sigma').
// This is "FON", the single-scattering lobe of EON. Constants: OrenNayarConsts (A = pi A, B = pi B).
SL_INLINE float ON_s_over_t(float s, float NoL, float NoVc) { return s > 0.0f ? s / fmax(NoL, NoVc) : s; }

SL_INLINE sl_rgb oren_nayar_fujii_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const float NoV = sl_dot(N, V);
    const float st = ON_s_over_t(ON_s(sl_dot(L, V), NoL, NoV, ON_sin_theta(N, V)), NoL, fmax(NoV, 0.0f));
    const OrenNayarConsts* k = SL_CONSTS(OrenNayarConsts, mc);
    const float f = k->A + k->B * st;
    return sl_albedo_times(mc, NoL > 0.0f ? NoL * f : 0.0f);
}

// Fujii's s/t form with his constants "to match the result with full O-N" (sigma in radians):
//   pi A = 1 - 0.5 sigma^2/(sigma^2+0.33) + 0.17 albedo sigma^2/(sigma^2+0.13),  pi B = 0.45 sigma^2/(sigma^2+0.09)
//   value = albedo * NoL * (pi A + pi B s / t)
// The albedo inside A is the full model's interreflection term with its angular factor dropped. Not energy
// conserving (Fujii: violated for albedo > 0.97). Constants: OrenNayarAlbedoConsts: pi A = A + albedo A_rho, pi B = B.
// One channel, rho NoL (x + rho y + z s/t) for albedo rho; 0 for NoL <= 0.
SL_INLINE float ON_fujii_full_channel(float rho, float NoL, float st, const OrenNayarAlbedoConsts* k) {
    return NoL > 0.0f ? rho * NoL * (k->A + rho * k->A_rho + k->B * st) : 0.0f;
}
SL_INLINE sl_rgb oren_nayar_fujii_full_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const float NoV = sl_dot(N, V);
    const float st = ON_s_over_t(ON_s(sl_dot(L, V), NoL, NoV, ON_sin_theta(N, V)), NoL, fmax(NoV, 0.0f));
    const OrenNayarAlbedoConsts* k = SL_CONSTS(OrenNayarAlbedoConsts, mc);
    return sl_rgb_make(ON_fujii_full_channel(mc->albedo[0], NoL, st, k),
                       ON_fujii_full_channel(mc->albedo[1], NoL, st, k),
                       ON_fujii_full_channel(mc->albedo[2], NoL, st, k));
}

// ---- EON: energy-preserving Oren-Nayar -----------------------------------------------------------------------

// Portsmouth, Kutz, Hill (2025) "EON: A practical energy-preserving rough diffuse BRDF", JCGT 14(1)
// (arXiv 2410.18026), as used by OpenPBR. Roughness r in [0, 1] (Fujii's sigma'):
//   f = f_ss + f_ms
//   f_ss = (albedo/pi) AF (1 + r s/t)                               (FON: Fujii, s/t as above)
//   f_ms = (rho_ms/pi) (1 - E(mu_o)) (1 - E(mu_i)) / (1 - Ebar)     (energy compensation)
//   AF = 1 / (1 + c1 r),  c1 = 1/2 - 2/(3 pi),  c2 = 2/3 - 28/(15 pi),  Ebar = AF (1 + c2 r)
//   E(mu) = AF (1 + r G(mu)/pi)                                     (FON directional albedo, exact)
//   G(mu) = sin(theta)(theta - sin(theta) mu) + 2/3 (sin(theta)/mu (1 - sin(theta)^3) - sin(theta))
//   rho_ms = albedo^2 Ebar / (1 - albedo (1 - Ebar))
// Evaluated without cancellation: 1 - E(mu) = r AF (c1 - G/pi) and 1 - Ebar = r AF (c1 - c2), so
//   f_ms = (rho_ms/pi) r AF (c1 - G_o/pi)(c1 - G_i/pi) / (c1 - c2)
// which is exactly 0 at r = 0 (the paper's listing guards 0/0 with max(1e-7, .) and so adds 1e-7 there), and
// sin(theta)/mu (1 - sin(theta)^3) = sin(theta) mu (1 + S + S^2)/(1 + S), S = sin(theta) (no 0/0 at mu = 0).
// Constants: EonConsts (AF, r, Ebar, k_ms = r AF / (c1 - c2), c1; all computed on the host in double).

// G(mu)/pi for the exact FON albedo (G(1) = 0, G(0)/pi = c1).
SL_INLINE float E_FON_G_over_pi(float mu) {
    const float S = sqrt(fmax(1.0f - mu * mu, 0.0f));
    const float theta = acos(clamp(mu, -1.0f, 1.0f));
    const float G = S * (theta - S * mu) + (2.0f / 3.0f) * (S * mu * (1.0f + S + S * S) / (1.0f + S) - S);
    return G * SL_INV_PI;
}

// The paper's polynomial fit of G/pi in 1 - mu (its E_FON_approx): g1 m + g2 m^2 + g3 m^3 + g4 m^4.
SL_INLINE float E_FON_G_over_pi_approx(float mu) {
    const float m = 1.0f - mu;
    return m * (0.0571085289f + m * (0.491881867f + m * (-0.332181442f + m * 0.0714429953f)));
}

// One channel of EON's value, NoL (f_ss + f_ms) for albedo rho (st = s/t, g_i, g_o = G/pi at NoL, NoV).
SL_INLINE float EON_channel(float rho, float NoL, float st, float g_i, float g_o, const EonConsts* k) {
    const float AF = k->AF, r = k->r, Ebar = k->Ebar, k_ms = k->k_ms, c1 = k->c1;
    const float f_ss = rho * (AF * (1.0f + r * st));
    // 1 - albedo (1 - Ebar) >= Ebar > 0.83 for albedo <= 1; the floor only matters for albedo > 5.9, where the
    // series behind rho_ms diverges (non-physical input), and keeps the value finite there.
    const float rho_ms = rho * rho * Ebar / fmax(1.0f - rho * (1.0f - Ebar), 1e-3f);
    // max(0, .): the polynomial fit slightly exceeds c1 near mu = 0 (by 4e-4); the listing clamps 1 - E there.
    const float f_ms = rho_ms * (k_ms * fmax(c1 - g_o, 0.0f) * fmax(c1 - g_i, 0.0f));
    // 0 for NoL <= 0 as a factor max(NoL, 0), not as NoL > 0 ? . : 0: that select, once per channel, becomes a
    // branch with one phi per channel, and LLVM's SLP vectoriser packs those phis (and the channels' arithmetic
    // under them) into <2 x float>, which stops PoCL's loop vectoriser. f_ss + f_ms is finite (EON_value passes
    // st = 0 where NoL <= 0, where s / t may be s / 0), so the product is 0 there.
    return fmax(NoL, 0.0f) * (f_ss + f_ms);
}

SL_INLINE sl_rgb EON_value(float NoL, float NoV, float s, float g_i, float g_o, const ModelConsts* mc) {
    // NoL <= 0: the value is 0 (EON_channel's factor); st is set to 0 there, as s / t divides by 0 when NoV <= 0 too.
    const float st = NoL > 0.0f ? ON_s_over_t(s, NoL, fmax(NoV, 0.0f)) : 0.0f;
    const EonConsts* k = SL_CONSTS(EonConsts, mc);
    return sl_rgb_make(EON_channel(mc->albedo[0], NoL, st, g_i, g_o, k),
                       EON_channel(mc->albedo[1], NoL, st, g_i, g_o, k),
                       EON_channel(mc->albedo[2], NoL, st, g_i, g_o, k));
}

SL_INLINE sl_rgb eon_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const float NoV = sl_dot(N, V);
    const float s = ON_s(sl_dot(L, V), NoL, NoV, ON_sin_theta(N, V));
    // The albedo of NoV after that of NoL (sl_after): the two are the same function, which SLP would pack.
    const float g_i = E_FON_G_over_pi(fmax(NoL, 0.0f));
    const float g_o = E_FON_G_over_pi(sl_after(fmax(NoV, 0.0f), g_i));
    return EON_value(NoL, NoV, s, g_i, g_o, mc);
}

// EON with the paper's fitted E_FON (its E_FON_approx): cheaper (no acos, sqrt); the white furnace deviates
// from 1 by the fit's error (docs).
SL_INLINE sl_rgb eon_approx_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const float NoV = sl_dot(N, V);
    const float s = ON_s(sl_dot(L, V), NoL, NoV, ON_sin_theta(N, V));
    const float g_i = E_FON_G_over_pi_approx(fmax(NoL, 0.0f));
    const float g_o = E_FON_G_over_pi_approx(sl_after(fmax(NoV, 0.0f), g_i));   // as in eon_eval
    return EON_value(NoL, NoV, s, g_i, g_o, mc);
}

#endif
