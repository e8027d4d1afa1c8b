#include "models/catalogue.hpp"

namespace shadelab {

// Filled in by the model-catalogue work (issue: the model catalogue).
void register_cook_torrance_family(std::vector<ModelInfo>& out) { (void)out; }

}  // namespace shadelab
