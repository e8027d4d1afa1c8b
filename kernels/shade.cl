// The shading kernels. The host builds this file with the model chosen by defines:
//   SL_MODEL_HEADER  e.g. <models/lambert.cl>   the file that defines the model's eval function
//   SL_EVAL          e.g. lambert_eval          sl_rgb f(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, consts*)
//   SL_NUM_LIGHTS    number of lights (the loop is unrolled for it)
//   SL_POINT_LIGHTS, SL_RANGED_LIGHTS  bit l set for a point light, for one with a range (optional, together:
//                    kernels/shade_parts.cl)
//   SL_TABLE         1 when the model reads a per-material table (the empirical family, kernels/consts/empirical.h):
//                    its eval takes the kernels' `tab` argument as a sixth argument (optional)
//   SL_TABLE_KNOTS   with SL_TABLE: the most knots the material's table may have in this program (4, 8, 16, 32)
// so each program holds only the model and options a scene uses.
#include "common.cl"
#include SL_MODEL_HEADER
#include "shade_parts.cl"

#define SL_SHADE_KERNEL shade_fragments
#include "shade_fragments.cl"
#undef SL_SHADE_KERNEL

// The model alone at triple i of xyz-interleaved N, L, V, P (unmasked: tests/test_precision.cpp counts its NaN/Inf).
SL_INLINE sl_rgb eval_direction_at(size_t i, __global const float* N_, __global const float* L_,
                                   __global const float* V_, __global const float* P_,
                                   const ModelConsts* mc, __global const float* restrict tab) {
    (void)tab;
    const sl_v3 N = sl_v3_make(N_[3 * i], N_[3 * i + 1], N_[3 * i + 2]);
    const sl_v3 L = sl_v3_make(L_[3 * i], L_[3 * i + 1], L_[3 * i + 2]);
    const sl_v3 V = sl_v3_make(V_[3 * i], V_[3 * i + 1], V_[3 * i + 2]);
    const sl_v3 P = sl_v3_make(P_[3 * i], P_[3 * i + 1], P_[3 * i + 2]);
    return SL_EVAL_AT(N, L, V, P, mc);
}

// The model alone for given unit directions (no lights, no attenuation): what the tests sweep, and the library's
// eval. SL_FRAGS_PER_ITEM triples a work-item in common.cl's fragment loop (one a work-item was left to PoCL's
// work-item loop vectoriser, whose code for it was scalar). A work-item whose triples would run past `n` (>=
// SL_FRAGS_PER_ITEM: the host pads fewer) evaluates the last SL_FRAGS_PER_ITEM of them instead, the same values to
// the same places, as shade_fragments does: no load or store is under a condition.
__kernel void eval_directions(__global const float* restrict N_, __global const float* restrict L_,
                              __global const float* restrict V_, __global const float* restrict P_,
                              __global float* restrict out, const uint n, __constant const ModelConsts* mc_arg,
                              __global const float* restrict tab) {
    SL_PRIVATE_CONSTS(mc, mc_arg);   // see common.cl's SL_CONSTS
    // size_t, not uint: a 32-bit index that may wrap makes px[i] a gather
    const size_t first = min(get_global_id(0) * SL_FRAGS_PER_ITEM, (size_t)n - SL_FRAGS_PER_ITEM);
    SL_FRAGMENT_LOOP
    for (uint k = 0; k < SL_FRAGS_PER_ITEM; ++k) {
        const size_t i = first + k;
        const sl_rgb r = eval_direction_at(i, N_, L_, V_, P_, mc, tab);
        out[3 * i] = sl_finite_or_zero(r.r);
        out[3 * i + 1] = sl_finite_or_zero(r.g);
        out[3 * i + 2] = sl_finite_or_zero(r.b);
    }
}

// ---- Batched evaluation for fitting (host/fit/) ----------------------------------------------------------------
// Many parameter sets x many samples in one launch: work item (w, s) evaluates the model alone (no lights, no
// ambient, as eval_directions) at samples w SL_FRAGS_PER_ITEM .. (w + 1) SL_FRAGS_PER_ITEM - 1 with constant set s,
// in common.cl's fragment loop (as shade_fragments: one sample a work-item was left to PoCL's work-item loop
// vectoriser, which ran it one sample at a time). The parameters live in the __constant block, not in the
// program, so every set shares this one build. Dimension 0 runs over the samples, so the set (and with it every
// constant load) is the same for a whole work-group and hoisted out of the loop.
//   dirs:  12 planes of `stride` floats: N.x N.y N.z L.x L.y L.z V.x V.y V.z P.x P.y P.z
//   out:   3 planes (r, g, b) of `stride` floats per set: out[(3 s + c) stride + i]
//   sets:  consts_per_set ModelConsts per set (the model's own, then its children's: gradient reads mc[1], mc[2])
// No bounds check: the host pads the samples to the launch size (zero directions, whose values are never read).
__kernel void eval_batch(__global const float* restrict dirs, __global float* restrict out, const uint stride,
                         const uint consts_per_set, __constant const ModelConsts* sets,
                         __global const float* restrict tab) {
    (void)tab;
    // size_t, not uint: a 32-bit index that may wrap makes dirs[i] a gather
    const size_t first = get_global_id(0) * SL_FRAGS_PER_ITEM, s = get_global_id(1);
    const size_t st = stride;
    SL_PRIVATE_CONSTS(mc, sets + s * consts_per_set);   // see common.cl's SL_CONSTS
    __global float* o = out + 3 * s * st;
    SL_FRAGMENT_LOOP
    for (uint k = 0; k < SL_FRAGS_PER_ITEM; ++k) {
        const size_t i = first + k;
        const sl_v3 N = sl_v3_make(dirs[i], dirs[st + i], dirs[2 * st + i]);
        const sl_v3 L = sl_v3_make(dirs[3 * st + i], dirs[4 * st + i], dirs[5 * st + i]);
        const sl_v3 V = sl_v3_make(dirs[6 * st + i], dirs[7 * st + i], dirs[8 * st + i]);
        const sl_v3 P = sl_v3_make(dirs[9 * st + i], dirs[10 * st + i], dirs[11 * st + i]);
        const sl_rgb r = SL_EVAL_AT(N, L, V, P, mc);
        o[i] = sl_finite_or_zero(r.r);
        o[st + i] = sl_finite_or_zero(r.g);
        o[2 * st + i] = sl_finite_or_zero(r.b);
    }
}
