// Planetary photometry: the disc-resolved laws of airless bodies as USGS ISIS3 defines them (its photometric
// models McEwen's Lunar-Lambert, Hapke with Henyey-Greenstein or Legendre phase functions; Lommel-Seeliger and
// Lunar-Lambert are their own family, kernels/models/lunar_lambert.cl, on this file's terms), written from the papers. docs/photometry.md has the formulas, the parameters in ISIS's
// names and shadelab's, the measured kernel-vs-reference errors and every difference from ISIS.
//
// Value convention (docs/notation.md): value = pi f_r NoL, a white Lambert surface lit head-on gives 1. That is
// the radiance factor I/F for unit solar flux, which is exactly what ISIS's photometric models return with
// albedo 1 (Lambert cos i; Hapke pi times Hapke's bidirectional reflectance r). `albedo` multiplies the value
// per channel; leave it at 1 for ISIS's numbers.
//
// Every model is written twice over the same terms: `<model>_pho(sl_pho g, consts)`, the law in photometric
// quantities (mu0, mu, the sines, the phase and the azimuth), and `<model>_eval(N, L, V, P, consts)`, the
// catalogue's entry point, which forms those quantities from the vectors. kernels/photometry.cl calls the
// `_pho` form straight from (phase, incidence, emission) triples, which need not be a consistent geometry
// (ISIS's own unit tests use phase > incidence + emission; the laws are defined on the three angles).
//
// Trigonometry: atan and exp are this file's own float polynomials (Pho_atan, Pho_exp), branch-free so that
// PoCL's loop vectoriser keeps 8 evaluations per instruction (its built-in exp/atan are calls it cannot widen:
// docs/precision.md). They can be switched to common.cl's vectorisable functions once those exist.
#ifndef SHADELAB_MODEL_PLANETARY_CL
#define SHADELAB_MODEL_PLANETARY_CL
#include "common.cl"
#include "consts/planetary.h"

#define PHO_PI 3.14159265358979323846f

// ---- photometric geometry -----------------------------------------------------------------------------
// mu0 = cos i, mu = cos e, sin i, sin e, cos g, tan(g/2) and tan(psi/2), psi the azimuth between the planes of
// incidence and emission (0 when either sine is 0, as ISIS). Half-angle tangents rather than cosines: they keep
// their digits at 0 and 180 degrees, where a float cosine within 6e-8 of +-1 leaves the angle uncertain by 3.5e-4
// rad (at theta-bar = 89 deg that moves Hapke's S(i, e, psi) by several percent near psi = 0).
// Padded past 16 bytes (common.cl says why).
typedef struct {
    float mu0, mu, sin_i, sin_e, cos_g, tan_half_g, tan_half_psi, pad_[2];
} sl_pho;

// The largest tan(g/2) used: at g = 180 deg tan is infinite, and 0 * inf (a zero 1/h) would be NaN.
#define PHO_TAN_MAX 1.0e18f

// From unit vectors. sin i = |N x L| (no cancellation near i = 0, where sqrt(1 - NoL^2) keeps no digit);
// tan(g/2) = |L - V| / |L + V| (exact for unit vectors, accurate at g -> 0 where acos(LoV) is not: float LoV
// is within 6e-8 of 1 for g < 3.5e-4 rad); tan(psi/2) = |u - v| / |u + v| for the unit directions u, v of N x L
// and N x V, formed as |a |b| - b |a|| / |a |b| + b |a|| with a = N x L, b = N x V (no normalisation, no
// cancellation).
SL_INLINE sl_pho Pho_from_vectors(sl_v3 N, sl_v3 L, sl_v3 V) {
    sl_pho g;
    // the V terms after the L terms, and tan(psi/2) after tan(g/2) (common.cl's sl_after): side by side they are
    // what LLVM's SLP vectoriser packs into <2 x float>, which stops PoCL's work-item loop vectoriser
    const sl_v3 nl = sl_cross(N, L);
    g.mu0 = sl_dot(N, L);
    g.sin_i = sl_length(nl);
    // (every component of V after a term of L: with only V.x after sin i, the two dot products N.L and N.V are still
    // packed into <2 x float> on AVX2 hosts, pthread-haswell)
    const sl_v3 Va = sl_v3_make(sl_after(V.x, g.sin_i), sl_after(V.y, g.mu0), sl_after(V.z, g.mu0));
    const sl_v3 nv = sl_cross(N, Va);
    g.mu = sl_dot(N, Va);
    g.sin_e = sl_length(nv);
    g.cos_g = sl_dot(L, Va);
    const sl_v3 d = sl_sub(L, Va), s = sl_add(L, Va);
    g.tan_half_g = fmin(sqrt(sl_dot(d, d) / sl_dot(s, s)), PHO_TAN_MAX);   // d/0 = inf, clamped (g = 180)
    const float sin_e_after = sl_after(g.sin_e, g.tan_half_g);   // tan(g/2) <= PHO_TAN_MAX: finite
    const sl_v3 pd = sl_sub(sl_scale(nl, sin_e_after), sl_scale(nv, g.sin_i));
    const sl_v3 ps = sl_add(sl_scale(nl, sin_e_after), sl_scale(nv, g.sin_i));
    const float t_psi = fmin(sqrt(sl_dot(pd, pd) / sl_dot(ps, ps)), PHO_TAN_MAX);
    g.tan_half_psi = g.sin_i * g.sin_e > 0.0f ? t_psi : 0.0f;   // no azimuth along N: psi = 0 (ISIS)
    return g;
}

