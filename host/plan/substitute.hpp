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

struct Substitution {
    std::size_t item = 0;
    Material requested;
    Material chosen;                 // == requested when nothing cheaper stays within the tolerance
    double fit_rel_rms = 0.0;        // the fit's own error on the material's fragments (grey)
    double error = 0.0;              // verified: the plan metric of the scene with this substitution alone
    double model_speedup = 1.0;      // this mesh's full-resolution shading time, requested / chosen
    int tried = 0;                   // candidates fitted and verified
};

struct SubstitutionPlan {
    std::vector<Substitution> items;
    double error = 0.0;              // verified: every substitution at once
    bool within = false;
    double requested_ms = 0.0, chosen_ms = 0.0, speedup = 1.0;   // full-resolution shading time, best of runs
    double planning_ms = 0.0;        // the whole search (fits, verifications, timings)
    int verify_width = 0, verify_height = 0;
};

SubstitutionPlan plan_substitutions(Runtime& runtime, const PlanInput& input, const PlanOptions& options);

std::string format_substitutions(const SubstitutionPlan& plan, const PlanOptions& options);

}  // namespace shadelab
