// The planner's catalogue search (issue 11): for each material of a scene separately, the cheaper catalogue
// models with their parameters fitted to the requested model on that material's own fragments (host/fit/,
// the scene's lights and ambient), each verified by rendering against the requested model's double reference
// before it can be chosen. Meshes of one scene may end up with different models.
//
// Per material: the requested model is fitted by every childless catalogue model whose shading kernel runs at
// least 10% faster (measured on this device, a small buffer), fastest first; the first whose verified render of
// the scene (this material substituted, the others as requested) stays within the tolerance and whose mesh
// shades at least 5% faster at full resolution is chosen. The fit is grey (the
// material's mean albedo and specular); the substitute keeps the material's colours, times the fitted scale.
// The combination of all choices is verified and timed once more at the end.
#pragma once
#include <string>
#include <vector>

#include "plan/planner.hpp"

namespace shadelab {

SubstitutionPlan plan_substitutions(Runtime& runtime, const PlanInput& input, const PlanOptions& options);

std::string format_substitutions(const SubstitutionPlan& plan, const PlanOptions& options);

}  // namespace shadelab
