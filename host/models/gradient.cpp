// Gradient blend registration (kernels/models/gradient.cl): two child materials, a world-space cosine wave.
#include <cmath>

#include "core/error.hpp"
#include "models/catalogue.hpp"

namespace shadelab {

void register_gradient_family(std::vector<ModelInfo>& out) {
    ModelInfo m;
    m.name = "gradient";
    m.family = "gradient";
    m.summary = "blend of two models along a cosine wave: (1 - t) A + t B, t = (1 + cos(2 pi P.g / period + phase)) / 2";
    m.source = "seed 004 (lecture slides, Gradient Shader)";
    m.header = "models/gradient.cl";
    m.eval = "gradient_eval";
    m.children = 2;
    m.params = {{"gx", 1.0, -1.0, 1.0, "gradient direction x (normalised on the host; not all of gx, gy, gz zero)"},
                {"gy", 0.0, -1.0, 1.0, "gradient direction y"},
                {"gz", 0.0, -1.0, 1.0, "gradient direction z"},
                {"period", 1.0, 1e-4, 1e4, "world-space length of one wave"},
                {"phase", 0.0, -2.0 * M_PI, 2.0 * M_PI, "phase of the wave, radians (0: B where P.g = 0)"}};
    m.pack = [](const std::vector<double>& p, float* c) {
        const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        if (!(len > 0.0))
            throw Error("model 'gradient': the gradient direction (gx, gy, gz) is zero: give a direction");
        for (int k = 0; k < 3; ++k) c[k] = float(p[std::size_t(k)] / len);
        c[3] = float(2.0 * M_PI / p[3]);
        c[4] = float(p[4]);
    };
    m.reciprocal = false;          // inherits its children's property (the catalogue test skips blends)
    m.energy_conserving = false;   // a convex blend conserves iff both children do; not a property of its own
    out.push_back(m);
}

}  // namespace shadelab
