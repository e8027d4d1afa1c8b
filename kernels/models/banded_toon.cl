// Banded lighting and toon shading: NoL (and a Blinn-Phong highlight) quantised into a few flat levels.
// Artist models in the value convention of common.cl; none is reciprocal. docs/models/banded_toon.md
// has the exact rules, the seed's slips, the parameter ranges and the measured kernel errors.
//
// Notation: NoL = dot(N, L); NoH with H = normalize(L + V); steps = number of lit bands (banded);
// t = seed 001's _LightSteps; n = Blinn-Phong exponent; width = smoothing width of a band edge.
// Quantisers are discontinuous: an input exactly at a band edge takes the UPPER level, and float
// rounding of NoL (~1e-7) can move an input that lies within a few ulps of an edge to the other band.
#ifndef SHADELAB_MODEL_BANDED_TOON_CL
#define SHADELAB_MODEL_BANDED_TOON_CL
#include "common.cl"
#include "phong.cl"   // BlinnPhong_NoH, Spec_Power
#include "consts/banded_toon.h"

// ---- terms ----------------------------------------------------------------------------------------

// Banded NoL: max(0, NoL) rounded to the nearest multiple of 1 / steps,
//   Band_Round(NoL) = floor(max(0, NoL) * steps + 1/2) / steps,
// i.e. seed 001's rounding with its step size corrected to 1 / steps (the seed's comment thread says
// _LightSteps is the number of bands). Levels 0, 1/steps, ..., 1: `steps` lit levels plus unlit, with
// edges at NoL = (k + 1/2) / steps. Rounding (not floor or ceil) keeps 0 at the terminator and 1
// head-on, and leaves the directional albedo of a banded Lambert surface exactly Lambert's (1) for
// every steps. Use it anywhere NoL is used: albedo * Band_Round(NoL) is banded Lambert.
// inv_steps = 1 / steps, precomputed on the host.
SL_INLINE float Band_Round(float NoL, float steps, float inv_steps) {
    return sl_floor_nonneg(fmax(NoL, 0.0f) * steps + 0.5f) * inv_steps;   // common.cl: its argument is >= 1/2
}

// Seed 001's banded NoL, literally (with its `_lightBandsMultiplier` typo read as lightBandsMultiplier):
//   floor((max(0, NoL) * 256 + t / 2) / t) * (t / 256),   t = _LightSteps.
// This rounds NoL to the nearest multiple of t / 256: t is a step size in 1/256 units, NOT a band count.
// t = 256 / s (s a power of two) equals Band_Round with steps = s; t = 1 gives 256 levels (almost no
// banding); for t not dividing 256 the top level can exceed 1 (t = 170: 1.328 for NoL >= 0.996).
// half_t = t / 2 and t_256 = t / 256 precomputed on the host (as the seed's two named constants).
SL_INLINE float Band_Seed001(float NoL, float t, float half_t, float t_256) {
    return sl_floor_nonneg((fmax(NoL, 0.0f) * 256.0f + half_t) / t) * t_256;   // common.cl: its argument is >= 0
}

// Hermite smoothstep over [e0, e0 + w] as OpenCL defines it: t = clamp((x - e0) / w, 0, 1), t^2 (3 - 2 t), with
// the slope inv_w = 1 / w precomputed on the host (toon's six edges divided by w each: a division is the
// costliest instruction of the vectorised loop). Written out because PoCL's smoothstep and step are calls the
// work-item loop vectoriser cannot widen.
SL_INLINE float Toon_Smoothstep(float e0, float inv_w, float x) {
    const float t = sl_saturate((x - e0) * inv_w);
    return t * t * (3.0f - 2.0f * t);
}

// One toon band edge at threshold `edge`: half_width 0 gives a hard step (x >= edge -> 1: a value
// exactly at the edge takes the upper level); half_width > 0 a smoothstep over
// [edge - half_width, edge + half_width], inv_width = 1 / (2 half_width). (Smoothstep is undefined for equal
// edges, hence the explicit hard case; both are computed and one selected, so there is no branch.)
SL_INLINE float Toon_Step(float x, float edge, float half_width, float inv_width) {
    const float smooth = Toon_Smoothstep(edge - half_width, inv_width, x);
    const float hard = x >= edge ? 1.0f : 0.0f;
    return half_width > 0.0f ? smooth : hard;
}

