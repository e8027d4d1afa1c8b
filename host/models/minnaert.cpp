// The Minnaert family (kernels/models/minnaert.cl, docs/models/minnaert.md): Minnaert's 1941 lunar law and
// the shader forms taken from it. Constants are packed once per material here; the kernels only read them.
#include "consts/minnaert.h"
#include "models/catalogue.hpp"
#include "models/model_info.hpp"

namespace shadelab {

namespace {

// Limb guard of the 1941-law models (see Minnaert_taper in the kernel): cosines below this are faded to 0.
// Only needed where the law diverges (k < 1); for k >= 1 the law is used unguarded (k = 1 stays Lambert).
constexpr double kMinnaertLimbEps = 1e-3;

MinnaertConsts limb_guard_consts(const std::vector<double>& p) {
    const double k = p[0];
    const double eps = k < 1.0 ? kMinnaertLimbEps : 0.0;
    MinnaertConsts c{};
    c.k_minus_1 = float(k - 1.0);
    c.eps = float(eps);
    c.inv_eps = eps > 0.0 ? float(1.0 / eps) : 0.0f;
    return c;
}

ModelInfo base(const char* name, const char* summary, const char* source, const char* eval) {
    return model_info("models/minnaert.cl", name, summary, source, eval);
}

ModelInfo minnaert_1941_model() {
    ModelInfo m = base("minnaert_1941", "Minnaert's lunar law: albedo * NoL^k * NoV^(k-1) (k = 1 Lambert)",
                       "Minnaert (1941) The Reciprocity Principle in Lunar Photometry, ApJ 93:403; seed 002",
                       "minnaert_1941_eval");
    m.params = {{"k", 0.7, 0.0, 2.0,
                 "Minnaert limb-darkening exponent: 1 Lambert, 0.5 flat disc at full phase, < 1 brightens "
                 "towards the limb (guarded below NoL, NoV = 1e-3)"}};
    m.pack = packer<MinnaertConsts>(limb_guard_consts);
    m.reciprocal = true;           // f_r = (albedo/pi) (NoL NoV)^(k-1), guard symmetric
    m.energy_conserving = false;   // directional albedo 2/(k+1) NoV^(k-1): > 1 for k < 1
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 1.33e-6, 4e-6, 6.64e-6, 2e-5}};   // fast: sl_fast_pow, 2026-12-05 (was 1.33e-6)
    return m;
}

ModelInfo minnaert_unity_model() {
    ModelInfo m = base("minnaert_unity", "seeds' Minnaert: albedo * saturate(NoL * (NoL NoV)^k) (k = 0 Lambert)",
                       "seeds 000 (Shader Story) and 001 (Unity-style pseudo-code); k_1941 = k + 1",
                       "minnaert_unity_eval");
    m.params = {{"k", 0.3, -1.0, 1.0,
                 "the seeds' _Roughness: 1941 exponent minus 1; 0 Lambert, > 0 darkens the limb, < 0 "
                 "brightens it (clipped at 1 by the saturate)"}};
    m.pack = packer<MinnaertUnityConsts>([](const std::vector<double>& p) {
        MinnaertUnityConsts k{};
        k.k = float(p[0]);
        return k;
    });
    // Reciprocal only for k >= 0; the saturate's clip breaks it for k < 0, so not over the whole range
    // (tests/test_minnaert.cpp checks both sides).
    m.reciprocal = false;
    m.energy_conserving = false;   // directional albedo 2/(2+k) at V = N: up to 2 for k = -1
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 1.33e-6, 4e-6, 6.25e-6, 2e-5}};   // fast: as minnaert_1941
    return m;
}

