#include "models/catalogue.hpp"

namespace shadelab {

void register_lambert_family(std::vector<ModelInfo>& out) {
    ModelInfo m;
    m.name = "lambert";
    m.family = "lambert";
    m.summary = "ideal diffuse: albedo * max(0, N.L)";
    m.source = "Lambert (1760) Photometria; seeds 000, 001";
    m.header = "models/lambert.cl";
    m.eval = "lambert_eval";
    m.reciprocal = true;
    m.energy_conserving = true;
    out.push_back(m);
}

}  // namespace shadelab