// The geometry of the laws of mu0, mu and the phase angle only (Lommel-Seeliger, Lunar-Lambert, McEwen's laws,
// the empirical tables): mu0, mu, cos g and tan(g/2) as Pho_from_vectors forms them; sin i, sin e and tan(psi/2)
// are not formed (0). Pho_from_vectors ties V to sin i (|N x L|) to keep LLVM's SLP vectoriser from pairing the
// two dot products; here V is tied to mu0, so a law that needs no sine does not pay for the cross product and
// its square root.
SL_INLINE sl_pho Pho_from_vectors_phase(sl_v3 N, sl_v3 L, sl_v3 V) {
    sl_pho g;
    g.mu0 = sl_dot(N, L);
    const sl_v3 Va = sl_v3_make(sl_after(V.x, g.mu0), sl_after(V.y, g.mu0), sl_after(V.z, g.mu0));
    g.mu = sl_dot(N, Va);
    g.cos_g = sl_dot(L, Va);
    const sl_v3 d = sl_sub(L, Va), s = sl_add(L, Va);
    g.tan_half_g = fmin(sqrt(sl_dot(d, d) / sl_dot(s, s)), PHO_TAN_MAX);   // d/0 = inf, clamped (g = 180)
    g.sin_i = 0.0f;
    g.sin_e = 0.0f;
    g.tan_half_psi = 0.0f;
    return g;
}

// The surface is lit and seen: the laws are defined for mu0 > 0 and mu > 0 only, and return 0 elsewhere.
SL_INLINE int Pho_visible(sl_pho g) { return g.mu0 > 0.0f && g.mu > 0.0f; }

// ---- this file's vectorisable elementary functions -------------------------------------------------------

// atan(x) for x >= 0 (inf included). Range reduction to |z| <= tan(pi/8) (Cody & Waite; Cephes atanf):
//   x > tan(3pi/8): atan x = pi/2 + atan(-1/x);  x > tan(pi/8): atan x = pi/4 + atan((x - 1)/(x + 1)),
// then atan z = z + z^3 P(z^2) with Cephes' minimax coefficients (relative error ~1e-7 on [0, 0.4142]).
SL_INLINE float Pho_atan_poly(float z) {
    const float z2 = z * z;
    const float p = ((8.05374449538e-2f * z2 - 1.38776856032e-1f) * z2 + 1.99777106478e-1f) * z2 - 3.33329491539e-1f;
    return p * z2 * z + z;
}

// The reduction with one division: z is the quotient of a selected numerator and denominator (-1 / x,
// (x - 1) / (x + 1) or x / 1, the last exact), the same z as a select between the three quotients, which would
// compute both divisions in every lane. Returns atan z and sets *y0 (atan x = y0 + atan z).
SL_INLINE float Pho_atan_reduced(float x, float* y0) {
    const int big = x > 2.414213562373095f, mid = x > 0.4142135623730950f;
    const float num = big ? -1.0f : (mid ? x - 1.0f : x);
    const float den = big ? x : (mid ? x + 1.0f : 1.0f);
    *y0 = big ? 0.5f * PHO_PI : (mid ? 0.25f * PHO_PI : 0.0f);
    return Pho_atan_poly(num / den);
}
// (the one-division form against the select between quotients, bench_models 1M precise, two alternating rounds:
// lunar_lambert_mcewen 1.10-1.15x, lunar_lambert_mcewen_ratio 1.05-1.12x, the same values bit for bit)
SL_INLINE float Pho_atan(float x) {
    float y0;
    const float a = Pho_atan_reduced(x, &y0);
    return y0 + a;
}

// atan x and atan(1/x) = pi/2 - atan x for x >= 0 (inf included) from one reduction: with atan x = y0 + a,
// atan(1/x) = (pi/2 - y0) - a, where pi/2 - y0 is exactly 0 (x > tan(3pi/8): then atan(1/x) = -a, atan(1/x)'s
// own polynomial, no cancellation), pi/4 (|a| <= pi/8) or pi/2 (a <= pi/8): never a difference of near-equal
// numbers, so atan(1/x) keeps its relative accuracy as x -> inf.
SL_INLINE float Pho_atan_and_atan_inv(float x, float* atan_inv) {
    float y0;
    const float a = Pho_atan_reduced(x, &y0);
    *atan_inv = (0.5f * PHO_PI - y0) - a;
    return y0 + a;
}

// 2^t for t in [-126, 0] (PHO_EXP2_MIN: the laws only take exponentials of non-positive numbers, and the float
// range ends at 2^-126): t = k + f, k = rint(t) by the 1.5 * 2^23 shift (the sum's low bits are k in two's
// complement, so shifting them into the exponent field builds 2^k with no conversion), |f| <= 1/2, and 2^f - 1 =
// f Q(f), Q common.cl's sl_exp2_q (fitted for relative error on [-1/2, 1/2]). Returns 2^k and sets *fq = f Q(f),
// so that 2^t = 2^k (1 + fq) and 1 - 2^t = (1 - 2^k) - 2^k fq, which keeps its relative accuracy as t -> 0
// (k = 0: -fq, no cancellation).
#define PHO_EXP2_MIN (-126.0f)
SL_INLINE float Pho_exp2_parts(float t, float* fq) {
    const float shifted = t + 12582912.0f, k = shifted - 12582912.0f;
    const float f = t - k;
    *fq = f * sl_exp2_q(f);
    return as_float((as_uint(shifted) << 23) + 0x3f800000u);   // unsigned: the shift wraps by definition
}

