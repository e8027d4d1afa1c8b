// Constants of the Phong family (kernels/models/phong.cl), packed once per material by host/models/phong.cpp.
#ifndef SHADELAB_CONSTS_PHONG_H
#define SHADELAB_CONSTS_PHONG_H
#include "consts/model_consts.h"

SL_SHARED_BEGIN

// phong, blinn_phong, phong_seed001, blinn_phong_seed001: albedo max(0, NoL) + ks specular x^n.
typedef struct {
    float n;   // cosine-power exponent (phong_seed001: gloss / 4)
    float ks;  // specular multiplier (the seeds' specular_power)
} PhongConsts;
SL_SIZE_IS(PhongConsts, 2)
SL_FIELD_AT(PhongConsts, n, 0)
SL_FIELD_AT(PhongConsts, ks, 1)
SL_FITS_BLOCK(PhongConsts)

// phong_normalized, blinn_phong_normalized(_approx): kd albedo NoL + lobe_scale specular x^n NoL.
typedef struct {
    float n;           // cosine-power exponent
    float kd;          // 1 - ks
    float lobe_scale;  // ks times the lobe's normalisation: (n + 2)/2, K_n (Giesen) or (n + 8)/8
} PhongNormalizedConsts;
SL_SIZE_IS(PhongNormalizedConsts, 3)
SL_FIELD_AT(PhongNormalizedConsts, n, 0)
SL_FIELD_AT(PhongNormalizedConsts, kd, 1)
SL_FIELD_AT(PhongNormalizedConsts, lobe_scale, 2)
SL_FITS_BLOCK(PhongNormalizedConsts)

SL_SHARED_END

#endif
