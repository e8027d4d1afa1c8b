// Constants of the planetary family (kernels/models/planetary.cl), ISIS3's photometric laws, packed once per
// material by host/models/planetary.cpp (in double, stored as float).
#ifndef SHADELAB_CONSTS_PLANETARY_H
#define SHADELAB_CONSTS_PLANETARY_H
#include "consts/model_consts.h"

SL_SHARED_BEGIN

// lunar_lambert_mcewen(_ratio): McEwen's L(g) = 1 + m1 g + m2 g^2 + m3 g^3, g in degrees; the ratio form also
// R30 = r(30, 30, 0) and the floor of r.
typedef struct {
    float m1, m2, m3;
    float r30;      // lunar_lambert_mcewen_ratio only
    float r_floor;  // lunar_lambert_mcewen_ratio only: 1e-3
} McEwenConsts;
SL_SIZE_IS(McEwenConsts, 5)
SL_FIELD_AT(McEwenConsts, m1, 0)
SL_FIELD_AT(McEwenConsts, m2, 1)
SL_FIELD_AT(McEwenConsts, m3, 2)
SL_FIELD_AT(McEwenConsts, r30, 3)
SL_FIELD_AT(McEwenConsts, r_floor, 4)
SL_FITS_BLOCK(McEwenConsts)

// ISIS's two-term Henyey-Greenstein P(g) (hapke_hen, hapke_2012), b = Hg1, c = Hg2.
typedef struct {
    float a;             // (1 - |b|)^2
    float two_abs_b;     // 2 |b|
    float b_positive;    // 1 if b >= 0, else 0
    float one_minus_b2;  // 1 - b^2
    float c;
    float one_minus_c;   // 1 - c
} HapkeHG2Consts;
SL_SIZE_IS(HapkeHG2Consts, 6)
SL_FIELD_AT(HapkeHG2Consts, a, 0)
SL_FIELD_AT(HapkeHG2Consts, two_abs_b, 1)
SL_FIELD_AT(HapkeHG2Consts, b_positive, 2)
SL_FIELD_AT(HapkeHG2Consts, one_minus_b2, 3)
SL_FIELD_AT(HapkeHG2Consts, c, 4)
SL_FIELD_AT(HapkeHG2Consts, one_minus_c, 5)

// Hapke's Legendre P(g) = 1 + b cos g + c (3 cos^2 g - 1) / 2 (hapke_leg).
typedef struct {
    float b;  // ISIS Bh
    float c;  // ISIS Ch
} HapkeLegendreConsts;
SL_SIZE_IS(HapkeLegendreConsts, 2)
SL_FIELD_AT(HapkeLegendreConsts, b, 0)
SL_FIELD_AT(HapkeLegendreConsts, c, 1)

// The one P(g) a Hapke model has.
typedef union {
    HapkeHG2Consts hg2;            // hapke_hen, hapke_2012
    HapkeLegendreConsts legendre;  // hapke_leg
} HapkePhaseConsts;
SL_SIZE_IS(HapkePhaseConsts, 6)

// hapke_hen, hapke_leg, hapke_2012. The cot terms are capped on the host (kernel: Hapke_E2 says why).
typedef struct {
    float w_over_4;  // w / 4 (hapke_2012 reads w instead)
    float gamma;     // sqrt(1 - w)
    float b0;        // opposition surge amplitude B0 (0 when h = 0)
    float inv_h;     // 1 / h (0 when h = 0)
    float rough;     // 1 for a rough surface (theta-bar > 0), 0 for the smooth law
    float chi;       // 1 / sqrt(1 + pi tan^2(theta-bar))
    float tan_t;     // tan(theta-bar)
    float k1;        // (2/pi) cot(theta-bar)
    float k2;        // (1/pi) cot^2(theta-bar)
    HapkePhaseConsts phase;
    float w;         // hapke_2012 only: w
    float r0;        // hapke_2012 only: (1 - gamma) / (1 + gamma)
    float K;         // hapke_2012 only: the porosity factor
    float bc0;       // hapke_2012 only: coherent-backscatter amplitude B_C0 (0 when h_C = 0)
    float inv_hc;    // hapke_2012 only: 1 / h_C (0 when h_C = 0)
} HapkeConsts;
SL_SIZE_IS(HapkeConsts, 20)
SL_FIELD_AT(HapkeConsts, w_over_4, 0)
SL_FIELD_AT(HapkeConsts, gamma, 1)
SL_FIELD_AT(HapkeConsts, b0, 2)
SL_FIELD_AT(HapkeConsts, inv_h, 3)
SL_FIELD_AT(HapkeConsts, rough, 4)
SL_FIELD_AT(HapkeConsts, chi, 5)
SL_FIELD_AT(HapkeConsts, tan_t, 6)
SL_FIELD_AT(HapkeConsts, k1, 7)
SL_FIELD_AT(HapkeConsts, k2, 8)
SL_FIELD_AT(HapkeConsts, phase, 9)
SL_FIELD_AT(HapkeConsts, w, 15)
SL_FIELD_AT(HapkeConsts, r0, 16)
SL_FIELD_AT(HapkeConsts, K, 17)
SL_FIELD_AT(HapkeConsts, bc0, 18)
SL_FIELD_AT(HapkeConsts, inv_hc, 19)
SL_FITS_BLOCK(HapkeConsts)

SL_SHARED_END

#endif