// exp(x) for x <= 0 (-inf included): 2^(x / ln 2) by Pho_exp2_parts, and 0 below 2^-125 (x < -86.6): a
// result under 2^-126 would be a denormal, and a float operation that makes one costs an Intel core a microcode
// assist of some hundred cycles (E2 = exp(-k2 cot^2 x) falls below it wherever i or e is near 0; holding it at
// 2^-126 instead of 0 made the photometric kernels 0.80-0.86x as fast). Branch-free (PoCL's exp is a call its
// loop vectoriser cannot widen).
#define PHO_EXP2_FLOOR (-125.0f)
SL_INLINE float Pho_exp(float x) {
    const float t = x * 1.44269504088896341f;
    float fq;
    const float two_k = Pho_exp2_parts(fmax(t, PHO_EXP2_FLOOR), &fq);   // >= 2^-125.5: no denormal
    const float r = fma(two_k, fq, two_k);
    return t < PHO_EXP2_FLOOR ? 0.0f : r;
}

// The phase angle g in degrees, 2 atan(tan(g/2)) (well conditioned at 0 and 180).
SL_INLINE float Pho_phase_deg(sl_pho g) { return 2.0f * (180.0f / PHO_PI) * Pho_atan(g.tan_half_g); }

// 1 + cos g and 1 - cos g from t = tan(g/2): 2/(1 + t^2) and 2 t^2/(1 + t^2), each without the cancellation of
// 1 +- cos g near g = 180 / g = 0 (t = 0 gives 2 and 0; t = PHO_TAN_MAX gives 2e-36 and 2: t^2 stays finite).
// Both from one reciprocal; returns 1 + cos g and sets *one_minus.
SL_INLINE float Pho_one_pm_cos_g(float t, float* one_minus) {
    const float t2 = t * t, inv = 2.0f / (1.0f + t2);
    *one_minus = t2 * inv;
    return inv;
}

// ---- the simple laws ------------------------------------------------------------------------------------

// Lommel-Seeliger (Seeliger 1888; ISIS's LommelSeeliger): value = 2 mu0 / (mu0 + mu), 1 head-on.
SL_INLINE float Pho_LommelSeeliger(float mu0, float mu) { return 2.0f * mu0 / (mu0 + mu); }

// Lunar-Lambert (McEwen 1991, Icarus 92:298; ISIS's LunarLambert): value = mu0 ((1 - L) + 2 L / (mu0 + mu)):
// L = 0 Lambert, L = 1 Lommel-Seeliger (normalised to 1 head-on).
SL_INLINE float Pho_LunarLambert(float mu0, float mu, float L) { return mu0 * ((1.0f - L) + 2.0f * L / (mu0 + mu)); }

// McEwen's L(g) (McEwen 1996, LPSC 27:841, the lunar fit ISIS's LunarLambertMcEwen uses): a cubic in the phase
// angle in degrees, L(g) = 1 + M1 g + M2 g^2 + M3 g^3.
SL_INLINE float Pho_McEwen_L(float g_deg, float m1, float m2, float m3) {
    return 1.0f + g_deg * (m1 + g_deg * (m2 + g_deg * m3));
}

// Minnaert's law with each cosine's power held below eps (the guard of kernels/models/minnaert.cl, applied here
// to the empirical K(g) law, whose K may be < 1): mu0 (mu0 mu)^(K-1). eps = 1e-3 for K < 1, else no guard.
SL_INLINE float Pho_Minnaert(float mu0, float mu, float k) {
    const float eps = k < 1.0f ? 1.0e-3f : 0.0f;   // (the tapers multiply by 1/eps = 1000: mu0 < eps > 0 there)
    const float taper0 = mu0 < eps ? mu0 * 1.0e3f : 1.0f;
    // mu's half after mu0's (sl_after, on a finite dependence): side by side they are packed into <2 x float> on
    // AVX2 hosts (pthread-haswell), which stops the work-item loop vectoriser
    const float mu_after = sl_after(mu, fmin(fabs(taper0), 1.0f));
    const float taper = taper0 * (mu_after < eps ? mu_after * 1.0e3f : 1.0f);
    return mu0 * pow_nonneg(fmax(mu0, eps) * fmax(mu_after, eps), k - 1.0f) * taper;
}

// ---- Hapke's terms (Hapke 1981 JGR 86:3039; 1984 Icarus 59:41; 1986 Icarus 67:264; Hapke 1993, ch. 8-12) ----

// Hapke's (1981) approximation to Chandrasekhar's H function, H(x) = (1 + 2x) / (1 + 2x gamma),
// gamma = sqrt(1 - w) (exact for isotropic scatterers at w = 0 and w = 1, within 4% between), as its numerator
// and denominator (the smooth law divides once for both H and its own quotient).
SL_INLINE float Hapke_H_num(float x) { return 1.0f + 2.0f * x; }
SL_INLINE float Hapke_H_den(float x, float gamma) { return 1.0f + 2.0f * x * gamma; }

