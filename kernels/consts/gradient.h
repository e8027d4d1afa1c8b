// Constants of the gradient shader (kernels/models/gradient.cl), packed once per material by
// host/models/gradient.cpp. Its two children's own constants follow it (ModelConsts [1] and [2]).
#ifndef SHADELAB_CONSTS_GRADIENT_H
#define SHADELAB_CONSTS_GRADIENT_H
#include "consts/model_consts.h"

SL_SHARED_BEGIN

typedef struct {
    float gx, gy, gz;   // the unit gradient direction g (normalised on the host)
    float wavenumber;   // 2 pi / period
    float phase;        // phi, radians
} GradientConsts;
SL_SIZE_IS(GradientConsts, 5)
SL_FIELD_AT(GradientConsts, gx, 0)
SL_FIELD_AT(GradientConsts, gy, 1)
SL_FIELD_AT(GradientConsts, gz, 2)
SL_FIELD_AT(GradientConsts, wavenumber, 3)
SL_FIELD_AT(GradientConsts, phase, 4)
SL_FITS_BLOCK(GradientConsts)

SL_SHARED_END

#endif
