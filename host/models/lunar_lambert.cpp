// The Lommel-Seeliger and Lunar-Lambert family (kernels/models/lunar_lambert.cl, docs/models/lunar_lambert.md):
// ISIS3's two simplest photometric laws of airless bodies, in one place: parameters, ranges, flags, precision
// bounds, the constants the kernel reads (kernels/consts/lunar_lambert.h) and the family's page. Their reference is
// host/reference/lunar_lambert_ref.cpp, their tests tests/test_lunar_lambert.cpp. Parameter names are shadelab's
// lower-case forms of ISIS's keywords (L -> l); host/photometry/isis_pvl.cpp maps ISIS's PVL files onto them.
#include "consts/lunar_lambert.h"
#include "models/catalogue.hpp"
#include "models/model_info.hpp"

namespace shadelab {

namespace {

ModelInfo base(const char* name, const char* summary, const char* source, const char* eval) {
    return model_info("models/lunar_lambert.cl", name, summary, source, eval);
}

}  // namespace

// The family as it registers itself (host/models/catalogue.hpp, ModelFamily): rank 85, after the gradient blend and
// before the rest of ISIS's laws (planetary, 90).
ModelFamily register_lunar_lambert_family() {
    ModelFamily family{"lunar_lambert", 85, "Lommel-Seeliger and Lunar-Lambert", "docs/models/lunar_lambert.md", {}};
    std::vector<ModelInfo>& out = family.models;
    {
        ModelInfo m = base("lommel_seeliger", "Lommel-Seeliger, ISIS's normalisation: albedo * 2 NoL / (NoL + NoV)",
                           "Seeliger (1888); ISIS3 LommelSeeliger photometric model", "lommel_seeliger_eval");
        m.reciprocal = true;   // f_r = 2 albedo / (pi (NoL + NoV))
        m.energy_conserving = false;
        // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
        m.precision = {{"*", 5.15e-7, 1.5e-6, 5.15e-7, 1.5e-6}};
        out.push_back(m);
    }
    {
        ModelInfo m = base("lunar_lambert", "Lunar-Lambert: albedo * NoL ((1 - L) + 2 L / (NoL + NoV))",
                           "McEwen (1991) Icarus 92:298; ISIS3 LunarLambert photometric model", "lunar_lambert_eval");
        m.params = {{"l", 1.0, -1.0, 2.0,
                     "limb-darkening weight L (ISIS L): 0 Lambert, 1 Lommel-Seeliger; ISIS sets no bounds"}};
        m.pack = packer<LunarLambertConsts>([](const std::vector<double>& p) {
            LunarLambertConsts c{};
            c.L = float(p[0]);
            return c;
        });
        m.reciprocal = true;   // f_r = albedo/pi ((1 - L) + 2L / (NoL + NoV)): symmetric
        m.energy_conserving = false;
        // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
        m.precision = {
            {"*", 5.52e-7, 1.5e-6, 5.52e-7, 1.5e-6},
            // L < 0: the two terms mu0 (1 - L) and 2 L mu0 / (mu0 + mu) cancel (docs/models/lunar_lambert.md)
            {"l=-1", 5.36e-5, 1.5e-4, 5.36e-5, 1.5e-4},
        };
        out.push_back(m);
    }
    // sixteen lanes a work-item on AVX2 hosts (1.17x at 1M and 1.32x at 16M fragments, the median of eight
    // alternating rounds on an AMD Zen 3: docs/speed.md, "Sixteen lanes on AVX2"; lunar_lambert 0.98x at 1M: not)
    use_sixteen_lanes_on_avx2(family, {"lommel_seeliger"}, 1);
    return family;
}

}  // namespace shadelab