// Shadow-hiding opposition surge (Hapke 1986): B(g) = B0 / (1 + tan(g/2) / h). The host passes B0 = 0 and
// 1/h = 0 for h = 0 (ISIS: no surge without a width), so t <= PHO_TAN_MAX keeps 0 * t finite.
SL_INLINE float Hapke_B(float t, float b0, float inv_h) { return b0 / (1.0f + t * inv_h); }

// The denominator of a Henyey-Greenstein lobe (1 - b^2) / (1 + b^2 +- 2 b cos g)^(3/2) in the phase angle g,
// d^(3/2) = d sqrt(d). d is formed as (1 - |b|)^2 + 2 |b| (1 -+ cos g), a sum of non-negative terms, so that it
// keeps its digits where it is smallest (|b| -> 1 near g = 0 or 180), instead of 1 + b^2 - 2b cos g, which
// cancels there. `one_pm_cos` is 1 + cos g or 1 - cos g, whichever the lobe and sign of b call for.
SL_INLINE float Hapke_HG_lobe_den(float a, float two_abs_b, float one_pm_cos) {
    const float d = a + two_abs_b * one_pm_cos;
    return d * sqrt(d);
}

// ISIS's two-term Henyey-Greenstein phase function (HapkeHen):
//   P(g) = (1 - c) (1 - b^2) / (1 + b^2 + 2 b cos g)^(3/2) + c (1 - b^2) / (1 + b^2 - 2 b cos g)^(3/2),
// b = Hg1, c = Hg2. HapkeHG2Consts: a = (1 - |b|)^2, two_abs_b = 2|b|, b_positive = 1 if b >= 0, 1 - b^2, c, 1 - c.
// The two lobes over one division, (1 - b^2) ((1 - c) D2 + c D1) / (D1 D2) with D1, D2 their denominators
// (each in [(1 - |b|)^3, (1 + |b|)^3], at least 1e-12 for |b| <= 0.9999: the product cannot underflow).
SL_INLINE float Hapke_P_HG2(float t, const HapkeHG2Consts* hg) {
    const float a = hg->a, two_abs_b = hg->two_abs_b, b_pos_flag = hg->b_positive, one_minus_b2 = hg->one_minus_b2;
    const float c = hg->c, one_minus_c = hg->one_minus_c;
    float omc;
    const float opc = Pho_one_pm_cos_g(t, &omc);
    const int b_pos = b_pos_flag != 0.0f;
    const float d1 = Hapke_HG_lobe_den(a, two_abs_b, b_pos ? opc : omc);   // + 2 b cos g
    // the second lobe after the first (common.cl's sl_after): two isomorphic lobes are what LLVM's SLP
    // vectoriser packs into <2 x float>, which stops the work-item loop vectoriser
    const float d2 = Hapke_HG_lobe_den(a, two_abs_b, sl_after(b_pos ? omc : opc, fmin(d1, 1.0f)));   // - 2 b cos g
    return one_minus_b2 * (one_minus_c * d2 + c * d1) / (d1 * d2);
}

// Hapke's (1981) Legendre phase function (HapkeLeg): P(g) = 1 + b cos g + c (3 cos^2 g - 1) / 2.
SL_INLINE float Hapke_P_Legendre(float cos_g, float b, float c) {
    return 1.0f + b * cos_g + c * (1.5f * cos_g * cos_g - 0.5f);
}

// The smooth-surface bidirectional reflectance times pi (Hapke 1981, 1986), in the (effective) cosines:
//   pi r = (w / 4) mu0 / (mu0 + mu) [(1 + B(g)) P(g) - 1 + H(mu0) H(mu)]
// With H(mu0) H(mu) = Hn / Hd, the bracket is (((1 + B) P - 1) Hd + Hn) / Hd, and the law one quotient:
// (w / 4) mu0 (((1 + B) P - 1) Hd + Hn) / ((mu0 + mu) Hd), Hd in [1, 9] (divisions are what this kernel waits on:
// docs/photometry.md, Speed).
SL_INLINE float Hapke_smooth(float mu0, float mu, float w_over_4, float gamma, float B, float P) {
    const float Hn = Hapke_H_num(mu0) * Hapke_H_num(mu), Hd = Hapke_H_den(mu0, gamma) * Hapke_H_den(mu, gamma);
    return w_over_4 * mu0 * (((1.0f + B) * P - 1.0f) * Hd + Hn) / ((mu0 + mu) * Hd);
}

// E1(x) = exp(-(2/pi) cot(theta) cot x) and E2(x) = exp(-(1/pi) cot^2(theta) cot^2 x) (Hapke 1984, eqs. 45-46).
// The host passes (2/pi) cot(theta) and (1/pi) cot^2(theta), capped at 1e15 and 1e30 (theta -> 0: the terms are
// 0 already; the cap keeps cot^2 finite in float, where inf * 0 at cot x = 0 would be NaN). E1 is used as
// 1 - E1 (Pho_one_minus_exp_neg, in Hapke_rough).
SL_INLINE float Hapke_E2(float cot_x, float k2) { return Pho_exp(-k2 * cot_x * cot_x); }

// mu_e(0) of a direction at angle x (Hapke 1984, eqs. 48-49):  chi (cos x + sin x tan(theta) E2(x) / (2 - E1(x))),
// chi = 1 / sqrt(1 + pi tan^2(theta)), here without its factor chi (Hapke_roughness forms S from eta / chi, which
// keeps its scale where chi is tiny: theta-bar -> 90 deg). `e2_over` is E2(x) / (2 - E1(x)) (Hapke_roughness
// forms both directions' quotients with one division).
SL_INLINE float Hapke_eta_over_chi(float cos_x, float sin_x, float e2_over, float tan_t) {
    return cos_x + sin_x * tan_t * e2_over;
}

