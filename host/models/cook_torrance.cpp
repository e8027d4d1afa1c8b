// Cook-Torrance family registration: parameters and the host-computed constants (kernels/models/cook_torrance.cl).
#include <cmath>

#include "models/catalogue.hpp"

namespace shadelab {

void register_cook_torrance_family(std::vector<ModelInfo>& out) {
    const std::vector<ParamSpec> params = {
        {"m", 0.3, 0.02, 1.0, "roughness: RMS microfacet slope (Beckmann m; GGX alpha)"},
        {"f0", 0.04, 0.0, 0.99, "Fresnel reflectance at normal incidence (0.04: glass/plastic)"},
        {"kd", 1.0, 0.0, 1.0, "weight of the Lambert diffuse term (albedo)"},
        {"ks", 1.0, 0.0, 1.0, "weight of the specular term (specular colour)"},
    };
    auto pack = [](const std::vector<double>& p, float* c) {
        const double m = p[0], f0 = p[1];
        c[0] = float(m);
        c[1] = float(f0);
        c[2] = float(p[2]);
        c[3] = float(p[3]);
        c[4] = float(1.0 / (m * m));
        c[5] = float(1.0 / (M_PI * m * m));
        const double s = std::sqrt(f0);
        c[6] = float((1.0 + s) / (1.0 - s));   // the dielectric's index from f0
    };
    auto add = [&](const char* name, const char* summary, const char* eval, const char* source) {
        ModelInfo m;
        m.name = name;
        m.family = "cook_torrance";
        m.summary = summary;
        m.source = source;
        m.header = "models/cook_torrance.cl";
        m.eval = eval;
        m.params = params;
        m.pack = pack;
        m.reciprocal = true;            // D, G symmetric in L and V; F depends on VoH = LoH
        m.energy_conserving = false;    // kd albedo + the specular lobe can exceed 1; V-groove G does not conserve
        out.push_back(m);
    };
    add("cook_torrance", "Cook-Torrance: kd albedo NoL + ks specular F_Schlick D_Beckmann G_VGroove / NoV",
        "cook_torrance_eval", "Cook & Torrance (1982) ACM ToG 1(1); Beckmann (1963); Schlick (1994); seed 004");
    add("cook_torrance_ggx", "Cook-Torrance with the GGX (Trowbridge-Reitz) distribution in place of Beckmann",
        "cook_torrance_ggx_eval", "Walter et al. (2007) EGSR; Cook & Torrance (1982)");
    add("cook_torrance_exact_fresnel", "Cook-Torrance with the exact dielectric Fresnel term (eta from f0)",
        "cook_torrance_exact_fresnel_eval", "Cook & Torrance (1982), Fresnel equations for unpolarised light");
    add("cook_torrance_seed004", "seed 004's Schlick read literally: (1 - theta)^5 with theta = acos(VoH) in radians",
        "cook_torrance_seed004_eval", "seed 004 (lecture slides), as written");
}

}  // namespace shadelab
