// Wrap lighting: diffuse terms that let light reach past the terminator (NoL = 0) so the shadow side
// keeps its shape. All are artist models written in the value convention of common.cl (NoL's role is
// taken by the term itself; there is no 1/pi). None is reciprocal; only Fd_Wrap conserves energy.
// docs/models/wrap.md has the formulas, their sources, the measured errors and the seed deviations.
//
// Notation: NoL = dot(N, L), unclamped (in [-1, 1]); wrap_value = the seed's "wrapValue" in [0.5, 1];
// w = Filament's wrap amount in [0, 1] (0 = Lambert). The two wrap parameters run in opposite
// directions: the squared wrap with wrap_value a and Fd_Wrap with w = (1 - a) / a both reach zero at
// NoL = -(1 - a) / a.
#ifndef SHADELAB_MODEL_WRAP_CL
#define SHADELAB_MODEL_WRAP_CL
#include "common.cl"
#include "consts/wrap.h"

// ---- terms ----------------------------------------------------------------------------------------

// Half-Lambert (Mitchell, McTaggart, Green 2006, "Shading in Valve's Source Engine", SIGGRAPH course;
// used since Half-Life, 1998): ((NoL + 1) / 2)^2 on the UNCLAMPED NoL.
// 1 head-on, 0.25 at the terminator, 0 only at NoL = -1 (light exactly behind).
// No clamp is needed: the base is >= 0 for NoL >= -1; float inputs that are unit only to ~1e-7 can
// give NoL = -1 - 1e-7, where the square returns ~1e-15 instead of 0 (harmless, not clamped).
SL_INLINE float Fd_HalfLambert(float NoL) {
    const float h = 0.5f * NoL + 0.5f;
    return h * h;
}

// Squared diffuse wrap (seed 001): (NoL * a + (1 - a))^2 with a = wrap_value in [0.5, 1]; a = 0.5 is
// half-Lambert. Guard: the base is clamped at 0 before squaring. Without it the square rises again
// beyond the wrap's own terminator NoL = -(1 - a) / a (a = 1 would give NoL^2: full light from
// directly behind). The clamp changes nothing where the base is >= 0, i.e. everywhere for a = 0.5.
// one_minus_a is precomputed on the host.
SL_INLINE float Fd_WrapSquared(float NoL, float a, float one_minus_a) {
    const float h = fmax(NoL * a + one_minus_a, 0.0f);
    return h * h;
}

// Energy-conserving wrap (Filament, google/filament shaders/src/surface_brdf.fs, Fd_Wrap, "energy
// conserving wrap diffuse term, does *not* include the divide by pi"):
//   saturate((NoL + w) / (1 + w)^2),  w in [0, 1],  w = 0 is Lambert's max(0, NoL).
// Integrated over the whole sphere of light directions it gives exactly 1 (the linear wrap
// (NoL + w) / (1 + w) of Green 2004, GPU Gems ch. 16, gives 1 + w; the extra 1 / (1 + w) removes that).
// inv_sq = 1 / (1 + w)^2, precomputed on the host. The upper clamp of saturate is never active for
// NoL <= 1 (the peak is 1 / (1 + w) <= 1); the lower clamp is the wrap's terminator at NoL = -w.
SL_INLINE float Fd_Wrap(float NoL, float w, float inv_sq) { return sl_saturate((NoL + w) * inv_sq); }

// ---- models ---------------------------------------------------------------------------------------

// half_lambert: value = albedo * ((NoL + 1) / 2)^2, NoL unclamped (Valve's form; the reference).
// Parameters: none. Leaves out: any physical basis (not reciprocal, directional albedo 7/6 over the
// hemisphere, 4/3 over the sphere).
SL_INLINE sl_rgb half_lambert_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)V; (void)P;
    const float NoL = sl_dot(N, L);
    return sl_albedo_times(mc, Fd_HalfLambert(NoL));
}

// half_lambert_seed001: value = albedo * ((max(0, NoL) + 1) / 2)^2 -- seed 001's code, which clamps NoL
// BEFORE the half-Lambert mapping, so every back-facing point gets a flat 0.25 instead of fading to 0.
// Kept as a named variant; the deviation (up to 0.25 * albedo at NoL = -1) is measured in the tests.
SL_INLINE sl_rgb half_lambert_seed001_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)V; (void)P;
    const float NoL = sl_dot(N, L);
    return sl_albedo_times(mc, Fd_HalfLambert(fmax(NoL, 0.0f)));
}

// wrap: value = albedo * max(0, NoL * a + (1 - a))^2, NoL unclamped, a = wrap_value in [0.5, 1]
// (WrapConsts: a, one_minus_a = 1 - a). a = 0.5: half_lambert; a = 1: max(0, NoL)^2 (narrower than Lambert).
SL_INLINE sl_rgb wrap_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)V; (void)P;
    const float NoL = sl_dot(N, L);
    const WrapConsts* k = SL_CONSTS(WrapConsts, mc);
    return sl_albedo_times(mc, Fd_WrapSquared(NoL, k->a, k->one_minus_a));
}

// wrap_seed001: value = albedo * (max(0, NoL) * a + (1 - a))^2 -- the seed's code applied to the wrap
// formula: NoL clamped first, so the back side gets a flat (1 - a)^2. (WrapConsts, as wrap.)
SL_INLINE sl_rgb wrap_seed001_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)V; (void)P;
    const float NoL = sl_dot(N, L);
    const WrapConsts* k = SL_CONSTS(WrapConsts, mc);
    return sl_albedo_times(mc, Fd_WrapSquared(fmax(NoL, 0.0f), k->a, k->one_minus_a));
}

// wrap_energy: value = albedo * saturate((NoL + w) / (1 + w)^2) (Filament's Fd_Wrap; WrapEnergyConsts: w,
// inv_sq = 1 / (1 + w)^2). Directional albedo over the sphere of light directions: exactly 1 for every w;
// over the upper hemisphere (1 + 2w) / (1 + w)^2 <= 1. Leaves out: reciprocity, any V dependence.
SL_INLINE sl_rgb wrap_energy_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)V; (void)P;
    const float NoL = sl_dot(N, L);
    const WrapEnergyConsts* k = SL_CONSTS(WrapEnergyConsts, mc);
    return sl_albedo_times(mc, Fd_Wrap(NoL, k->w, k->inv_sq));
}

#endif
