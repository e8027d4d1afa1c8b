// The Oren-Nayar family (kernels/models/oren_nayar.cl, docs/models/oren_nayar.md): parameters and the
// constants each kernel reads, computed once per material in double and stored as float.
#include <cmath>

#include "consts/oren_nayar.h"
#include "models/catalogue.hpp"

namespace shadelab {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kHalfPi = kPi / 2.0;

// The paper's qualitative-model coefficients (Oren & Nayar 1994), sigma in radians.
double qon_A(double sigma) {
    const double s2 = sigma * sigma;
    return 1.0 - 0.5 * s2 / (s2 + 0.33);
}
double qon_B(double sigma) {
    const double s2 = sigma * sigma;
    return 0.45 * s2 / (s2 + 0.09);
}

ParamSpec sigma_param(const std::string& doc) {
    return ParamSpec{"sigma", 0.3, 0.0, kHalfPi, doc, false};
}

// EON / Fujii constants (Portsmouth, Kutz, Hill 2025): c1 = 1/2 - 2/(3 pi), c2 = 2/3 - 28/(15 pi).
constexpr double kFonC1 = 0.5 - 2.0 / (3.0 * kPi);
constexpr double kFonC2 = 2.0 / 3.0 - 28.0 / (15.0 * kPi);

EonConsts eon_consts(const std::vector<double>& p) {
    const double r = p[0];
    const double AF = 1.0 / (1.0 + kFonC1 * r);
    EonConsts k{};
    k.AF = float(AF);
    k.r = float(r);
    k.Ebar = float(AF * (1.0 + kFonC2 * r));        // the FON average albedo
    k.k_ms = float(r * AF / (kFonC1 - kFonC2));     // f_ms scale: (1-E_o)(1-E_i)/(1-Ebar) = r AF (c1-g_o)(c1-g_i)/(c1-c2)
    k.c1 = float(kFonC1);
    return k;
}

// The paper's qualitative model's A and B (oren_nayar, oren_nayar_st, oren_nayar_blender).
OrenNayarConsts qon_consts(const std::vector<double>& p) {
    OrenNayarConsts k{};
    k.A = float(qon_A(p[0]));
    k.B = float(qon_B(p[0]));
    return k;
}

// A, the albedo term's factor and B of the forms matched to the full model (oren_nayar_seed001,
// oren_nayar_fujii_full): the seed's on.x, on.y, on.z and Fujii's "match full O-N" constants are the same.
OrenNayarAlbedoConsts albedo_term_consts(const std::vector<double>& p) {
    const double s2 = p[0] * p[0];
    OrenNayarAlbedoConsts k{};
    k.A = float(1.0 - 0.5 * s2 / (s2 + 0.33));
    k.A_rho = float(0.17 * s2 / (s2 + 0.13));
    k.B = float(0.45 * s2 / (s2 + 0.09));
    return k;
}

constexpr const char* kPaper = "Oren & Nayar (1994) Generalization of Lambert's Reflectance Model, SIGGRAPH";
constexpr const char* kSigmaDoc = "facet slope standard deviation, radians (0 = Lambert)";

ModelInfo base(const std::string& name, const std::string& summary, const std::string& source,
               const std::string& eval) {
    ModelInfo m;
    m.name = name;
    m.family = "oren_nayar";
    m.summary = summary;
    m.source = source;
    m.header = "models/oren_nayar.cl";
    m.eval = eval;
    return m;
}



ModelInfo oren_nayar_model() {
    ModelInfo m = base("oren_nayar", "paper's qualitative model: A + B max(0, cos dphi) sin(alpha) tan(beta)",
                       std::string(kPaper) + " (qualitative model); pbrt-v3 OrenNayar", "oren_nayar_eval");
    m.params = {sigma_param(kSigmaDoc)};
    m.pack = packer<OrenNayarConsts>(qon_consts);
    m.reciprocal = true;
    m.energy_conserving = false;   // directional albedo reaches 1.015 at grazing view, sigma ~ 0.2 (docs)
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 7.44e-7, 2e-6, 7.44e-7, 2e-6}};
    return m;
}

ModelInfo oren_nayar_st_model() {
    ModelInfo m = base("oren_nayar_st", "paper's qualitative model, trig-free: A + B max(0, s) / max(NoL, NoV)",
                       std::string(kPaper) + " (qualitative model, s/t form of Fujii 2013)", "oren_nayar_st_eval");
    m.params = {sigma_param(kSigmaDoc)};
    m.pack = packer<OrenNayarConsts>(qon_consts);
    m.reciprocal = true;
    m.energy_conserving = false;   // the same function as oren_nayar
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 7.44e-7, 2e-6, 7.44e-7, 2e-6}};
    return m;
}

