// The constant block every model reads: the material's colours and the model's own constants, filled once per
// material on the host (host/models/catalogue.cpp, pack_material) from the user's parameters.
//
// `block` holds one model's named struct (consts/<family>.h, e.g. OrenNayarConsts); a kernel reads it as that
// struct through SL_CONSTS (common.cl), the host writes it through packer<T> (host/models/catalogue.hpp). Each
// struct is checked to fit (SL_FITS_BLOCK). Models that blend others (gradient) get an array of these: [0] their
// own, then one per child.
#ifndef SHADELAB_CONSTS_MODEL_CONSTS_H
#define SHADELAB_CONSTS_MODEL_CONSTS_H
#include "consts/shared.h"

SL_SHARED_BEGIN

#define SL_MAX_CONSTS 24

typedef struct {
    float albedo[4];              // diffuse colour (rgb, linear; [3] unused)
    float specular[4];            // specular colour (rgb, linear; [3] unused)
    float block[SL_MAX_CONSTS];   // the model's own constants, as its struct
} ModelConsts;
SL_SIZE_IS(ModelConsts, 8 + SL_MAX_CONSTS)
SL_FIELD_AT(ModelConsts, albedo, 0)
SL_FIELD_AT(ModelConsts, specular, 4)
SL_FIELD_AT(ModelConsts, block, 8)

// A model's struct fits in ModelConsts.block (host only: the kernels cannot overrun what they never index).
#if defined(__OPENCL_VERSION__) || defined(__OPENCL_C_VERSION__)
#define SL_FITS_BLOCK(T)
#else
#define SL_FITS_BLOCK(T) static_assert(sizeof(T) <= SL_MAX_CONSTS * sizeof(float), #T " must fit ModelConsts.block");
#endif

SL_SHARED_END

#endif
