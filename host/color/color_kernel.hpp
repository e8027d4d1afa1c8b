// CIEDE2000 on the OpenCL device (kernels/color.cl), for scoring large images without a host loop.
#pragma once
#include <vector>

#include "cl/runtime.hpp"

namespace shadelab {

// a, b: rgb interleaved linear sRGB (3n floats each). Returns n Delta E 2000 values.
std::vector<float> delta_e2000_device(Runtime& rt, const std::vector<float>& a, const std::vector<float>& b);

// a, b: L*a*b* interleaved (3n floats each). Returns n Delta E 2000 values.
std::vector<float> delta_e2000_lab_device(Runtime& rt, const std::vector<float>& a, const std::vector<float>& b);

}  // namespace shadelab
