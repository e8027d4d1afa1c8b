// Image against image in CIEDE2000 (on linear sRGB -> CIE L*a*b*), and the relative error on linear values.
#pragma once
#include <cstddef>

#include "shadelab/types.hpp"

namespace shadelab::api {

struct Comparison {
    std::size_t pixels = 0;             // compared (covered in both when both have alpha)
    std::size_t coverage_mismatch = 0;  // covered in one image only
    double de_mean = 0.0, de_p99 = 0.0, de_max = 0.0;
    double rel_max = 0.0, rel_p99 = 0.0;
};

// `b` is the reference; the images must have the same size and 3 or 4 channels. Throws Error on NaN/Inf.
Comparison compare(const Image& a, const Image& b);

}  // namespace shadelab::api