// 1 - exp(-x) for x >= 0 (+inf included) without the cancellation of 1 - Pho_exp(-x) at small x (theta-bar ->
// 90 deg makes every E1 -> 1): (1 - 2^k) - 2^k f Q(f) from Pho_exp2_parts, at x -> 0 the polynomial's own
// relative accuracy, and no branch between a series and the exponential.
SL_INLINE float Pho_one_minus_exp_neg(float x) {
    float fq;
    const float two_k = Pho_exp2_parts(fmax(-x * 1.44269504088896341f, PHO_EXP2_MIN), &fq);
    return fma(-two_k, fq, 1.0f - two_k);
}

// Hapke (1984) macroscopic roughness: the effective cosines mu0e, mue and the shadowing function S(i, e, psi)
// (eqs. 46-51, the i <= e and i > e cases), ISIS's formulation; the law is the smooth one at mu0e, mue times S.
// Returns S (0 where both effective cosines are 0) and sets *mu0e, *mue.
// HapkeConsts: chi, tan_t = tan(theta), k1 = (2/pi) cot(theta), k2 = (1/pi) cot^2(theta).
// Float care: the denominators 2 - E1(e) - (psi/pi) E1(i) are formed as the sum of the non-negative terms
// (1 - E1(e)) + (1 - psi/pi) + (psi/pi)(1 - E1(i)), with 1 - psi/pi = (2/pi) atan(1/tan(psi/2)): written as the
// paper has them they cancel to nothing (and change sign in float) where theta-bar -> 90 deg and psi -> 180 deg.
// The effective cosines are floored at 0 (they are cosines; at theta-bar -> 90 deg the float sum of a cosine and
// a large tan(theta) term can round below 0), and the law is 0 where both are 0.
SL_INLINE float Hapke_roughness(sl_pho g, float chi, float tan_t, float k1, float k2, float* mu0e_out, float* mue_out) {
    // cot i, cot e with ISIS's floor of 1e-10 on the sine (i or e = 0: cot is huge, E1 = E2 = 0)
    // Every term of e is computed after the same term of i, and E2 after E1 (common.cl's sl_after): the two
    // chains are isomorphic, and LLVM's SLP vectoriser would otherwise pack them into <2 x float>, which stops
    // PoCL's work-item loop vectoriser (the kernel then runs one geometry at a time: docs/photometry.md, Speed).
    // Both cotangents from one division, mu0 s_e / (s_i s_e) and mu s_i / (s_i s_e), s the floored sines (their
    // product is at least 1e-20, a normal float); and both E2 / (2 - E1) from one, by (1 + (1 - E1(i))) (1 + (1 -
    // E1(e))), in [1, 4]. Each product's second factor after its first (sl_after): a product of two isomorphic
    // terms is a reduction the SLP vectoriser packs.
    const float s_i = fmax(g.sin_i, 1.0e-10f), s_e = fmax(sl_after(g.sin_e, s_i), 1.0e-10f);
    const float inv_sines = 1.0f / (s_i * s_e);
    const float cot_i = g.mu0 * s_e * inv_sines;
    const float om1i = Pho_one_minus_exp_neg(k1 * cot_i);   // 1 - E1(i)
    const float e2i = Hapke_E2(sl_after(cot_i, om1i), k2);
    const float cot_e = sl_after(g.mu, e2i) * s_i * inv_sines;
    const float om1e = Pho_one_minus_exp_neg(k1 * cot_e);   // 1 - E1(e)
    const float e2e = Hapke_E2(sl_after(cot_e, om1e), k2);
    const float den_i = 1.0f + om1i, den_e = 1.0f + sl_after(om1e, den_i);   // 2 - E1(i), 2 - E1(e)
    // the azimuth psi from t = tan(psi/2): cos psi, sin^2(psi/2), psi / pi, 1 - psi / pi, f(psi)
    const float tan_half_psi = g.tan_half_psi, t2 = tan_half_psi * tan_half_psi;
    const float inv_1pt2 = 1.0f / (1.0f + t2);
    const float c = (1.0f - t2) * inv_1pt2;
    const float sin2_half_psi = t2 * inv_1pt2;
    float atan_inv;   // atan(1 / tan(psi/2)): psi = 0 gives pi/2, so 1 - psi/pi = 1
    const float psi_over_pi = (2.0f / PHO_PI) * Pho_atan_and_atan_inv(tan_half_psi, &atan_inv);
    const float one_minus_psi_over_pi = (2.0f / PHO_PI) * atan_inv;
    // f(psi) = exp(-2 tan(psi/2)) (Hapke 1984, eq. 50), used as 1 - f: at grazing with a large theta-bar, S
    // depends on 1 - f ~ psi against q ~ chi mu0 / eta_i, both tiny; 1 - Pho_exp(.) would round 1 - f to 0 for
    // psi < 6e-8 rad
    const float one_minus_f = Pho_one_minus_exp_neg(2.0f * tan_half_psi);
    // i <= e and i > e: eqs. 46-47 and 50-51; both are formed and one selected (no branch). i <= e is mu0 > mu,
    // or sin i <= sin e where the float cosines are equal (near i = e = 0, cos rounds to 1 for both)
    // The two cases differ in which of E1(i), E1(e) and E2(i), E2(e) take which place: the case's terms are
    // selected first, and the cosines formed once, with one division (both cases formed and one selected took two).
    const int i_le_e = g.mu0 > g.mu || (g.mu0 == g.mu && g.sin_i <= g.sin_e);
    const float om1_near = i_le_e ? om1e : om1i, om1_far = i_le_e ? om1i : om1e;   // 1 - E1 of e, i (i <= e)
    const float e2_near = i_le_e ? e2e : e2i, e2_far = i_le_e ? e2i : e2e;         // E2 of e, i (i <= e)
    const float den = om1_near + one_minus_psi_over_pi + psi_over_pi * om1_far;   // 2 - E1(e) - (psi/pi) E1(i)
    // one division for 1 / den (den >= 2e-18 / pi: tan(psi/2) <= PHO_TAN_MAX) and 1 / ((2 - E1(i)) (2 - E1(e))),
    // the latter in [1/4, 1]: their product cannot overflow or underflow
    const float inv_all = 1.0f / (den * (den_i * den_e));
    const float tan_t_over_den = tan_t * (den_i * den_e) * inv_all, inv_dens = den * inv_all;
    const float eta_i = Hapke_eta_over_chi(g.mu0, g.sin_i, e2i * den_e * inv_dens, tan_t);   // eta(i) / chi
    const float eta_e = Hapke_eta_over_chi(g.mu, g.sin_e, e2e * sl_after(den_i, eta_i) * inv_dens, tan_t);
    // i <= e: mu0e takes cos psi E2(e) + sin^2(psi/2) E2(i), mue E2(e) - sin^2(psi/2) E2(i); i > e the other way
    const float sum = c * e2_near + sin2_half_psi * e2_far, diff = e2_near - sin2_half_psi * e2_far;
    const float mu0e = fmax(chi * (g.mu0 + g.sin_i * tan_t_over_den * (i_le_e ? sum : diff)), 0.0f);
    // mue after mu0e (sl_after, with a finite dependence: fmin(NaN or Inf, 1) is a number): the two floors side by
    // side are packed into <2 x float> on AVX2 hosts (pthread-haswell), which stops the work-item loop vectoriser
    const float mue_over_chi = fmax(sl_after(g.mu + g.sin_e * tan_t_over_den * (i_le_e ? diff : sum), fmin(mu0e, 1.0f)), 0.0f);
    const float mue = chi * mue_over_chi;
    // S = (mue / eta_e) (mu0 / eta_i) chi / (1 - f + f q),  q = chi mu0 / eta_i (i <= e) or chi mu / eta_e (i > e):
    // as one quotient, with eta_sel the eta of q and eta_other the other one,
    //   S = mue mu0 chi / (eta_other ((1 - f) eta_sel + f chi mu_sel)),
    // formed from eta / chi and mue / chi (chi cancels): the denominator is at least mu0 mu (eta / chi >= the
    // cosine), so it keeps its scale at theta-bar -> 90 deg, where chi -> 0 (chi^2 mu0 mu would underflow)
    const float eta_sel = i_le_e ? eta_i : eta_e, eta_other = i_le_e ? eta_e : eta_i, mu_sel = i_le_e ? g.mu0 : g.mu;
    const float S = mue_over_chi * g.mu0 / (eta_other * (one_minus_f * eta_sel + (1.0f - one_minus_f) * mu_sel));
    const int some = mu0e + mue > 0.0f;
    *mu0e_out = some ? mu0e : 1.0f;   // any positive pair: the law is multiplied by S = 0 there
    *mue_out = some ? mue : 1.0f;
    return some ? S : 0.0f;
}

