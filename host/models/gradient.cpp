// Gradient blend registration (kernels/models/gradient.cl): two child materials, a world-space cosine wave.
#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "consts/gradient.h"
#include "models/catalogue.hpp"

namespace shadelab {

// The family as it registers itself (host/models/catalogue.hpp, ModelFamily): rank 80 in the catalogue.
ModelFamily register_gradient_family() {
    ModelFamily family{"gradient", 80, "gradient blend", "docs/models/gradient.md", {}};
    std::vector<ModelInfo>& out = family.models;
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
    // resolve_material checks each component's range only; the direction as a whole is checked here, where it
    // is normalised (pack_material runs before every launch, so no kernel ever sees it).
    m.pack = packer<GradientConsts>([](const std::vector<double>& p) {
        // Scaled by the largest component first, so a tiny direction (1e-200, 0, 0) normalises instead of
        // squaring to 0.
        const double big = std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])});
        if (!(big > 0.0))
            throw Error("model 'gradient': the gradient direction (gx, gy, gz) is (0, 0, 0): give a direction, "
                        "e.g. gx = 1");
        const double x = p[0] / big, y = p[1] / big, z = p[2] / big;
        const double len = std::sqrt(x * x + y * y + z * z);
        GradientConsts k{};
        k.gx = float(x / len);
        k.gy = float(y / len);
        k.gz = float(z / len);
        k.wavenumber = float(2.0 * M_PI / p[3]);
        k.phase = float(p[4]);
        return k;
    });
    m.reciprocal = false;          // inherits its children's property (the catalogue test skips blends)
    m.energy_conserving = false;   // a convex blend conserves iff both children do; not a property of its own
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {
        {"*", 4.17e-6, 1.2e-5, 4.17e-6, 1.2e-5},
        // fast was 3.05e-2 with PoCL's native_cos (argument reduction lost past 5e4 rad); own cos in both modes now
        {"period=0.0001", 2.00e-2, 6e-2, 2.00e-2, 6e-2},
    };
    out.push_back(m);
    return family;
}

}  // namespace shadelab
