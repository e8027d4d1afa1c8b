// The Minnaert family: Minnaert's (1941) lunar limb-darkening law and the shading models graphics made of it.
// docs/models/minnaert.md has the formulas, the table mapping every parameter onto the 1941 k, and the
// measured kernel-vs-reference errors. All five depend on NoL and NoV only (not on LoV or H).
//
//   minnaert_1941        albedo * NoL^k * NoV^(k-1)                  Minnaert 1941, ApJ 93:403 (the reference law)
//   minnaert_unity       albedo * saturate(NoL * (NoL*NoV)^k)        seeds 000, 001 ("_Roughness"; k = k_1941 - 1)
//   minnaert_blender     albedo * Blender 2.4x Minnaert_Diff(d)      seed 002; Blender's shadeoutput.c
//   minnaert_b           albedo * NoL * NoL^k * (1 - NoV)^(1-k)      seed 002 ("MinnaertB")
//   minnaert_normalized  albedo * (k+1)/2 * NoL^k * NoV^(k-1)        the 1941 law scaled to unit albedo at normal incidence
//
// Behind the horizon: every model is 0 for NoL <= 0. For NoV <= 0 (viewer below the tangent plane) the two
// 1941-law models return 0, as the law is defined for mu, mu0 > 0; the three shader models keep their
// sources' own handling, max(0, NoV) (seeds 000/001, Blender), which keeps them continuous across silhouettes.
#ifndef SHADELAB_MODEL_MINNAERT_CL
#define SHADELAB_MODEL_MINNAERT_CL
#include "common.cl"
#include "consts/minnaert.h"

// ---- terms --------------------------------------------------------------------------------------------

// 1 - NoV for unit N and V, computed as |N - V|^2 / 2: the two are equal for unit vectors, and this form has
// no cancellation as V -> N, where 1 - sl_dot(N, V) keeps no correct digit and a fractional power of it
// (MinnaertB's (1 - NoV)^(1-k), Blender's (1.001 - NoV)^(d-1)) would amplify that to 1e-2 of the value.
SL_INLINE float Minnaert_one_minus_NoV(sl_v3 N, sl_v3 V) {
    const sl_v3 d = sl_sub(N, V);
    return 0.5f * sl_dot(d, d);
}

// Limb guard of the 1941 law, for one cosine c (NoL or NoV): 1 above eps, falling linearly to 0 at c = 0.
// Why: for k < 1, (NoL NoV)^(k-1) diverges as either cosine -> 0 (the lunar limb, NoV -> 0). Below
// eps = 1e-3 (0.057 deg from grazing) each cosine's power is held at eps^(k-1) and faded linearly to 0,
// so the value is bounded (by albedo * eps^(k-1) <= 1000 albedo at k = 0), continuous where the surface
// turns away (no 1000x jump between a fragment at NoV = +1e-8 and one at -1e-8), and still reciprocal.
// For k >= 1 nothing diverges and the host passes eps = 0: the law is then used as is (k = 1 is Lambert).
// The guard is part of the model's definition (the reference applies it too); the law is exact for
// NoL, NoV >= eps, which no pixel of a disc under 10^6 pixels in radius ever samples beyond.
SL_INLINE float Minnaert_taper(float c, float eps, float inv_eps) { return c < eps ? c * inv_eps : 1.0f; }

// Minnaert's factor on Lambert, (NoL * NoV)^(k-1), with the limb guard: symmetric in NoL and NoV (reciprocal).
SL_INLINE float Minnaert_limb(float NoL, float NoV, float k_minus_1, float eps, float inv_eps) {
    return pow_nonneg(fmax(NoL, eps) * fmax(NoV, eps), k_minus_1) * Minnaert_taper(NoL, eps, inv_eps) *
           Minnaert_taper(NoV, eps, inv_eps);
}

// Seeds 000/001: saturate(NoL * pow(NoL * NoV, k)) with NoL, NoV already max(0, .)-clamped as the seeds do.
// For k < 0 the product's power exceeds 1 near the limb and the saturate clips it (pow(0, k < 0) = +inf,
// NoL * inf = inf, saturate -> 1: the seeds' value at and behind the limb; docs measure how often it clips).
SL_INLINE float Fd_MinnaertUnity(float NoL, float NoV, float k) {
    return sl_saturate(NoL * pow_nonneg(NoL * NoV, k));
}