// Hapke's model with either phase function (HapkeConsts): w_over_4 = w/4, gamma = sqrt(1 - w), b0 = B0 (0 if
// h = 0), inv_h = 1/h (0 if h = 0), rough = 1 for a rough surface (theta > 0), else the smooth law (ISIS: theta <= 0).
// Every constant is read before any choice is made: a load under a condition is one PoCL's vectorised work-item
// loop cannot hoist (kernels/shade.cl), and both laws are formed and one selected.
SL_INLINE float Hapke_value(sl_pho g, float P, const HapkeConsts* k) {
    const float w_over_4 = k->w_over_4, gamma = k->gamma, b0 = k->b0, inv_h = k->inv_h, rough_flag = k->rough;
    const float chi = k->chi, tan_t = k->tan_t, k1 = k->k1, k2 = k->k2;
    const float B = Hapke_B(g.tan_half_g, b0, inv_h);
    float mu0e, mue;
    const float S = Hapke_roughness(g, chi, tan_t, k1, k2, &mu0e, &mue);
    // the smooth law at (mu0e, mue) times S, or at (mu0, mu) times 1: one evaluation of it at the selected cosines
    const int rough = rough_flag != 0.0f;
    return Hapke_smooth(rough ? mu0e : g.mu0, rough ? mue : g.mu, w_over_4, gamma, B, P) * (rough ? S : 1.0f);
}

// ---- Hapke's 2002/2012 refinements (the variant hapke_2012) ----------------------------------------------------

