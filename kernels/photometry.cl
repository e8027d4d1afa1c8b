// Photometric-angle evaluation: a model at (phase, incidence, emission) triples, as ISIS3's photometric models are
// called, rather than at vectors. The host builds this file with
//   SL_MODEL_HEADER  the model's file, SL_EVAL its catalogue eval function, and, for the planetary family,
//   SL_PHO_EVAL      its `_pho` function (kernels/models/planetary.cl), which takes the angles as they are: the
//                    phase need not be one a facet with that incidence and emission can have.
// Models without a `_pho` form are evaluated at vectors built from the angles (N = z, L in the xz plane, V at
// azimuth psi), so for them only a consistent geometry is meaningful (psi is clamped as ISIS clamps it).
//
// The host computes each row's cosines, sines and half-angle tangents in double (cos 90 deg = 0 exactly) and
// passes seven arrays.
#include "common.cl"
#include SL_MODEL_HEADER
#include "models/planetary.cl"

// A non-finite value (only from invalid input) is written as 0 (common.cl's sl_finite_or_zero). Built with
// SL_PHO_RAW=1 (the tests) the value is written as it is, so that a NaN or Inf a law produces can be counted.
SL_INLINE float pho_finite_or_zero(float v) {
#if defined(SL_PHO_RAW) && SL_PHO_RAW
    return v;
#endif
    return sl_finite_or_zero(v);   // common.cl
}

// The law at row i of the seven arrays, written as the kernels below write it (non-finite as 0 unless SL_PHO_RAW).
SL_INLINE float pho_row(size_t i, __global const float* restrict mu0, __global const float* restrict mu,
                        __global const float* restrict sin_i, __global const float* restrict sin_e,
                        __global const float* restrict cos_g, __global const float* restrict tan_half_g,
                        __global const float* restrict tan_half_psi, const ModelConsts* mc) {
    sl_pho g;
    g.mu0 = mu0[i];
    g.mu = mu[i];
    g.sin_i = sin_i[i];
    g.sin_e = sin_e[i];
    g.cos_g = cos_g[i];
    g.tan_half_g = tan_half_g[i];
    g.tan_half_psi = tan_half_psi[i];
#ifdef SL_PHO_EVAL
    const float v = mc->albedo[0] * SL_PHO_EVAL(g, mc);
#else
    const float t2 = g.tan_half_psi * g.tan_half_psi;
    const float cos_psi = (1.0f - t2) / (1.0f + t2), sin_psi = 2.0f * g.tan_half_psi / (1.0f + t2);
    const sl_v3 N = sl_v3_make(0.0f, 0.0f, 1.0f), L = sl_v3_make(g.sin_i, 0.0f, g.mu0);
    const sl_v3 V = sl_v3_make(g.sin_e * cos_psi, g.sin_e * sin_psi, g.mu);
    const float v = SL_EVAL(N, L, V, N, mc).r;
#endif
    return pho_finite_or_zero(v);
}

// Every row: SL_FRAGS_PER_ITEM rows a work-item (common.cl's SL_FRAGMENT_LOOP).
__kernel void eval_photometric(__global const float* restrict mu0, __global const float* restrict mu,
                               __global const float* restrict sin_i, __global const float* restrict sin_e,
                               __global const float* restrict cos_g, __global const float* restrict tan_half_g,
                               __global const float* restrict tan_half_psi, __global float* restrict out, const uint n,
                               __constant const ModelConsts* mc_arg) {
    // No bounds check: the host pads every array to the launch size (a check here would put the constants' loads
    // under a condition, where PoCL's work-item loop cannot hoist them; kernels/shade.cl says more). `n` is unused.
    (void)n;
    SL_PRIVATE_CONSTS(mc, mc_arg);   // see common.cl's SL_CONSTS
    const size_t first = get_global_id(0) * SL_FRAGS_PER_ITEM;
    SL_FRAGMENT_LOOP
    for (uint k = 0; k < SL_FRAGS_PER_ITEM; ++k)
        out[first + k] = pho_row(first + k, mu0, mu, sin_i, sin_e, cos_g, tan_half_g, tan_half_psi, mc);
}

// ISIS's empirical laws with the phase-dependent parameter and brightness already interpolated per row (the host
// evaluates ISIS's spline of K(g) or L(g) and of B(g) in double):
//   law 1, MinnaertEmpirical:      B(g) mu0 (mu0 mu)^(K(g) - 1)
//   law 2, LunarLambertEmpirical:  B(g) mu0 ((1 - L(g)) + 2 L(g) / (mu0 + mu))
__kernel void eval_empirical(__global const float* restrict mu0, __global const float* restrict mu,
                             __global const float* restrict param, __global const float* restrict brightness,
                             __global float* restrict out, const uint n, const uint law) {
    const size_t i = get_global_id(0);
    if (i >= n) return;
    const float a = mu0[i], b = mu[i];
    const float v = law == 1u ? Pho_Minnaert(a, b, param[i]) : Pho_LunarLambert(a, b, param[i]);
    out[i] = pho_finite_or_zero(a > 0.0f && b > 0.0f ? brightness[i] * v : 0.0f);
}

// Many parameter sets at once (the fits of host/photometry/fit.hpp): work-item (w, s) evaluates rows
// w SL_FRAGS_PER_ITEM .. (w + 1) SL_FRAGS_PER_ITEM - 1 with the constants sets[s], row i into out[s * stride + i].
// The rows are uploaded once per fit; each launch carries the current parameters, their finite-difference
// neighbours and the trial steps. No bounds check (the host pads).
__kernel void eval_photometric_sets(__global const float* restrict mu0, __global const float* restrict mu,
                                    __global const float* restrict sin_i, __global const float* restrict sin_e,
                                    __global const float* restrict cos_g, __global const float* restrict tan_half_g,
                                    __global const float* restrict tan_half_psi, __global float* restrict out,
                                    const uint stride, __constant const ModelConsts* sets) {
    const size_t first = get_global_id(0) * SL_FRAGS_PER_ITEM, s = get_global_id(1);
    SL_PRIVATE_CONSTS(mc, sets + s);   // see common.cl's SL_CONSTS
    SL_FRAGMENT_LOOP
    for (uint k = 0; k < SL_FRAGS_PER_ITEM; ++k)
        out[s * (size_t)stride + first + k] =
            pho_row(first + k, mu0, mu, sin_i, sin_e, cos_g, tan_half_g, tan_half_psi, mc);
}
