// Constants of the Cook-Torrance family (kernels/models/cook_torrance.cl), packed once per material by
// host/models/cook_torrance.cpp. Every model of the family reads the same struct.
#ifndef SHADELAB_CONSTS_COOK_TORRANCE_H
#define SHADELAB_CONSTS_COOK_TORRANCE_H
#include "consts/model_consts.h"

SL_SHARED_BEGIN

typedef struct {
    float m;               // roughness: RMS microfacet slope (Beckmann m, GGX alpha)
    float f0;              // Fresnel reflectance at normal incidence
    float kd;              // weight of the Lambert part
    float ks;              // weight of the specular part
    float inv_m2;          // 1 / m^2 (Beckmann)
    float inv_pi_m2;       // 1 / (pi m^2) (Beckmann)
    float m2;              // m^2 (GGX alpha^2)
    float inv_eta;         // 1 / eta of the dielectric with reflectance f0 (exact Fresnel)
    float one_minus_inv_eta2;  // 1 - 1 / eta^2
} CookTorranceConsts;
SL_SIZE_IS(CookTorranceConsts, 9)
SL_FIELD_AT(CookTorranceConsts, m, 0)
SL_FIELD_AT(CookTorranceConsts, f0, 1)
SL_FIELD_AT(CookTorranceConsts, kd, 2)
SL_FIELD_AT(CookTorranceConsts, ks, 3)
SL_FIELD_AT(CookTorranceConsts, inv_m2, 4)
SL_FIELD_AT(CookTorranceConsts, inv_pi_m2, 5)
SL_FIELD_AT(CookTorranceConsts, m2, 6)
SL_FIELD_AT(CookTorranceConsts, inv_eta, 7)
SL_FIELD_AT(CookTorranceConsts, one_minus_inv_eta2, 8)
SL_FITS_BLOCK(CookTorranceConsts)

SL_SHARED_END

#endif