ModelInfo oren_nayar_full_model() {
    ModelInfo m = base("oren_nayar_full", "paper's full model: C1, C2, C3 and the interreflection term",
                       std::string(kPaper) + " (functional approximation with interreflections)", "oren_nayar_full_eval");
    m.params = {sigma_param(kSigmaDoc)};
    m.pack = packer<OrenNayarFullConsts>([](const std::vector<double>& p) {
        const double s2 = p[0] * p[0];
        OrenNayarFullConsts k{};
        k.C1 = float(1.0 - 0.5 * s2 / (s2 + 0.33));
        k.C2_scale = float(0.45 * s2 / (s2 + 0.09));
        k.C3_scale = float(0.125 * s2 / (s2 + 0.09));
        k.L2_scale = float(0.17 * s2 / (s2 + 0.13));
        return k;
    });
    m.reciprocal = true;
    m.energy_conserving = false;   // the rho^2 interreflection term lifts it above 1 for albedo near 1
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {
        {"*", 7.74e-7, 2e-6, 7.74e-7, 2e-6},
        {"sigma=1.5708", 2.62e-5, 8e-5, 2.62e-5, 8e-5},
    };
    return m;
}

ModelInfo oren_nayar_seed001_model() {
    ModelInfo m = base("oren_nayar_seed001",
                       "seed 001 (Unity-style): A + albedo 0.17 r^2/(r^2+0.13) + B s/t, saturate(L.V)",
                       "seed 001 (lighting-models article); = Fujii 2013 matched to full O-N, but saturate(L.V)",
                       "oren_nayar_seed001_eval");
    m.params = {sigma_param("the seed's _Roughness (= sigma, radians)")};
    m.pack = packer<OrenNayarAlbedoConsts>(albedo_term_consts);
    m.reciprocal = true;
    m.energy_conserving = false;   // the albedo colour term adds energy (docs table)
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 7.71e-7, 2e-6, 7.71e-7, 2e-6}};
    return m;
}

ModelInfo oren_nayar_seed003_model() {
    ModelInfo m = base("oren_nayar_seed003",
                       "seed 003 (HLSL): PhiR = |Vt| |Lt| (product of lengths) in place of cos dphi",
                       "seed 003 (Oren-Nayar notes, HLSL listing)", "oren_nayar_seed003_eval");
    m.params = {ParamSpec{"roughness", 0.3, 0.0, kHalfPi,
                          "the listing's MaterialRoughness; squared inside, so it equals sigma (radians)", false}};
    m.pack = packer<OrenNayarConsts>([](const std::vector<double>& p) {
        const double R = std::pow(p[0], 2.0);   // Roughness = pow(MaterialRoughness, 2)
        OrenNayarConsts k{};
        k.A = float(1.0 - 0.5 * (R / (R + 0.33)));
        k.B = float(0.45 * (R / (R + 0.09)));
        return k;
    });
    m.reciprocal = true;
    m.energy_conserving = false;   // the unclamped, azimuth-free B term exceeds 1 (docs table)
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 8.46e-7, 2.5e-6, 8.46e-7, 2.5e-6}};
    return m;
}

ModelInfo oren_nayar_seed004_model() {
    ModelInfo m = base("oren_nayar_seed004",
                       "seed 004 (slides): A with 0.57, B term times unnormalised gamma = (Vt . Lt)",
                       "seed 004 (lecture slides 'Shaders', Oren Nayar formulas)", "oren_nayar_seed004_eval");
    m.params = {sigma_param("the slides' roughness (= sigma, radians)")};
    m.pack = packer<OrenNayarConsts>([](const std::vector<double>& p) {
        const double r2 = p[0] * p[0];
        OrenNayarConsts k{};
        k.A = float(1.0 - 0.5 * r2 / (r2 + 0.57));
        k.B = float(0.45 * r2 / (r2 + 0.09));
        return k;
    });
    m.reciprocal = true;
    m.energy_conserving = false;   // the A nearer 1 overshoots at grazing view for small sigma (docs)
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 7.95e-7, 2.5e-6, 7.95e-7, 2.5e-6}};
    return m;
}

ModelInfo oren_nayar_blender_model() {
    ModelInfo m = base("oren_nayar_blender", "Blender 2.4x OrenNayar_Diff: the paper's QON with beta * 0.95",
                       "Blender 2.4x source/blender/render/intern/source/shadeoutput.c, OrenNayar_Diff",
                       "oren_nayar_blender_eval");
    m.params = {ParamSpec{"sigma", 0.3, 0.0, kPi, "Blender's 'rough' (sigma, radians; Blender's UI range)", false}};
    m.pack = packer<OrenNayarConsts>(qon_consts);
    m.reciprocal = true;
    m.energy_conserving = false;   // 1.0036 at grazing view, sigma ~ 0.14: less than QON's 1.015 (docs)
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 7.88e-7, 3e-6, 7.88e-7, 3e-6}};   // 9.92e-7 with two atan2 and sin (before 2026-12-07)
    return m;
}