// ln(n / d) for normal floats n, d > 0, with one division: n = 2^a m_n and d = 2^b m_d with m_n, m_d in [1, 2);
// m_n halved (a + 1) or doubled (a - 1) so that r = m_n / m_d is in [sqrt(1/2), sqrt(2)); then ln(n / d) =
// (a - b) ln 2 + 2 atanh(s), s = (r - 1)/(r + 1) = (m_n - m_d)/(m_n + m_d) (the difference exact: Sterbenz),
// |s| <= 0.1716, 2 atanh(s) = 2 (s + s^3/3 + ... + s^9/9) (first omitted term s^11/11 < 2e-9 of the sum;
// Abramowitz & Stegun 4.1.27). Forming n / d first and then its logarithm took two divisions.
// This file's own, branch-free (PoCL's log is a call the vectoriser cannot widen).
SL_INLINE float Pho_log_ratio(float n, float d) {
    const int nb = as_int(n), db = as_int(d);
    const float mn0 = as_float((nb & 0x007fffff) | 0x3f800000), md = as_float((db & 0x007fffff) | 0x3f800000);
    const int up = mn0 > 1.41421356f * md, down = 1.41421356f * mn0 < md;
    const float mn = up ? 0.5f * mn0 : (down ? 2.0f * mn0 : mn0);
    const float k = (float)(((nb >> 23) - (db >> 23)) + up - down);
    const float s = (mn - md) / (mn + md), s2 = s * s;
    const float p = 1.0f + s2 * (1.0f / 3.0f + s2 * (0.2f + s2 * (1.0f / 7.0f + s2 * (1.0f / 9.0f))));
    return k * 0.693147180559945309f + 2.0f * s * p;
}

// Hapke's (2002, Icarus 157:523, eq. 13) better H approximation (within 1% of Chandrasekhar's H for all w, x):
//   H(x) = 1 / (1 - w x [r0 + (1 - 2 r0 x)/2 ln((1 + x)/x)]),  r0 = (1 - gamma)/(1 + gamma), gamma = sqrt(1 - w).
// Hapke_H2002_den is the denominator 1 / H(x) (in (0, 1] for w in [0, 1]; the smooth law divides once by the
// product of two). x ln((1 + x)/x) -> 0 as x -> 0 (H(0) = 1); below x = 1e-30 the term is taken as 0 (its limit).
SL_INLINE float Hapke_H2002_den(float x, float w, float r0) {
    const float xl = x > 1.0e-30f ? x * Pho_log_ratio(1.0f + x, fmax(x, 1.0e-30f)) : 0.0f;
    return 1.0f - w * (x * r0 + 0.5f * (1.0f - 2.0f * r0 * x) * xl);
}

// Coherent-backscatter opposition effect (Hapke 2002, eq. 32; Hapke 2012, eq. 9.43):
//   B_C(g) = (1 + (1 - exp(-z))/z) / (2 (1 + z)^2),  z = tan(g/2)/h_C;  B_C(0) = 1. inv_hc = 1/h_C (0: none).
SL_INLINE float Hapke_BC(float t, float bc0, float inv_hc) {
    const float z = t * inv_hc;
    // (1 + (1 - e^-z)/z) / d, d = 2 (1 + z)^2, as one quotient: (z + 1 - e^-z) / (z d) for z > 1e-4, and with
    // (1 - e^-z)/z -> 1 - z/2 as z -> 0, (2 - z/2) / d below (a select between quotients would divide twice)
    const float d = 2.0f * (1.0f + z) * (1.0f + z);
    const int big = z > 1.0e-4f;
    const float num = big ? z + Pho_one_minus_exp_neg(z) : 2.0f - 0.5f * z;
    return bc0 * num / (big ? z * d : d);
}

// The porosity-corrected smooth law (Hapke 2008, Icarus 195:918; Hapke 2012, eq. 12.55 without roughness):
//   pi r = K (w/4) mu0/(mu0 + mu) [P(g) (1 + B_SH(g)) + H(mu0/K) H(mu/K) - 1] (1 + B_CB(g)),
// H the 2002 approximation, K = -ln(1 - 1.209 phi^(2/3)) / (1.209 phi^(2/3)) the porosity factor (host).
// With D = 1 / (H(mu0/K) H(mu/K)) in (0, 1], the bracket is ((P (1 + B_SH) - 1) D + 1) / D: one division by
// (mu0 + mu) D for both quotients.
SL_INLINE float Hapke2012_smooth(float mu0, float mu, float w, float r0, float K, float B_SH, float B_CB, float P) {
    const float inv_K = 1.0f / K;
    const float D0 = Hapke_H2002_den(mu0 * inv_K, w, r0);   // 1 / H(mu0 / K)
    const float D = D0 * Hapke_H2002_den(sl_after(mu, D0) * inv_K, w, r0);   // 1 / (H H); mu's after mu0's (sl_after)
    return K * 0.25f * w * mu0 * ((P * (1.0f + B_SH) - 1.0f) * D + 1.0f) / ((mu0 + mu) * D) * (1.0f + B_CB);
}

// ---- models, in photometric quantities (value for albedo 1; 0 where not lit or not seen) -------------------
// (lommel_seeliger and lunar_lambert, which use this file's geometry and terms, are their own family:
// kernels/models/lunar_lambert.cl.)

