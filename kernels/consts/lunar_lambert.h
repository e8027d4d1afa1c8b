// Constants of the Lommel-Seeliger and Lunar-Lambert family (kernels/models/lunar_lambert.cl), packed once per
// material by host/models/lunar_lambert.cpp. lommel_seeliger has none.
#ifndef SHADELAB_CONSTS_LUNAR_LAMBERT_H
#define SHADELAB_CONSTS_LUNAR_LAMBERT_H
#include "consts/model_consts.h"

SL_SHARED_BEGIN

// lunar_lambert: mu0 ((1 - L) + 2 L / (mu0 + mu)).
typedef struct {
    float L;  // limb-darkening weight (ISIS L)
} LunarLambertConsts;
SL_SIZE_IS(LunarLambertConsts, 1)
SL_FIELD_AT(LunarLambertConsts, L, 0)
SL_FITS_BLOCK(LunarLambertConsts)

SL_SHARED_END

#endif
