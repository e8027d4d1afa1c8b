// Lommel-Seeliger and Lunar-Lambert: the two simplest disc-resolved laws of airless bodies, as USGS ISIS3 defines
// them (its photometric models LommelSeeliger and LunarLambert), written from the papers. docs/models/lunar_lambert.md
// has the formulas, ISIS's conventions and the measured kernel-vs-reference errors.
//
//   lommel_seeliger  2 mu0 / (mu0 + mu)                   Seeliger (1888); ISIS's normalisation (2x the classical)
//   lunar_lambert    mu0 ((1 - L) + 2 L / (mu0 + mu))     McEwen (1991) Icarus 92:298: L = 0 Lambert, 1 Lommel-Seeliger
//
// Value convention (docs/notation.md): value = pi f_r NoL, the radiance factor I/F for unit solar flux, which is
// what ISIS's models return with albedo 1. Like the planetary family (kernels/models/planetary.cl, whose
// photometric geometry and terms they use: sl_pho, Pho_visible, Pho_LommelSeeliger, Pho_LunarLambert) each law is
// written as `<model>_pho(sl_pho g, consts)` in photometric quantities, which kernels/photometry.cl calls straight
// from (phase, incidence, emission) triples, and `<model>_eval(N, L, V, P, consts)`, the catalogue's entry point.
// Both are 0 where the surface is not lit or not seen (mu0 <= 0 or mu <= 0).
#ifndef SHADELAB_MODEL_LUNAR_LAMBERT_CL
#define SHADELAB_MODEL_LUNAR_LAMBERT_CL
#include "common.cl"
#include "consts/lunar_lambert.h"
#include "planetary.cl"

// lommel_seeliger: 2 mu0 / (mu0 + mu). No parameters.
SL_INLINE float lommel_seeliger_pho(sl_pho g, const ModelConsts* mc) {
    (void)mc;
    return Pho_visible(g) ? Pho_LommelSeeliger(g.mu0, g.mu) : 0.0f;
}

// lunar_lambert: mu0 ((1 - L) + 2 L / (mu0 + mu)). LunarLambertConsts: L.
SL_INLINE float lunar_lambert_pho(sl_pho g, const ModelConsts* mc) {
    return Pho_visible(g) ? Pho_LunarLambert(g.mu0, g.mu, SL_CONSTS(LunarLambertConsts, mc)->L) : 0.0f;
}

// value = albedo * law(photometric quantities of N, L, V) (planetary.cl's entry-point pattern)
PHO_CATALOGUE_EVAL_WITH(lommel_seeliger, Pho_from_vectors_phase)
PHO_CATALOGUE_EVAL_WITH(lunar_lambert, Pho_from_vectors_phase)

#endif
