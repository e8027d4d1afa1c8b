// The Phong family (kernels/models/phong.cl, docs/models/phong.md): Phong and Blinn-Phong as references
// (highlight gated to NoL > 0), as seed 001 wrote them (ungated, _SpecularGloss / _SpecularPower), and
// energy-normalised. Constants (exponent conventions, normalisation factors) are packed once here.
#include <cmath>

#include "consts/phong.h"
#include "models/catalogue.hpp"
#include "models/model_info.hpp"

namespace shadelab {

namespace {

ModelInfo base(const char* name, const char* summary, const char* source, const char* eval) {
    return model_info("models/phong.cl", name, summary, source, eval);
}

const char* kPhong = "Phong (1975) Illumination for computer generated pictures, CACM 18(6); seed 001";
const char* kBlinn = "Blinn (1977) Models of light reflection for computer synthesized pictures, SIGGRAPH; seed 001";

ParamSpec exponent_param(double def) {
    return {"n", def, 0.0, 10000.0,
            "cosine-power exponent (shininess); 0 is the hemisphere around the peak (x^0 = 1 for x > 0, 0 for x <= 0)"};
}
ParamSpec ks_param() {
    return {"ks", 1.0, 0.0, 10.0, "specular intensity (a multiplier of the specular colour, seed 001's _SpecularPower)"};
}
ParamSpec ks_fraction_param() {
    return {"ks", 0.5, 0.0, 1.0,
            "specular fraction: the lobe is weighted by ks and the diffuse by 1 - ks (kd + ks <= 1 built in)"};
}
ParamSpec gloss_param() {
    return {"gloss", 128.0, 0.0, 40000.0, "seed 001's _SpecularGloss"};
}
ParamSpec specular_power_param() {
    return {"specular_power", 1.0, 0.0, 10.0, "seed 001's _SpecularPower: a multiplier of the specular colour"};
}

// Exact Blinn-Phong normalisation in the value convention (pi * f_r): directional albedo 1 at V = N.
// Giesen (2009), "Derivation of Phong and Blinn-Phong BRDF normalization factors".
double blinn_phong_exact_norm(double n) { return (n + 2.0) * (n + 4.0) / (8.0 * (std::exp2(-0.5 * n) + n)); }

// Parameters (n, ks) as they are.
PhongConsts phong_consts(const std::vector<double>& p) {
    PhongConsts k{};
    k.n = float(p[0]);
    k.ks = float(p[1]);
    return k;
}

// Parameters (n, ks) of an energy-normalised form whose lobe has the normalisation factor `norm`.
PhongNormalizedConsts normalized_consts(const std::vector<double>& p, double norm) {
    PhongNormalizedConsts k{};
    k.n = float(p[0]);
    k.kd = float(1.0 - p[1]);
    k.lobe_scale = float(p[1] * norm);
    return k;
}

ModelInfo phong_model() {
    ModelInfo m = base("phong", "Phong: albedo max(0, NoL) + ks specular [NoL > 0] max(0, RoV)^n", kPhong, "phong_eval");
    m.params = {exponent_param(32.0), ks_param()};
    m.pack = packer<PhongConsts>(phong_consts);
    m.reciprocal = false;          // value / NoL = albedo + ks RoV^n / NoL
    m.energy_conserving = false;   // un-normalised lobe added to a full Lambert term
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {
        {"*", 9.53e-6, 3e-5, 9.53e-6, 3e-5},
        {"n=10000", 2.19e-3, 6e-3, 2.19e-3, 6e-3},
    };
    return m;
}

ModelInfo phong_seed001_model() {
    ModelInfo m = base("phong_seed001",
                       "seed 001's Phong: albedo max(0, NoL) + specular_power specular max(0, RoV)^(gloss/4), ungated",
                       "seed 001 (Phong lighting); the reference is phong (gated; n = gloss / 4)", "phong_seed001_eval");
    m.params = {gloss_param(), specular_power_param()};
    m.pack = packer<PhongConsts>([](const std::vector<double>& p) {
        PhongConsts k{};
        k.n = float(p[0] / 4.0);   // seed 001: pow(RdotV, _SpecularGloss / 4)
        k.ks = float(p[1]);
        return k;
    });
    m.reciprocal = false;
    m.energy_conserving = false;
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {
        {"*", 9.53e-6, 3e-5, 9.53e-6, 3e-5},
        {"gloss=40000", 2.19e-3, 6e-3, 2.19e-3, 6e-3},
    };
    return m;
}

ModelInfo phong_normalized_model() {
    ModelInfo m = base("phong_normalized",
                       "energy-normalised Phong: (1-ks) albedo NoL + ks specular (n+2)/2 RoV^n NoL (pi f_r NoL)",
                       "Lewis (1994) Making shaders more physically plausible; Lafortune & Willems (1994) modified Phong",
                       "phong_normalized_eval");
    m.params = {exponent_param(32.0), ks_fraction_param()};
    m.pack = packer<PhongNormalizedConsts>([](const std::vector<double>& p) {
        return normalized_consts(p, (p[0] + 2.0) / 2.0);
    });
    m.reciprocal = true;          // RoV = R(L).V = R(V).L and value / NoL has no other L, V asymmetry
    m.energy_conserving = true;   // lobe albedo 1 at V = N, less elsewhere; (1 - ks) + ks <= 1
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {
        {"*", 1.33e-5, 4e-5, 1.53e-5, 4e-5},
        {"n=10000", 3.10e-3, 9e-3, 3.10e-3, 9e-3},
    };
    return m;
}

ModelInfo blinn_phong_model() {
    ModelInfo m = base("blinn_phong", "Blinn-Phong: albedo max(0, NoL) + ks specular [NoL > 0] max(0, NoH)^n", kBlinn,
                       "blinn_phong_eval");
    m.params = {exponent_param(128.0), ks_param()};
    m.pack = packer<PhongConsts>(phong_consts);
    m.reciprocal = false;          // value / NoL = albedo + ks NoH^n / NoL: reciprocal only as f_r (normalized)
    m.energy_conserving = false;
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {
        {"*", 2.26e-5, 6e-5, 2.26e-5, 6e-5},
        {"n=10000", 9.40e-4, 3e-3, 9.40e-4, 3e-3},
    };
    return m;
}

ModelInfo blinn_phong_seed001_model() {
    ModelInfo m = base("blinn_phong_seed001",
                       "seed 001's Blinn-Phong: albedo max(0, NoL) + specular_power specular max(0, NoH)^gloss, ungated",
                       "seed 001 (Blinn-Phong lighting; its N.H variable is named NdotV); the reference is blinn_phong",
                       "blinn_phong_seed001_eval");
    m.params = {gloss_param(), specular_power_param()};
    m.pack = packer<PhongConsts>(phong_consts);   // seed 001: pow(NdotH, _SpecularGloss), no / 4
    m.reciprocal = false;
    m.energy_conserving = false;
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {
        {"*", 2.26e-5, 6e-5, 2.26e-5, 6e-5},
        {"gloss=40000", 1.09e-3, 3e-3, 1.09e-3, 3e-3},
    };
    return m;
}

ModelInfo blinn_phong_normalized_model() {
    ModelInfo m = base("blinn_phong_normalized",
                       "energy-normalised Blinn-Phong, exact factor: (1-ks) albedo NoL + ks specular K_n NoH^n NoL",
                       "Blinn (1977); normalisation K_n = (n+2)(n+4) / (8 (2^(-n/2) + n)): Giesen (2009)",
                       "blinn_phong_normalized_eval");
    m.params = {exponent_param(128.0), ks_fraction_param()};
    m.pack = packer<PhongNormalizedConsts>([](const std::vector<double>& p) {
        return normalized_consts(p, blinn_phong_exact_norm(p[0]));
    });
    m.reciprocal = true;          // H, hence NoH, is symmetric in L and V
    m.energy_conserving = true;   // lobe albedo exactly 1 at V = N, less elsewhere (tests/test_phong.cpp)
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {
        {"*", 2.38e-5, 7e-5, 2.38e-5, 7e-5},
        {"n=10000", 1.59e-3, 5e-3, 1.59e-3, 5e-3},
    };
    return m;
}

ModelInfo blinn_phong_normalized_approx_model() {
    ModelInfo m = base("blinn_phong_normalized_approx",
                       "Blinn-Phong with the common (n+8)/(8 pi) factor: (1-ks) albedo NoL + ks specular (n+8)/8 NoH^n NoL",
                       "Akenine-Moller, Haines, Hoffman (2008) Real-Time Rendering 3rd ed.; exact factor: Giesen (2009)",
                       "blinn_phong_normalized_approx_eval");
    m.params = {exponent_param(128.0), ks_fraction_param()};
    m.pack = packer<PhongNormalizedConsts>([](const std::vector<double>& p) {
        return normalized_consts(p, (p[0] + 8.0) / 8.0);
    });
    m.reciprocal = true;
    m.energy_conserving = false;   // (n+8)/8 exceeds the exact factor: lobe albedo up to 1.074 (n = 11)
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {
        {"*", 2.38e-5, 7e-5, 2.38e-5, 7e-5},
        {"n=10000", 1.59e-3, 5e-3, 1.59e-3, 5e-3},
    };
    return m;
}

}  // namespace

// The family as it registers itself (host/models/catalogue.hpp, ModelFamily): rank 30 in the catalogue.
ModelFamily register_phong_family() {
    ModelFamily family{"phong", 30, "Phong and Blinn-Phong", "docs/models/phong.md", {}};
    family.models = {
        phong_model(),
        phong_seed001_model(),
        phong_normalized_model(),
        blinn_phong_model(),
        blinn_phong_seed001_model(),
        blinn_phong_normalized_model(),
        blinn_phong_normalized_approx_model(),
    };
    // two chains a work-item where measuring each model at one and two found two faster (docs/speed.md,
    // "Two chains")
    use_two_chains(family, {"phong", "phong_normalized", "phong_seed001", "blinn_phong", "blinn_phong_normalized",
                            "blinn_phong_normalized_approx", "blinn_phong_seed001"});
    // every model of the family raises a cosine to a power: fast mode's own pow (ModelInfo::fast_differs)
    use_fast_pow(family, {"phong", "phong_seed001", "phong_normalized", "blinn_phong", "blinn_phong_seed001",
                          "blinn_phong_normalized", "blinn_phong_normalized_approx"});
    return family;
}

}  // namespace shadelab