// Blender 2.4x Minnaert_Diff, d <= 1 ("The Real model"): Minnaert's factor (nv nl)^(d-1) with nv nl clamped
// at 0.1, Blender's own guard against the limb singularity (seed 002). nv = max(NoV, 0) as in Blender.
SL_INLINE float Minnaert_blender_real(float NoL, float nv, float d_minus_1) {
    return pow_nonneg(fmax(nv * NoL, 0.1f), d_minus_1);
}

// Blender 2.4x Minnaert_Diff, d > 1 ("Nvidia model"): (1.001 - nv)^(d-1), darkening where the surface faces
// the viewer. 1.001 - nv is computed as 0.001 + (1 - nv) (see Minnaert_one_minus_NoV).
SL_INLINE float Minnaert_blender_nvidia(float one_minus_nv, float d_minus_1) {
    return pow_nonneg(0.001f + one_minus_nv, d_minus_1);   // one_minus_nv >= 0 (Minnaert_one_minus_NoV, or 1)
}

// Seed 002's MinnaertB factor on Lambert: NoL^k * (1 - NoV)^(1-k). pow(0, 0) = 1 at k = 1, V = N (the limit).
// Returned times a (the caller's NoL). The two powers are one exponential, 2^(k log2 NoL + (1-k) log2(1 - NoV))
// (common.cl's pow2_nonneg, which also keeps LLVM's SLP vectoriser from pairing the two logarithms, which would
// stop the loop vectoriser).
// For NoL > 0 and one_minus_NoV >= 0 (Minnaert_one_minus_NoV, or 1): the caller selects 0 where NoL <= 0, so the
// base max(NoL, 0) changes no value it keeps and lets both powers skip pow's tests for a negative or NaN base.
SL_INLINE float MinnaertB_factor_times(float a, float NoL, float one_minus_NoV, float k, float one_minus_k) {
    return a * pow2_nonneg(fmax(NoL, 0.0f), k, one_minus_NoV, one_minus_k);
}

// ---- models -------------------------------------------------------------------------------------------

// minnaert_1941 (Minnaert 1941, "The Reciprocity Principle in Lunar Photometry", ApJ 93:403):
//   value = albedo * NoL^k * NoV^(k-1) = albedo * NoL * (NoL NoV)^(k-1)    for NoL > 0 and NoV > 0, else 0
//   f_r = (albedo / pi) * (NoL NoV)^(k-1): reciprocal for every k. k = 1 is Lambert; at zero phase (L = V,
//   NoL = NoV = mu) the disc profile is mu^(2k-1), flat for k = 0.5.
// Parameter: k in [0, 2] (MinnaertConsts: k_minus_1 = k - 1, eps, inv_eps = 1/eps; eps = 1e-3 for k < 1, else 0).
// albedo is Minnaert's B0 (the value at NoL = NoV = 1), not a hemispherical albedo: the directional albedo is
// 2/(k+1) * NoV^(k-1), so neither energy-conserving for k < 1 nor normalised. Leaves out: phase dependence
// of k and B0 (planetary fits use k(alpha)); opposition surge; limb guard below NoL or NoV = 1e-3 (above).
SL_INLINE sl_rgb minnaert_1941_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L), NoV = sl_dot(N, V);
    const MinnaertConsts* k = SL_CONSTS(MinnaertConsts, mc);
    const float f = NoL * Minnaert_limb(NoL, NoV, k->k_minus_1, k->eps, k->inv_eps);
    return sl_albedo_times(mc, NoL > 0.0f && NoV > 0.0f ? f : 0.0f);
}

// minnaert_unity (seeds 000 "Shader Story" and 001, Unity-style HLSL):
//   value = albedo * saturate(NoL * (NoL NoV)^k),  NoL = max(0, N.L), NoV = max(0, N.V)    (0 for NoL <= 0)
// = albedo * min(1, NoL^(1+k) NoV^k): the 1941 law with k_1941 = k + 1, clipped at 1 (only possible for k < 0).
// Parameter: k ("_Roughness") in [-1, 1] (MinnaertUnityConsts: k); k = 0 is Lambert. Reciprocal for k >= 0 only (the clip
// is not symmetric). No limb guard needed: the saturate bounds it. NoL <= 0 returns 0 explicitly, where the
// seed's 0 * pow(0, k < 0) = 0 * inf would be NaN. Leaves out: 1/pi, any normalisation.
SL_INLINE sl_rgb minnaert_unity_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = fmax(sl_dot(N, L), 0.0f), NoV = fmax(sl_dot(N, V), 0.0f);
    const float f = Fd_MinnaertUnity(NoL, NoV, SL_CONSTS(MinnaertUnityConsts, mc)->k);
    return sl_albedo_times(mc, NoL > 0.0f ? f : 0.0f);
}

