// The wrap-lighting family (kernels/models/wrap.cl, docs/models/wrap.md): half-Lambert, the seed's
// squared diffuse wrap and Filament's energy-conserving wrap. Constants are packed once per material here.
#include "consts/wrap.h"
#include "models/catalogue.hpp"
#include "models/model_info.hpp"

namespace shadelab {

namespace {

ModelInfo base(const char* name, const char* summary, const char* source, const char* eval) {
    ModelInfo m = model_info("models/wrap.cl", name, summary, source, eval);
    // None of the wrap terms is reciprocal: value / NoL = g(NoL) / NoL is not symmetric in L and V.
    m.reciprocal = false;
    m.normals_only = true;   // every wrap term is a function of NoL alone
    return m;
}

const char* kValveSource =
    "Mitchell, McTaggart, Green (2006) Shading in Valve's Source Engine, SIGGRAPH course (Half-Life, 1998); seed 001";

ParamSpec wrap_value_param() {
    return {"wrap_value", 0.5, 0.5, 1.0,
            "seed 001's wrapValue a in (NoL a + 1 - a)^2: 0.5 half-Lambert (light wraps to NoL = -1), "
            "1 no wrap (max(0, NoL)^2)"};
}

WrapConsts wrap_consts(const std::vector<double>& p) {
    WrapConsts k{};
    k.a = float(p[0]);
    k.one_minus_a = float(1.0 - p[0]);
    return k;
}

}  // namespace

// The family as it registers itself (host/models/catalogue.hpp, ModelFamily): rank 20 in the catalogue.
ModelFamily register_wrap_family() {
    ModelFamily family{"wrap", 20, "Half-Lambert and wrap", "docs/models/wrap.md", {}};
    std::vector<ModelInfo>& out = family.models;
    {
        ModelInfo m = base("half_lambert", "Valve's half-Lambert: albedo * ((NoL + 1) / 2)^2, NoL unclamped (0 at NoL = -1)",
                           kValveSource, "half_lambert_eval");
        m.energy_conserving = false;   // directional albedo 7/6 (hemisphere), 4/3 (sphere)
        // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
        m.precision = {{"*", 2.50e-7, 8e-7, 2.50e-7, 8e-7}};
        out.push_back(m);
    }
    {
        ModelInfo m = base("half_lambert_seed001",
                           "seed 001's half-Lambert: NoL clamped first, albedo * ((max(0, NoL) + 1) / 2)^2 (0.25 behind)",
                           "seed 001 (its code clamps NoL before the mapping); Valve's form is half_lambert",
                           "half_lambert_seed001_eval");
        m.energy_conserving = false;   // 7/6 over the hemisphere, 5/3 over the sphere
        // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
        m.precision = {{"*", 2.50e-7, 8e-7, 2.50e-7, 8e-7}};
        out.push_back(m);
    }
    {
        ModelInfo m = base("wrap", "seed 001's diffuse wrap: albedo * max(0, NoL a + 1 - a)^2, NoL unclamped, a in [0.5, 1]",
                           "seed 001 (Half-Lambert / diffuse wrap); a = 0.5 is Valve's half-Lambert", "wrap_eval");
        m.params = {wrap_value_param()};
        m.pack = packer<WrapConsts>(wrap_consts);
        m.energy_conserving = false;   // hemisphere 2 (1 - (1 - a)^3) / (3 a): 7/6 at a = 0.5
        // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
        m.precision = {{"*", 1.42e-6, 4e-6, 1.42e-6, 4e-6}};
        out.push_back(m);
    }
    {
        ModelInfo m = base("wrap_seed001", "seed 001's wrap with its NoL clamp: albedo * (max(0, NoL) a + 1 - a)^2",
                           "seed 001 (clamped NoL as in its half-Lambert code); the reference is wrap",
                           "wrap_seed001_eval");
        m.params = {wrap_value_param()};
        m.pack = packer<WrapConsts>(wrap_consts);
        m.energy_conserving = false;
        // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
        m.precision = {{"*", 1.42e-6, 4e-6, 1.42e-6, 4e-6}};
        out.push_back(m);
    }
    {
        ModelInfo m = base("wrap_energy", "energy-conserving wrap: albedo * saturate((NoL + w) / (1 + w)^2), w in [0, 1]",
                           "Filament (google/filament, surface_brdf.fs Fd_Wrap); linear wrap of Green (2004) GPU Gems ch. 16",
                           "wrap_energy_eval");
        m.params = {{"w", 0.5, 0.0, 1.0,
                     "wrap amount: 0 Lambert, 1 light wraps to NoL = -1; the terminator is at NoL = -w"}};
        m.pack = packer<WrapEnergyConsts>([](const std::vector<double>& p) {
            WrapEnergyConsts k{};
            k.w = float(p[0]);
            k.inv_sq = float(1.0 / ((1.0 + p[0]) * (1.0 + p[0])));
            return k;
        });
        m.energy_conserving = true;   // sphere: exactly 1; hemisphere: (1 + 2w) / (1 + w)^2 <= 1
        // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
        m.precision = {{"*", 7.33e-7, 2e-6, 7.33e-7, 2e-6}};
        out.push_back(m);
    }
    // two chains a work-item where measuring each model at one and two found two faster (docs/speed.md,
    // "Two chains")
    use_two_chains(family, {"half_lambert_seed001", "wrap", "wrap_energy", "wrap_seed001"});
    return family;
}

}  // namespace shadelab
