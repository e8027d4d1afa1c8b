// Constants of the banded and toon family (kernels/models/banded_toon.cl), packed once per material by
// host/models/banded_toon.cpp.
#ifndef SHADELAB_CONSTS_BANDED_TOON_H
#define SHADELAB_CONSTS_BANDED_TOON_H
#include "consts/model_consts.h"

SL_SHARED_BEGIN

// banded: NoL rounded to the nearest of `steps` levels.
typedef struct {
    float steps;      // whole number in [1, 256]
    float inv_steps;  // 1 / steps
} BandedConsts;
SL_SIZE_IS(BandedConsts, 2)
SL_FIELD_AT(BandedConsts, steps, 0)
SL_FIELD_AT(BandedConsts, inv_steps, 1)
SL_FITS_BLOCK(BandedConsts)

// banded_seed001: seed 001's bandedNdotL with t = light_steps.
typedef struct {
    float t;      // light_steps, a step size in 1/256 units
    float half_t; // t / 2, the seed's lightBandsAdditive
    float t_256;  // t / 256, the seed's lightBandsMultiplier
} BandedSeed001Consts;
SL_SIZE_IS(BandedSeed001Consts, 3)
SL_FIELD_AT(BandedSeed001Consts, t, 0)
SL_FIELD_AT(BandedSeed001Consts, half_t, 1)
SL_FIELD_AT(BandedSeed001Consts, t_256, 2)
SL_FITS_BLOCK(BandedSeed001Consts)

// toon: four diffuse levels d0..d3 at thresholds t1 <= t2 <= t3 of NoL, three specular levels s0..s2 at
// thresholds u1 <= u2 of max(0, NoH)^n; each level after the first as its difference to the one below. The
// thresholds of one kind sit next to each other (kernels/models/banded_toon.cl, Toon_Diffuse, says why that
// matters to the vectoriser and how the kernel keeps it from mattering).
typedef struct {
    float n;           // Blinn-Phong exponent of the highlight
    float half_width;  // half the smoothstep width of every edge (0: hard steps)
    float t1, t2, t3;  // diffuse thresholds
    float d0;          // diffuse level below t1
    float dd1, dd2, dd3;  // d1 - d0, d2 - d1, d3 - d2
    float u1, u2;      // specular thresholds
    float s0;          // specular level below u1
    float ds1, ds2;    // s1 - s0, s2 - s1
    float inv_width;   // 1 / (2 half_width), the smoothstep's slope (0 for hard steps: unused there)
} ToonConsts;
SL_SIZE_IS(ToonConsts, 15)
SL_FIELD_AT(ToonConsts, n, 0)
SL_FIELD_AT(ToonConsts, half_width, 1)
SL_FIELD_AT(ToonConsts, t1, 2)
SL_FIELD_AT(ToonConsts, t2, 3)
SL_FIELD_AT(ToonConsts, t3, 4)
SL_FIELD_AT(ToonConsts, d0, 5)
SL_FIELD_AT(ToonConsts, dd1, 6)
SL_FIELD_AT(ToonConsts, dd2, 7)
SL_FIELD_AT(ToonConsts, dd3, 8)
SL_FIELD_AT(ToonConsts, u1, 9)
SL_FIELD_AT(ToonConsts, u2, 10)
SL_FIELD_AT(ToonConsts, s0, 11)
SL_FIELD_AT(ToonConsts, ds1, 12)
SL_FIELD_AT(ToonConsts, ds2, 13)
SL_FIELD_AT(ToonConsts, inv_width, 14)
SL_FITS_BLOCK(ToonConsts)

SL_SHARED_END

#endif
