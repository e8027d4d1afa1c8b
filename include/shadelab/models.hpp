// The model catalogue and the double-precision references, without the OpenCL device.
#pragma once
#include <string>
#include <vector>

#include "shadelab/types.hpp"

namespace shadelab::api {

// "shadelab X.Y.Z"'s X.Y.Z.
std::string version();

// Every model name of the catalogue, in its order.
std::vector<std::string> models();

// One model's description; throws shadelab::api::Error for an unknown name (with the closest name as a hint).
ModelInfo model_info(const std::string& name);

// The double-precision reference of the material's model at unit N, L, V (and world position P, used by the
// gradient model only): outgoing value for a unit white light (a white Lambert surface lit head-on gives 1).
Vec3 reference(const Material& material, const Vec3& N, const Vec3& L, const Vec3& V, const Vec3& P = {0, 0, 0});

}  // namespace shadelab::api
