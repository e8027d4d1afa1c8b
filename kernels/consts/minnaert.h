// Constants of the Minnaert family (kernels/models/minnaert.cl), packed once per material by
// host/models/minnaert.cpp.
#ifndef SHADELAB_CONSTS_MINNAERT_H
#define SHADELAB_CONSTS_MINNAERT_H
#include "consts/model_consts.h"

SL_SHARED_BEGIN

// minnaert_1941: NoL (NoL NoV)^(k - 1) with the limb guard (kernels/models/minnaert.cl, Minnaert_limb).
typedef struct {
    float k_minus_1;  // k - 1
    float eps;        // the guard's taper width: 1e-3 for k < 1, else 0
    float inv_eps;    // 1 / eps (0 when eps = 0)
} MinnaertConsts;
SL_SIZE_IS(MinnaertConsts, 3)
SL_FIELD_AT(MinnaertConsts, k_minus_1, 0)
SL_FIELD_AT(MinnaertConsts, eps, 1)
SL_FIELD_AT(MinnaertConsts, inv_eps, 2)
SL_FITS_BLOCK(MinnaertConsts)

// minnaert_normalized: minnaert_1941 times (k + 1) / 2.
typedef struct {
    float k_minus_1;  // as MinnaertConsts
    float eps;
    float inv_eps;
    float norm;       // (k + 1) / 2
} MinnaertNormalizedConsts;
SL_SIZE_IS(MinnaertNormalizedConsts, 4)
SL_FIELD_AT(MinnaertNormalizedConsts, k_minus_1, 0)
SL_FIELD_AT(MinnaertNormalizedConsts, eps, 1)
SL_FIELD_AT(MinnaertNormalizedConsts, inv_eps, 2)
SL_FIELD_AT(MinnaertNormalizedConsts, norm, 3)
SL_FITS_BLOCK(MinnaertNormalizedConsts)

// minnaert_unity: saturate(NoL (NoL NoV)^k).
typedef struct {
    float k;  // the seed's _Roughness
} MinnaertUnityConsts;
SL_SIZE_IS(MinnaertUnityConsts, 1)
SL_FIELD_AT(MinnaertUnityConsts, k, 0)
SL_FITS_BLOCK(MinnaertUnityConsts)

// minnaert_blender: Blender's two branches of darkness d.
typedef struct {
    float d_minus_1;    // d - 1
    float real_branch;  // 1 for d <= 1 (Blender's "real model"), 0 for its "Nvidia model"
} MinnaertBlenderConsts;
SL_SIZE_IS(MinnaertBlenderConsts, 2)
SL_FIELD_AT(MinnaertBlenderConsts, d_minus_1, 0)
SL_FIELD_AT(MinnaertBlenderConsts, real_branch, 1)
SL_FITS_BLOCK(MinnaertBlenderConsts)

// minnaert_b: NoL^k (1 - NoV)^(1 - k).
typedef struct {
    float k;
    float one_minus_k;  // 1 - k
} MinnaertBConsts;
SL_SIZE_IS(MinnaertBConsts, 2)
SL_FIELD_AT(MinnaertBConsts, k, 0)
SL_FIELD_AT(MinnaertBConsts, one_minus_k, 1)
SL_FITS_BLOCK(MinnaertBConsts)

SL_SHARED_END

#endif
