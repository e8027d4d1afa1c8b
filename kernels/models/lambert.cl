// Lambert (Lambert 1760, Photometria): an ideal diffuse surface, f_r = albedo / pi.
//   value = albedo * max(0, NoL)
// Parameters: none beyond the albedo. Leaves out: nothing (the 1/pi cancels under the value convention).
#ifndef SHADELAB_MODEL_LAMBERT_CL
#define SHADELAB_MODEL_LAMBERT_CL
#include "common.cl"

SL_INLINE float Fd_Lambert_cos(float NoL) { return fmax(NoL, 0.0f); }

SL_INLINE sl_rgb lambert_eval(sl_v3 N, sl_v3 L, sl_v3 V, sl_v3 P, const ModelConsts* mc) {
    (void)V; (void)P;
    return sl_albedo_times(mc, Fd_Lambert_cos(sl_dot(N, L)));
}
#endif
