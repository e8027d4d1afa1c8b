// ISIS's empirical photometric laws as catalogue models: Minnaert and Lunar-Lambert with the phase-dependent
// parameter K(g) or L(g) and the phase curve B(g) given as tables over the phase angle (ISIS3's MinnaertEmpirical
// and LunarLambertEmpirical; McEwen 1991, Icarus 92:298, for the Lunar-Lambert L(g) these tables sample),
// interpolated by ISIS's natural cubic spline and continued by the end intervals' cubics outside the table.
// docs/models/empirical.md has the formulas, the sources and the measured errors.
//
//   minnaert_empirical       albedo * B(g) mu0 (mu0 mu)^(K(g) - 1)           with the catalogue's limb guard
//   lunar_lambert_empirical  albedo * B(g) mu0 ((1 - L(g)) + 2 L(g) / (mu0 + mu))
//
// g = 2 atan(|L - V| / |L + V|) in degrees per fragment (planetary.cl's Pho_phase_deg). Both are 0 where the
// surface is not lit or not seen (mu0 <= 0 or mu <= 0). The splines come per material in the table buffer `tab`
// (kernels/consts/empirical.h): these models' eval functions take it as a sixth argument (the registration marks
// them as table models, and kernels/shade.cl passes `tab` to them).
#ifndef SHADELAB_MODEL_EMPIRICAL_CL
#define SHADELAB_MODEL_EMPIRICAL_CL
#include "common.cl"
#include "consts/empirical.h"
#include "planetary.cl"

// The segments scanned: the program is built for a bucket of knot counts (SL_TABLE_KNOTS, host/shade/shader.cpp:
// 4, 8, 16 or 32), so a 7-knot table scans 7 segment starts, not 31; the unused ones start beyond every phase.
#if defined(SL_TABLE_KNOTS) && SL_TABLE_KNOTS < SL_EMP_MAX_KNOTS
#define SL_EMP_SCAN (SL_TABLE_KNOTS - 1)
#else
#define SL_EMP_SCAN SL_EMP_MAX_SEGMENTS
#endif

// K(g) or L(g) (*param) and B(g) (*bright) at phase g (degrees) from the segments in `tab`. The segment is found
// by a scan of fixed length over every segment start, each step a compare and selects (no data-dependent loop,
// no indexed load: either would stop PoCL's work-item loop vectoriser, and every load here is the same for all
// fragments, so it is hoisted out of the loop). The last start <= g wins; below the first knot segment 0, beyond
// the last the last segment (unused segments start at SL_EMP_UNUSED): the end cubics continued, as ISIS, except
// that B(g) is held at 0 where its continued cubic falls below 0.
SL_INLINE void Emp_splines(float g, __global const float* restrict tab, float* param, float* bright) {
    __global const EmpiricalSegment* seg = (__global const EmpiricalSegment*)tab;
    float x = seg[0].start, p0 = seg[0].param[0], p1 = seg[0].param[1], p2 = seg[0].param[2], p3 = seg[0].param[3];
    float b0 = seg[0].bright[0], b1 = seg[0].bright[1], b2 = seg[0].bright[2], b3 = seg[0].bright[3];
#pragma unroll
    for (int j = 1; j < SL_EMP_SCAN; ++j) {
        // every value loaded before the choice: a load inside `in ? load : x` is conditional code, which cannot be
        // hoisted out of the work-item loop
        const float sj = seg[j].start, q0 = seg[j].param[0], q1 = seg[j].param[1], q2 = seg[j].param[2];
        const float q3 = seg[j].param[3], c0 = seg[j].bright[0], c1 = seg[j].bright[1], c2 = seg[j].bright[2];
        const float c3 = seg[j].bright[3];
        const int in = g >= sj;
        x = in ? sj : x;
        p0 = in ? q0 : p0;
        p1 = in ? q1 : p1;
        p2 = in ? q2 : p2;
        p3 = in ? q3 : p3;
        b0 = in ? c0 : b0;
        b1 = in ? c1 : b1;
        b2 = in ? c2 : b2;
        b3 = in ? c3 : b3;
    }
    const float t = g - x;
    *param = fma(t, fma(t, fma(t, p3, p2), p1), p0);
    // after the first cubic (common.cl's sl_after): the two side by side are what LLVM's SLP vectoriser packs
    // into <2 x float>, which stops the loop vectoriser
    const float ta = sl_after(t, *param);
    // a phase curve continued below 0 beyond its table is held at 0 (a brightness is not negative; ISIS does not)
    *bright = fmax(fma(ta, fma(ta, fma(ta, b3, b2), b1), b0), 0.0f);
}

// minnaert_empirical: B(g) mu0 (mu0 mu)^(K(g) - 1) (planetary.cl's Pho_Minnaert: the 1941 law with the catalogue's
// limb guard, held below 1e-3 in either cosine for K < 1).
SL_INLINE float minnaert_empirical_pho(sl_pho g, __global const float* restrict tab) {
    float K, B;
    Emp_splines(Pho_phase_deg(g), tab, &K, &B);
    return Pho_visible(g) ? B * Pho_Minnaert(g.mu0, g.mu, K) : 0.0f;
}

// lunar_lambert_empirical: B(g) mu0 ((1 - L(g)) + 2 L(g) / (mu0 + mu)) (planetary.cl's Pho_LunarLambert).
SL_INLINE float lunar_lambert_empirical_pho(sl_pho g, __global const float* restrict tab) {
    float L, B;
    Emp_splines(Pho_phase_deg(g), tab, &L, &B);
    return Pho_visible(g) ? B * Pho_LunarLambert(g.mu0, g.mu, L) : 0.0f;
}

// The catalogue's entry points, with the table: value = albedo * law(photometric quantities of N, L, V).
#define EMP_CATALOGUE_EVAL(model)                                                                              \
    SL_INLINE sl_rgb model##_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc,       \
                                  __global const float* restrict tab) {                                       \
        (void)P;                                                                                               \
        return sl_albedo_times(mc, model##_pho(Pho_from_vectors_phase(N, L, V), tab));                               \
    }
EMP_CATALOGUE_EVAL(minnaert_empirical)
EMP_CATALOGUE_EVAL(lunar_lambert_empirical)

#endif
