// Lambert (Lambert 1760, Photometria): an ideal diffuse surface, f_r = albedo / pi.
//   value = albedo * max(0, NoL)
// Parameters: none beyond the albedo. Leaves out: nothing (the 1/pi cancels under the value convention).
#ifndef SHADELAB_MODEL_LAMBERT_CL
#define SHADELAB_MODEL_LAMBERT_CL
#include "common.cl"

SL_INLINE float Fd_Lambert_cos(float NoL) { return fmax(NoL, 0.0f); }

// value = albedo * lambert_nol(NoL): shade.cl's scalar path for models of N.L alone uses this factor directly.
SL_INLINE float lambert_nol(float NoL, __constant const ModelConsts* mc) {
    (void)mc;
    return Fd_Lambert_cos(NoL);
}
#define SL_HAS_NOL_lambert_eval 1
#define SL_NOL_lambert_eval lambert_nol

SL_INLINE float3 lambert_eval(float3 N, float3 L, float3 V, float3 P, __constant const ModelConsts* mc) {
    (void)V; (void)P;
    return sl_albedo(mc) * lambert_nol(dot(N, L), mc);
}
#endif