// minnaert_blender (Blender 2.37-2.7x internal renderer, source/blender/render/intern/source/shadeoutput.c,
// Minnaert_Diff; the "darkness" material setting, range [0, 2]):
//   d <= 1:  value = albedo * NoL * max(nv NoL, 0.1)^(d-1)     (1941 law with k = d where nv NoL >= 0.1)
//   d >  1:  value = albedo * NoL * (1.001 - nv)^(d-1)         (not a Minnaert law: darkens the centre)
//   nv = max(NoV, 0) (Blender clamps, it does not return 0 behind the limb); 0 for NoL <= 0.
// Parameter: darkness d in [0, 2] (MinnaertBlenderConsts: d_minus_1 = d - 1, real_branch = 1 for d <= 1 else 0); d = 1 is Lambert.
// Reciprocal for d <= 1 only. Leaves out: 1/pi, normalisation (d < 1 brightens up to 10x Lambert).
SL_INLINE sl_rgb minnaert_blender_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L), NoV = sl_dot(N, V);
    const float nv = fmax(NoV, 0.0f);
    const float one_minus_nv = NoV > 0.0f ? Minnaert_one_minus_NoV(N, V) : 1.0f;
    const MinnaertBlenderConsts* k = SL_CONSTS(MinnaertBlenderConsts, mc);
    const float factor = k->real_branch != 0.0f ? Minnaert_blender_real(NoL, nv, k->d_minus_1)
                                                : Minnaert_blender_nvidia(one_minus_nv, k->d_minus_1);
    return sl_albedo_times(mc, NoL > 0.0f ? NoL * factor : 0.0f);
}

// minnaert_b (seed 002, "MinnaertB", citing a course page I could not retrieve to check it against):
//   value = albedo * NoL * NoL^k * (1 - NoV)^(1-k),  NoV clamped to [0, 1] as shaders do;  0 for NoL <= 0
// Parameter: k in [0, 1] (MinnaertBConsts: k, one_minus_k = 1 - k). No k gives Lambert (k = 1 gives NoL^2); for k < 1 the
// value is 0 where the surface faces the viewer (NoV = 1) and largest at the limb: a velvet/rim look, not a
// lunar law. Never brighter than Lambert (energy-conserving), not reciprocal. Leaves out: 1/pi.
SL_INLINE sl_rgb minnaert_b_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L), NoV = sl_dot(N, V);
    const float one_minus_NoV = NoV > 0.0f ? Minnaert_one_minus_NoV(N, V) : 1.0f;
    const MinnaertBConsts* k = SL_CONSTS(MinnaertBConsts, mc);
    const float f = MinnaertB_factor_times(NoL, NoL, one_minus_NoV, k->k, k->one_minus_k);   // NoL * factor
    return sl_albedo_times(mc, NoL > 0.0f ? f : 0.0f);
}

// minnaert_normalized: the 1941 law as a normalised BRDF,
//   f_r = albedo * (k+1)/(2 pi) * (NoL NoV)^(k-1),  value = pi f_r NoL = albedo * (k+1)/2 * NoL^k * NoV^(k-1)
// The factor (k+1)/2 makes the directional albedo exactly `albedo` at normal incidence (and, by
// reciprocity, the white-furnace value for a viewer on the normal); at other angles it is albedo * mu^(k-1)
// (above albedo for k < 1, below for k > 1). Parameter: k in [0, 2] (MinnaertNormalizedConsts: k_minus_1, eps,
// inv_eps as minnaert_1941, norm = (k+1)/2). Same limb guard as minnaert_1941. k = 1 is Lambert.
SL_INLINE sl_rgb minnaert_normalized_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L), NoV = sl_dot(N, V);
    const MinnaertNormalizedConsts* k = SL_CONSTS(MinnaertNormalizedConsts, mc);
    const float f = k->norm * NoL * Minnaert_limb(NoL, NoV, k->k_minus_1, k->eps, k->inv_eps);
    return sl_albedo_times(mc, NoL > 0.0f && NoV > 0.0f ? f : 0.0f);
}

#endif