// Toon diffuse: four levels d0..d3 over the unclamped NoL with ascending thresholds t1 <= t2 <= t3,
//   d0 + (d1 - d0) Step(NoL, t1) + (d2 - d1) Step(NoL, t2) + (d3 - d2) Step(NoL, t3).
// ToonConsts: t1..t3, d0 and the level differences dd1..dd3 (host).
// Written for PoCL's loop vectoriser: the steps are the same computation at thresholds that sit next to each
// other in memory, and as a sum of products they are what LLVM's SLP vectoriser packs into <2 x float>
// (a horizontal reduction over adjacent loads), which stops the loop vectoriser (toon ran 51 Mfrag/s, one
// fragment at a time). So the sum is an fma chain (no reduction to match) and each step starts after the
// previous one (common.cl's sl_after: no two steps are independent, so none can be bundled).
SL_INLINE float Toon_Diffuse(float NoL, float half_width, const ToonConsts* k) {
    const float s1 = Toon_Step(NoL, k->t1, half_width, k->inv_width);
    const float s2 = Toon_Step(sl_after(NoL, s1), k->t2, half_width, k->inv_width);
    const float s3 = Toon_Step(sl_after(NoL, s2), k->t3, half_width, k->inv_width);
    return fma(k->dd3, s3, fma(k->dd2, s2, fma(k->dd1, s1, k->d0)));
}

// Toon specular: three levels s0..s2 of the Blinn-Phong intensity x = max(0, NoH)^n with thresholds
// u1 <= u2, s0 + (s1 - s0) Step(x, u1) + (s2 - s1) Step(x, u2).
// ToonConsts: u1, u2, s0 and the level differences ds1, ds2 (host). Written as Toon_Diffuse, for the same reason.
SL_INLINE float Toon_Specular(float x, float half_width, const ToonConsts* k) {
    const float s1 = Toon_Step(x, k->u1, half_width, k->inv_width);
    const float s2 = Toon_Step(sl_after(x, s1), k->u2, half_width, k->inv_width);
    return fma(k->ds2, s2, fma(k->ds1, s1, k->s0));
}

// ---- models ---------------------------------------------------------------------------------------

// banded: banded Lambert, value = albedo * floor(max(0, NoL) * steps + 1/2) / steps.
// BandedConsts: steps (whole number in [1, 256]), inv_steps = 1 / steps. Source: seed 001 (banded lighting), rule
// corrected as above. Directional albedo: exactly 1 for albedo 1 (rounding is unbiased per band).
SL_INLINE sl_rgb banded_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)V; (void)P;
    const BandedConsts* k = SL_CONSTS(BandedConsts, mc);
    return sl_albedo_times(mc, Band_Round(sl_dot(N, L), k->steps, k->inv_steps));
}

// banded_seed001: value = albedo * (seed 001's bandedNdotL) with t = light_steps (whole number in
// [1, 256]). BandedSeed001Consts: t, half_t = t / 2, t_256 = t / 256.
SL_INLINE sl_rgb banded_seed001_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)V; (void)P;
    const BandedSeed001Consts* k = SL_CONSTS(BandedSeed001Consts, mc);
    return sl_albedo_times(mc, Band_Seed001(sl_dot(N, L), k->t, k->half_t, k->t_256));
}

// toon: value = albedo * Toon_Diffuse(NoL) + specular * Toon_Step(NoL, 0) * Toon_Specular(max(0, NoH)^n)
// Seed 004 ("discretize diffuse and specular factor: ~4 intensity values for diffuse, ~3 for
// specular"); hard shading as in Lake, Marshall, Harris, Blackstein 2000, "Stylized rendering
// techniques for scalable real-time 3D animation" (NPAR), with the 1-D texture replaced by thresholds.
// ToonConsts: n, half_width = width / 2, inv_width = 1 / width, the levels. The highlight is gated by the
// light's side, an edge at NoL = 0 like the others (hard: NoL >= 0; smoothed with the same width), and is 0
// where H is undefined (L = -V).
// Leaves out: energy conservation, reciprocity, outlines.
SL_INLINE sl_rgb toon_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)P;
    const float NoL = sl_dot(N, L);
    const ToonConsts* k = SL_CONSTS(ToonConsts, mc);
    const float half_width = k->half_width;
    const float x = Spec_Power(BlinnPhong_NoH(N, L, V), k->n);
    return sl_diffuse_specular(mc, Toon_Diffuse(NoL, half_width, k),
                               Toon_Step(NoL, 0.0f, half_width, k->inv_width) * Toon_Specular(x, half_width, k));
}

#endif
