// Constants of the Oren-Nayar family (kernels/models/oren_nayar.cl), packed once per material by
// host/models/oren_nayar.cpp from the user's parameters (in double, stored as float). The formulas behind each
// field are in the kernel file, above the model that reads it, and in docs/models/oren_nayar.md.
#ifndef SHADELAB_CONSTS_OREN_NAYAR_H
#define SHADELAB_CONSTS_OREN_NAYAR_H
#include "consts/model_consts.h"

SL_SHARED_BEGIN

// value = albedo NoL (A + B * angular term): oren_nayar, oren_nayar_st, oren_nayar_blender (the paper's
// A = 1 - 0.5 s2/(s2 + 0.33), B = 0.45 s2/(s2 + 0.09), s2 = sigma^2), oren_nayar_seed003 (the same from its
// R = roughness^2), oren_nayar_seed004 (0.57 for 0.33 in A), oren_nayar_fujii (Fujii's pi A and pi B).
typedef struct {
    float A;
    float B;
} OrenNayarConsts;
SL_SIZE_IS(OrenNayarConsts, 2)
SL_FIELD_AT(OrenNayarConsts, A, 0)
SL_FIELD_AT(OrenNayarConsts, B, 1)
SL_FITS_BLOCK(OrenNayarConsts)

// The paper's full model (oren_nayar_full): the sigma-only factors of C1, C2, C3 and the interreflection term.
typedef struct {
    float C1;        // 1 - 0.5 s2/(s2 + 0.33)
    float C2_scale;  // 0.45 s2/(s2 + 0.09)
    float C3_scale;  // 0.125 s2/(s2 + 0.09)
    float L2_scale;  // 0.17 s2/(s2 + 0.13)
} OrenNayarFullConsts;
SL_SIZE_IS(OrenNayarFullConsts, 4)
SL_FIELD_AT(OrenNayarFullConsts, C1, 0)
SL_FIELD_AT(OrenNayarFullConsts, C2_scale, 1)
SL_FIELD_AT(OrenNayarFullConsts, C3_scale, 2)
SL_FIELD_AT(OrenNayarFullConsts, L2_scale, 3)
SL_FITS_BLOCK(OrenNayarFullConsts)

// value = rho NoL (A + rho A_rho + B * s-term) per channel of albedo rho: oren_nayar_seed001 (its on.x, on.y,
// on.z) and oren_nayar_fujii_full (Fujii's A, B matched to the full model): A = 1 - 0.5 s2/(s2 + 0.33),
// A_rho = 0.17 s2/(s2 + 0.13), B = 0.45 s2/(s2 + 0.09).
typedef struct {
    float A;
    float A_rho;
    float B;
} OrenNayarAlbedoConsts;
SL_SIZE_IS(OrenNayarAlbedoConsts, 3)
SL_FIELD_AT(OrenNayarAlbedoConsts, A, 0)
SL_FIELD_AT(OrenNayarAlbedoConsts, A_rho, 1)
SL_FIELD_AT(OrenNayarAlbedoConsts, B, 2)
SL_FITS_BLOCK(OrenNayarAlbedoConsts)

// EON (eon, eon_approx), roughness r: c1 = 1/2 - 2/(3 pi), c2 = 2/3 - 28/(15 pi).
typedef struct {
    float AF;    // 1 / (1 + c1 r)
    float r;     // the roughness itself
    float Ebar;  // AF (1 + c2 r), the FON average albedo
    float k_ms;  // r AF / (c1 - c2), the multiple-scattering lobe's scale
    float c1;    // 1/2 - 2/(3 pi)
} EonConsts;
SL_SIZE_IS(EonConsts, 5)
SL_FIELD_AT(EonConsts, AF, 0)
SL_FIELD_AT(EonConsts, r, 1)
SL_FIELD_AT(EonConsts, Ebar, 2)
SL_FIELD_AT(EonConsts, k_ms, 3)
SL_FIELD_AT(EonConsts, c1, 4)
SL_FITS_BLOCK(EonConsts)

SL_SHARED_END

#endif