ModelInfo oren_nayar_fujii_model() {
    ModelInfo m = base("oren_nayar_fujii", "Fujii's improved O-N: (1 + sigma' s/t) / (1 + (1/2 - 2/(3 pi)) sigma')",
                       "Fujii (2013) A tiny improvement of Oren-Nayar reflectance model (mimosa-pudica.net)",
                       "oren_nayar_fujii_eval");
    m.params = {ParamSpec{"roughness", 0.5, 0.0, 1.0,
                          "Fujii's sigma': ratio of the non-diffuse to the diffuse term (0 = Lambert)", false}};
    m.pack = packer<OrenNayarConsts>([](const std::vector<double>& p) {
        const double A = 1.0 / (kPi + (kHalfPi - 2.0 / 3.0) * p[0]);
        OrenNayarConsts k{};
        k.A = float(kPi * A);
        k.B = float(kPi * p[0] * A);
        return k;
    });
    m.reciprocal = true;
    m.energy_conserving = true;    // normalised at NoV = 0, where its albedo is exactly 1 (docs)
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 2.42e-6, 7e-6, 2.42e-6, 7e-6}};
    return m;
}

ModelInfo oren_nayar_fujii_full_model() {
    ModelInfo m = base("oren_nayar_fujii_full",
                       "Fujii's s/t form with A, B matched to the full model (A has 0.17 albedo term)",
                       "Fujii (2013) A tiny improvement of Oren-Nayar reflectance model, 'match full O-N'",
                       "oren_nayar_fujii_full_eval");
    m.params = {sigma_param(kSigmaDoc)};
    m.pack = packer<OrenNayarAlbedoConsts>(albedo_term_consts);
    m.reciprocal = true;
    m.energy_conserving = false;   // Fujii: violated for albedo > 0.97
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 7.71e-7, 2e-6, 7.71e-7, 2e-6}};
    return m;
}

ModelInfo eon_model() {
    ModelInfo m = base("eon", "energy-preserving Oren-Nayar: FON + multiple-scattering lobe, exact E_FON",
                       "Portsmouth, Kutz, Hill (2025) EON: A practical energy-preserving rough diffuse BRDF, "
                       "JCGT 14(1) (arXiv 2410.18026); OpenPBR",
                       "eon_eval");
    m.params = {ParamSpec{"roughness", 0.5, 0.0, 1.0, "EON's r (Fujii's sigma'), 0 = Lambert", false}};
    m.pack = packer<EonConsts>(eon_consts);
    m.reciprocal = true;
    m.energy_conserving = true;    // white furnace 1 to the integration error (docs)
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 2.07e-6, 6e-6, 2.07e-6, 6e-6}};
    return m;
}

ModelInfo eon_approx_model() {
    ModelInfo m = base("eon_approx", "EON with the paper's polynomial fit of the FON albedo",
                       "Portsmouth, Kutz, Hill (2025) EON, E_FON_approx (arXiv 2410.18026)", "eon_approx_eval");
    m.params = {ParamSpec{"roughness", 0.5, 0.0, 1.0, "EON's r (Fujii's sigma'), 0 = Lambert", false}};
    m.pack = packer<EonConsts>(eon_consts);
    m.reciprocal = true;
    m.energy_conserving = false;   // the fit's error lifts the furnace to 1.00015 near 82 deg (docs)
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 2.14e-6, 6e-6, 2.14e-6, 6e-6}};
    return m;
}

}  // namespace

// The family as it registers itself (host/models/catalogue.hpp, ModelFamily): rank 60 in the catalogue.
ModelFamily register_oren_nayar_family() {
    ModelFamily family{"oren_nayar", 60, "Oren-Nayar", "docs/models/oren_nayar.md", {}};
    family.models = {
        oren_nayar_model(),
        oren_nayar_st_model(),
        oren_nayar_full_model(),
        oren_nayar_seed001_model(),
        oren_nayar_seed003_model(),
        oren_nayar_seed004_model(),
        oren_nayar_blender_model(),
        oren_nayar_fujii_model(),
        oren_nayar_fujii_full_model(),
        eon_model(),
        eon_approx_model(),
    };
    // two chains a work-item where measuring each model at one and two found two faster (docs/speed.md,
    // "Two chains")
    use_two_chains(family, {"oren_nayar_blender"});
    // and on AVX2 hosts every other model of the family, where two chains gained 1.13-1.58x (the median of
    // three alternating rounds at 1M and 16M fragments, both modes, an AMD Zen 3: docs/speed.md, "Chains on AVX2")
    use_two_chains_on_avx2(family, {"oren_nayar", "oren_nayar_st", "oren_nayar_full", "oren_nayar_seed001",
                                    "oren_nayar_seed003", "oren_nayar_seed004", "oren_nayar_fujii",
                                    "oren_nayar_fujii_full", "eon", "eon_approx"});
    // and eon_approx at sixteen lanes there, two chains of them (1.15x at 1M and 1.20x at 16M fragments, the
    // median of eight alternating rounds: docs/speed.md, "Sixteen lanes on AVX2")
    use_sixteen_lanes_on_avx2(family, {"eon_approx"}, 2);
    return family;
}

}  // namespace shadelab
