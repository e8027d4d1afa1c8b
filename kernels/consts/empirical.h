// The table buffer of the empirical family (kernels/models/empirical.cl): ISIS's MinnaertEmpirical and
// LunarLambertEmpirical, whose K(g) or L(g) and phase curve B(g) are natural cubic splines over a table of phases.
// The tables do not fit ModelConsts' 24 floats, so a material of this family carries a second buffer, the
// `__global const float* tab` argument of kernels/shade.cl's kernels, filled once per material by
// host/models/empirical.cpp from the splines computed in double (host/core/spline.hpp).
//
// The buffer is SL_EMP_MAX_SEGMENTS EmpiricalSegment one after another: segment j is the interval from knot j to
// knot j+1, its start phase and the two cubics in t = g - start. A table of n knots fills segments 0 .. n-2; the
// others start at SL_EMP_UNUSED (beyond every phase, so the kernel's scan never selects them).
#ifndef SHADELAB_CONSTS_EMPIRICAL_H
#define SHADELAB_CONSTS_EMPIRICAL_H
#include "consts/shared.h"

SL_SHARED_BEGIN

#define SL_EMP_MAX_KNOTS 32                       // the most phases a table may have (checked by the registration)
#define SL_EMP_MAX_SEGMENTS (SL_EMP_MAX_KNOTS - 1)
#define SL_EMP_UNUSED 1.0e30f                     // start phase of an unused segment

typedef struct {
    float start;      // the segment's first phase, degrees (x_j)
    float param[4];   // K(g) or L(g) = param[0] + t (param[1] + t (param[2] + t param[3])), t = g - start
    float bright[4];  // B(g), the same form
} EmpiricalSegment;
SL_SIZE_IS(EmpiricalSegment, 9)
SL_FIELD_AT(EmpiricalSegment, start, 0)
SL_FIELD_AT(EmpiricalSegment, param, 1)
SL_FIELD_AT(EmpiricalSegment, bright, 5)

SL_SHARED_END

#endif