ModelInfo minnaert_blender_model() {
    ModelInfo m = base("minnaert_blender",
                       "Blender 2.4x Minnaert: NoL max(NoV NoL, 0.1)^(d-1) for d <= 1, NoL (1.001 - NoV)^(d-1) above",
                       "Blender internal renderer, shadeoutput.c Minnaert_Diff (2005-2019); seed 002",
                       "minnaert_blender_eval");
    m.params = {{"darkness", 1.0, 0.0, 2.0,
                 "Blender's Minnaert 'darkness' d: 1 Lambert; < 1 the 1941 law with k = d (clamped at "
                 "NoV NoL = 0.1); > 1 darkens where the surface faces the viewer"}};
    m.pack = packer<MinnaertBlenderConsts>([](const std::vector<double>& p) {
        MinnaertBlenderConsts k{};
        k.d_minus_1 = float(p[0] - 1.0);
        k.real_branch = p[0] <= 1.0 ? 1.0f : 0.0f;   // Blender: if (darkness <= 1) "The Real model" else "Nvidia model"
        return k;
    });
    // Reciprocal only for d <= 1 (max(NoV NoL, 0.1)^(d-1) is symmetric); not for d > 1, so not over the
    // whole range (tests/test_minnaert.cpp checks both sides).
    m.reciprocal = false;
    m.energy_conserving = false;   // d < 1 multiplies Lambert by up to 0.1^(d-1) = 10
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 7.33e-7, 2e-6, 6.64e-6, 2e-5}};   // fast: as minnaert_1941
    return m;
}

ModelInfo minnaert_b_model() {
    ModelInfo m = base("minnaert_b", "MinnaertB: albedo * NoL * NoL^k * (1 - NoV)^(1-k) (velvet-like, never Lambert)",
                       "seed 002 (MinnaertB as quoted there from a course page)", "minnaert_b_eval");
    m.params = {{"k", 0.7, 0.0, 1.0,
                 "MinnaertB exponent: light falloff NoL^(1+k), view factor (1 - NoV)^(1-k) (k = 1: NoL^2)"}};
    m.pack = packer<MinnaertBConsts>([](const std::vector<double>& p) {
        MinnaertBConsts k{};
        k.k = float(p[0]);
        k.one_minus_k = float(1.0 - p[0]);
        return k;
    });
    m.reciprocal = false;          // NoL^k (1 - NoV)^(1-k) is not symmetric
    m.energy_conserving = true;    // value <= albedo * NoL everywhere: never brighter than Lambert
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 1.42e-6, 4e-6, 9.14e-6, 2.5e-5}};   // fast: as minnaert_1941 (two powers)
    return m;
}

ModelInfo minnaert_normalized_model() {
    ModelInfo m = base("minnaert_normalized",
                       "normalised Minnaert BRDF: albedo * (k+1)/2 * NoL^k * NoV^(k-1) (albedo 1 at normal incidence)",
                       "Minnaert (1941) ApJ 93:403, scaled by (k+1)/2 so the directional albedo at normal "
                       "incidence is the albedo",
                       "minnaert_normalized_eval");
    m.params = {{"k", 0.7, 0.0, 2.0,
                 "Minnaert exponent as in minnaert_1941; (k+1)/2 normalises normal incidence only"}};
    m.pack = packer<MinnaertNormalizedConsts>([](const std::vector<double>& p) {
        const MinnaertConsts guard = limb_guard_consts(p);
        MinnaertNormalizedConsts k{};
        k.k_minus_1 = guard.k_minus_1;
        k.eps = guard.eps;
        k.inv_eps = guard.inv_eps;
        k.norm = float((p[0] + 1.0) / 2.0);
        return k;
    });
    m.reciprocal = true;
    m.energy_conserving = false;   // directional albedo mu^(k-1): > 1 at oblique incidence for k < 1
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 1.39e-6, 4e-6, 6.64e-6, 2e-5}};   // fast: as minnaert_1941
    return m;
}

}  // namespace

// The family as it registers itself (host/models/catalogue.hpp, ModelFamily): rank 50 in the catalogue.
ModelFamily register_minnaert_family() {
    ModelFamily family{"minnaert", 50, "Minnaert", "docs/models/minnaert.md", {}};
    family.models = {
        minnaert_1941_model(),
        minnaert_unity_model(),
        minnaert_blender_model(),
        minnaert_b_model(),
        minnaert_normalized_model(),
    };
    // two chains a work-item where measuring each model at one and two found two faster (docs/speed.md,
    // "Two chains")
    use_two_chains(family, {"minnaert_1941", "minnaert_b", "minnaert_blender", "minnaert_normalized"});
    // and on AVX2 hosts minnaert_unity too (1.21x at 1M and at 16M fragments: docs/speed.md, "Chains on AVX2")
    use_two_chains_on_avx2(family, {"minnaert_unity"});
    // every model of the family is a power law: fast mode's own pow (ModelInfo::fast_differs)
    use_fast_pow(family, {"minnaert_1941", "minnaert_unity", "minnaert_blender", "minnaert_b", "minnaert_normalized"});
    return family;
}

}  // namespace shadelab
