#include "models/catalogue.hpp"

namespace shadelab {

// The family as it registers itself (host/models/catalogue.hpp, ModelFamily): rank 10 in the catalogue.
ModelFamily register_lambert_family() {
    ModelFamily family{"lambert", 10, "Lambert", "docs/models/README.md", {}};
    std::vector<ModelInfo>& out = family.models;
    ModelInfo m;
    m.name = "lambert";
    m.family = "lambert";
    m.summary = "ideal diffuse: albedo * max(0, N.L)";
    m.source = "Lambert (1760) Photometria; seeds 000, 001";
    m.header = "models/lambert.cl";
    m.eval = "lambert_eval";
    m.reciprocal = true;
    m.energy_conserving = true;
    m.normals_only = true;
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 7.33e-7, 2e-6, 7.33e-7, 2e-6}};
    out.push_back(m);
    // two chains a work-item where measuring each model at one and two found two faster (docs/speed.md,
    // "Two chains")
    use_two_chains(family, {"lambert"});
    return family;
}

}  // namespace shadelab
