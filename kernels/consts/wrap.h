// Constants of the wrap-lighting family (kernels/models/wrap.cl), packed once per material by
// host/models/wrap.cpp. half_lambert and half_lambert_seed001 have none.
#ifndef SHADELAB_CONSTS_WRAP_H
#define SHADELAB_CONSTS_WRAP_H
#include "consts/model_consts.h"

SL_SHARED_BEGIN

// wrap, wrap_seed001: value = albedo * max(0, NoL a + (1 - a))^2.
typedef struct {
    float a;            // wrap_value
    float one_minus_a;  // 1 - a
} WrapConsts;
SL_SIZE_IS(WrapConsts, 2)
SL_FIELD_AT(WrapConsts, a, 0)
SL_FIELD_AT(WrapConsts, one_minus_a, 1)
SL_FITS_BLOCK(WrapConsts)

// wrap_energy: value = albedo * saturate((NoL + w) / (1 + w)^2).
typedef struct {
    float w;
    float inv_sq;  // 1 / (1 + w)^2
} WrapEnergyConsts;
SL_SIZE_IS(WrapEnergyConsts, 2)
SL_FIELD_AT(WrapEnergyConsts, w, 0)
SL_FIELD_AT(WrapEnergyConsts, inv_sq, 1)
SL_FITS_BLOCK(WrapEnergyConsts)

SL_SHARED_END

#endif