// lunar_lambert_mcewen: Lunar-Lambert with McEwen's L(g). McEwenConsts: m1, m2, m3.
SL_INLINE float lunar_lambert_mcewen_pho(sl_pho g, const ModelConsts* mc) {
    const McEwenConsts* k = SL_CONSTS(McEwenConsts, mc);
    const float L = Pho_McEwen_L(Pho_phase_deg(g), k->m1, k->m2, k->m3);
    return Pho_visible(g) ? Pho_LunarLambert(g.mu0, g.mu, L) : 0.0f;
}

// lunar_lambert_mcewen_ratio: what ISIS's LunarLambertMcEwen returns, the normalising ratio
//   R30 / r(g, i, e),  r = Lunar-Lambert with L(g),  R30 = r(30, 30, 0) (McEwenConsts.r30, computed on the
// host); 0 where r <= 0 (ISIS). r is floored at 1e-3 (r_floor), capping the ratio at 1000 R30 (ISIS divides by r as it
// is, and the ratio grows without bound at the terminator); the floor acts where mu0 < ~1e-3 (i > 89.94 deg) or
// where McEwen's L(g) < 0 brings r itself near 0.
SL_INLINE float lunar_lambert_mcewen_ratio_pho(sl_pho g, const ModelConsts* mc) {
    const McEwenConsts* k = SL_CONSTS(McEwenConsts, mc);
    const float r30 = k->r30, r_floor = k->r_floor;
    const float L = Pho_McEwen_L(Pho_phase_deg(g), k->m1, k->m2, k->m3);
    const float r = Pho_LunarLambert(g.mu0, g.mu, L);
    return Pho_visible(g) && r > 0.0f ? r30 / fmax(r, r_floor) : 0.0f;
}

// hapke_hen: Hapke with the two-term Henyey-Greenstein phase function (ISIS HapkeHen).
SL_INLINE float hapke_hen_pho(sl_pho g, const ModelConsts* mc) {
    const HapkeConsts* k = SL_CONSTS(HapkeConsts, mc);
    const float v = Hapke_value(g, Hapke_P_HG2(g.tan_half_g, &k->phase.hg2), k);
    return Pho_visible(g) ? v : 0.0f;
}

// hapke_leg: Hapke with the Legendre phase function (ISIS HapkeLeg). HapkeConsts.phase.legendre: b (Bh), c (Ch).
SL_INLINE float hapke_leg_pho(sl_pho g, const ModelConsts* mc) {
    const HapkeConsts* k = SL_CONSTS(HapkeConsts, mc);
    const float bh = k->phase.legendre.b, ch = k->phase.legendre.c;
    const float v = Hapke_value(g, Hapke_P_Legendre(g.cos_g, bh, ch), k);
    return Pho_visible(g) ? v : 0.0f;
}

// hapke_2012: Hapke's 2002/2012 refinements - the 2002 H function, porosity K, coherent backscatter - with the
// 1986 shadow-hiding surge, the 1984 roughness and ISIS's two-term Henyey-Greenstein P(g) (phase.hg2 as hapke_hen).
// HapkeConsts: w_over_4 unused (w is read), b0 .. k2 as hapke_hen, w, r0, K, bc0 = B_C0, inv_hc = 1/h_C (0: no
// coherent backscatter).
SL_INLINE float hapke_2012_pho(sl_pho g, const ModelConsts* mc) {
    const HapkeConsts* k = SL_CONSTS(HapkeConsts, mc);
    const float b0 = k->b0, inv_h = k->inv_h, rough_flag = k->rough;
    const float chi = k->chi, tan_t = k->tan_t, k1 = k->k1, k2 = k->k2;
    const float w = k->w, r0 = k->r0, K = k->K, bc0 = k->bc0, inv_hc = k->inv_hc;
    const float P = Hapke_P_HG2(g.tan_half_g, &k->phase.hg2);
    const float B_SH = Hapke_B(g.tan_half_g, b0, inv_h), B_CB = Hapke_BC(g.tan_half_g, bc0, inv_hc);
    float mu0e, mue;
    const float S = Hapke_roughness(g, chi, tan_t, k1, k2, &mu0e, &mue);
    const int rough = rough_flag != 0.0f;   // one evaluation at the selected cosines, as Hapke_value
    const float v =
        Hapke2012_smooth(rough ? mu0e : g.mu0, rough ? mue : g.mu, w, r0, K, B_SH, B_CB, P) * (rough ? S : 1.0f);
    return Pho_visible(g) ? v : 0.0f;
}

// ---- the catalogue's entry points: value = albedo * law(photometric quantities of N, L, V) --------------------
// (PHO_CATALOGUE_EVAL_WITH names the geometry: Pho_from_vectors_phase for the laws of mu0, mu and g only.)
#define PHO_CATALOGUE_EVAL_WITH(model, geometry)                                                              \
    SL_INLINE sl_rgb model##_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {     \
        (void)P;                                                                                              \
        return sl_albedo_times(mc, model##_pho(geometry(N, L, V), mc));                                        \
    }
#define PHO_CATALOGUE_EVAL(model) PHO_CATALOGUE_EVAL_WITH(model, Pho_from_vectors)
PHO_CATALOGUE_EVAL_WITH(lunar_lambert_mcewen, Pho_from_vectors_phase)
PHO_CATALOGUE_EVAL_WITH(lunar_lambert_mcewen_ratio, Pho_from_vectors_phase)
PHO_CATALOGUE_EVAL(hapke_hen)
PHO_CATALOGUE_EVAL(hapke_leg)
PHO_CATALOGUE_EVAL(hapke_2012)

#endif
