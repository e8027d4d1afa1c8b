// Gradient shader (seed 004, "Gradient Shader"): a cosine wave along a world-space direction blends two
// other models. With g the unit gradient direction, period T and phase phi:
//   t = 0.5 + 0.5 cos(2 pi (P . g) / T + phi)            (the cosine mapped from [-1, 1] to [0, 1])
//   value = (1 - t) value_A + t value_B                   (alpha blending of shader A and shader B)
// The children's headers and eval functions come from SL_CHILD0_HEADER / SL_CHILD0_EVAL (A) and SL_CHILD1_*
// (B); their constants are at mc + 1 and mc + 2. Constants: GradientConsts (gx, gy, gz = g, unit, from the host;
// wavenumber = 2 pi / T; phase = phi). Leaves out: nothing of its own (the children carry the cosine and the 1/pi convention).
// Precision: the phase 2 pi (P . g) / T + phi is formed in float, so its absolute error is a few 6e-8 times
// its size: 1e-6 rad at 2 pi |P . g| / T = 10, 0.06 rad at 1e6 (a period of 1e-4 at |P| = 10). The weight t
// moves by at most half that; the children's own precision is theirs.
#ifndef SHADELAB_MODEL_GRADIENT_CL
#define SHADELAB_MODEL_GRADIENT_CL
#include "common.cl"
#include "consts/gradient.h"
#include SL_CHILD0_HEADER
#include SL_CHILD1_HEADER

SL_INLINE float Gradient_Weight(sl_v3 P, const ModelConsts* mc) {
    const GradientConsts* k = SL_CONSTS(GradientConsts, mc);
    const sl_v3 g = sl_v3_make(k->gx, k->gy, k->gz);
    return 0.5f + 0.5f * cos(sl_dot(P, g) * k->wavenumber + k->phase);
}

SL_INLINE sl_rgb gradient_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    const float t = Gradient_Weight(P, mc);
    return sl_rgb_mix(SL_CHILD0_EVAL(N, L, V, P, mc + 1), SL_CHILD1_EVAL(N, L, V, P, mc + 2), t);
}
#endif
