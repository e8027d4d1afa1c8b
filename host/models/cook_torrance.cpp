// The Cook-Torrance family (kernels/models/cook_torrance.cl, docs/models/cook_torrance.md): a Lambert base plus
// the 1982 microfacet specular term, with the Beckmann or GGX distribution and Schlick's or the exact dielectric
// Fresnel term. Parameter-only constants (1/m^2, the dielectric's index) are packed here, once per material.
#include <cmath>

#include "consts/cook_torrance.h"
#include "models/catalogue.hpp"

namespace shadelab {

// The family as it registers itself (host/models/catalogue.hpp, ModelFamily): rank 70 in the catalogue.
ModelFamily register_cook_torrance_family() {
    ModelFamily family{"cook_torrance", 70, "Cook-Torrance", "docs/models/cook_torrance.md", {}};
    std::vector<ModelInfo>& out = family.models;
    const std::vector<ParamSpec> params = {
        // 0.02: sharper lobes are near-mirrors (peak D = 1/(pi m^2) = 796 here), and the float error near the
        // peak grows as 1/m (the exponent's slope, docs). 1: rougher than that is no longer a highlight.
        {"m", 0.3, 0.02, 1.0, "roughness: RMS microfacet slope (Beckmann m; GGX alpha)"},
        {"f0", 0.04, 0.0, 1.0, "Fresnel reflectance at normal incidence (0.04: glass/plastic; 1: perfect mirror)"},
        // kd = 1 by default so the model is a complete plastic-like material (diffuse base + highlight); the
        // paper weights the two with d + s = 1, which ks = 1 - kd reproduces. kd = 0 isolates the lobe.
        {"kd", 1.0, 0.0, 1.0, "weight of the Lambert diffuse part (times the albedo)"},
        {"ks", 1.0, 0.0, 1.0,
         "weight of the specular part (times the specular colour); pi/4 = 0.785 gives today's 4 NoL NoV denominator"},
    };
    const PackFn pack = packer<CookTorranceConsts>([](const std::vector<double>& p) {
        const double m = p[0], f0 = p[1];
        CookTorranceConsts c{};
        c.m = float(m);
        c.f0 = float(f0);
        c.kd = float(p[2]);
        c.ks = float(p[3]);
        c.inv_m2 = float(1.0 / (m * m));
        c.inv_pi_m2 = float(1.0 / (M_PI * m * m));
        c.m2 = float(m * m);
        // The dielectric with normal-incidence reflectance f0 = ((eta - 1) / (eta + 1))^2 has
        // eta = (1 + sqrt f0) / (1 - sqrt f0); the kernel takes 1/eta, which is 0 (not infinite) at f0 = 1.
        const double s = std::sqrt(f0);
        const double inv_eta = (1.0 - s) / (1.0 + s);
        c.inv_eta = float(inv_eta);
        c.one_minus_inv_eta2 = float(1.0 - inv_eta * inv_eta);
        return c;
    });
    auto add = [&](const char* name, const char* summary, const char* eval, const char* source,
                   std::vector<PrecisionBound> precision) {
        ModelInfo m;
        m.name = name;
        m.family = "cook_torrance";
        m.summary = summary;
        m.source = source;
        m.header = "models/cook_torrance.cl";
        m.eval = eval;
        m.params = params;
        m.pack = pack;
        // D and G are symmetric in L and V, and F depends on VoH = LoH only, so f_r(L, V) = f_r(V, L).
        m.reciprocal = true;
        // Not at every parameter value: the 1982 pi (not 4) in the denominator lets the lobe reflect up to 4/pi
        // of the light at F = 1, and kd albedo is added on top of it (docs: white furnace table).
        m.energy_conserving = false;
        m.precision = std::move(precision);
        out.push_back(m);
    };
    add("cook_torrance", "Cook-Torrance 1982: kd albedo NoL + ks specular F_Schlick D_Beckmann G_VGroove / NoV",
        "cook_torrance_eval",
        "Cook & Torrance (1982) ACM ToG 1(1); Beckmann (1963); Schlick (1994); Blinn (1977); seed 004",
        // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
        {{"*", 3.80e-6, 1e-5, 3.80e-6, 1e-5}, {"m=0.02", 7.73e-4, 2e-3, 7.73e-4, 2e-3}});
    add("cook_torrance_ggx", "Cook-Torrance with the GGX (Trowbridge-Reitz) distribution in place of Beckmann",
        "cook_torrance_ggx_eval", "Walter et al. (2007) EGSR; Cook & Torrance (1982)",
        // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
        {{"*", 5.69e-6, 1.5e-5, 5.69e-6, 1.5e-5}, {"m=0.02", 1.51e-3, 4e-3, 1.51e-3, 4e-3}});
    add("cook_torrance_exact_fresnel", "Cook-Torrance with the exact dielectric Fresnel term (eta from f0) for Schlick",
        "cook_torrance_exact_fresnel_eval", "Cook & Torrance (1982), Fresnel equations for unpolarised light",
        // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
        {{"*", 3.64e-6, 1e-5, 3.64e-6, 1e-5}, {"m=0.02", 7.73e-4, 2e-3, 7.73e-4, 2e-3}});
    add("cook_torrance_seed004",
        "seed 004's Schlick read literally: (1 - theta)^5 with theta = acos(VoH) in radians (F = 1 at normal incidence)",
        "cook_torrance_seed004_eval", "seed 004 (lecture slides), as written",
        // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
        {{"*", 1.00e-5, 3e-5, 1.00e-5, 3e-5}, {"m=0.02", 7.82e-4, 2e-3, 7.82e-4, 2e-3}});
    // two chains a work-item where measuring each model at one and two found two faster (docs/speed.md,
    // "Two chains")
    use_two_chains(family, {"cook_torrance", "cook_torrance_exact_fresnel", "cook_torrance_seed004", "cook_torrance_ggx"});
    return family;
}

}  // namespace shadelab
