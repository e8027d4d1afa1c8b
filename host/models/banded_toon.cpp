// The banded / toon family (kernels/models/banded_toon.cl, docs/models/banded_toon.md): banded Lambert
// (NoL rounded to steps levels), seed 001's literal banding formula, and the toon shader of seed 004.
// Constants are packed once per material here.
#include <algorithm>
#include <cfloat>
#include <string>

#include "core/error.hpp"
#include "consts/banded_toon.h"
#include "models/catalogue.hpp"
#include "models/model_info.hpp"

namespace shadelab {

namespace {

ModelInfo base(const char* name, const char* summary, const char* source, const char* eval) {
    ModelInfo m = model_info("models/banded_toon.cl", name, summary, source, eval);
    m.reciprocal = false;   // value / NoL is a function of NoL alone (plus, for toon, a quantised highlight)
    return m;
}

// Toon parameters in declared order (packed into ToonConsts, kernels/consts/banded_toon.h).
enum ToonParam { kN, kWidth, kDt1, kDt2, kDt3, kDl0, kDl1, kDl2, kDl3, kSt1, kSt2, kSl0, kSl1, kSl2, kToonParams };

void require_ascending(double a, double b, const char* na, const char* nb) {
    if (a > b)
        throw Error(std::string("model 'toon': threshold ") + na + " (" + std::to_string(a) + ") must not exceed " + nb +
                    " (" + std::to_string(b) + "): thresholds are ascending");
}

ModelInfo banded_model() {
    ModelInfo m = base("banded", "banded Lambert: albedo * floor(max(0, NoL) steps + 1/2) / steps",
                       "seed 001 (banded lighting), with _LightSteps read as the band count its author meant",
                       "banded_eval");
    m.normals_only = true;
    m.params = {{"steps", 4.0, 1.0, 256.0,
                 "number of lit bands: NoL is rounded to multiples of 1/steps (levels 0, 1/steps, ..., 1)", true}};
    m.pack = packer<BandedConsts>([](const std::vector<double>& p) {
        BandedConsts k{};
        k.steps = float(p[0]);
        k.inv_steps = float(1.0 / p[0]);
        return k;
    });
    m.energy_conserving = true;   // 2 * integral of round(x s)/s over [0, 1] is exactly 1 for every s
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 7.06e-8, 2e-7, 7.06e-8, 2e-7}};
    return m;
}

ModelInfo banded_seed001_model() {
    ModelInfo m = base("banded_seed001",
                       "seed 001's banding as written: floor((NoL 256 + t/2) / t) t/256 (t = _LightSteps, a step in 1/256)",
                       "seed 001 (banded lighting) literally; the intended model is banded (t = 256 / steps)",
                       "banded_seed001_eval");
    m.normals_only = true;
    m.params = {{"light_steps", 64.0, 1.0, 256.0,
                 "seed 001's _LightSteps: the band step in units of 1/256 (64 gives 4 lit bands)", true}};
    m.pack = packer<BandedSeed001Consts>([](const std::vector<double>& p) {
        BandedSeed001Consts k{};
        k.t = float(p[0]);
        k.half_t = float(p[0] / 2.0);     // the seed's lightBandsAdditive
        k.t_256 = float(p[0] / 256.0);    // the seed's lightBandsMultiplier
        return k;
    });
    // Directional albedo 1 where t divides 256 and below 1 otherwise (min 0.89 at t = 171), computed
    // band by band for every t in tests/test_banded_toon.cpp, although single levels can exceed 1.
    m.energy_conserving = true;
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 7.06e-8, 2e-7, 7.06e-8, 2e-7}};
    return m;
}

ModelInfo toon_model() {
    ModelInfo m = base("toon",
                       "toon: NoL quantised to 4 levels, Blinn-Phong NoH^n to 3, optional smoothstep edges",
                       "seed 004 (toon shader); Lake et al. (2000) Stylized rendering techniques for scalable "
                       "real-time 3D animation, NPAR",
                       "toon_eval");
    m.params.resize(kToonParams);
    m.params[kN] = {"n", 64.0, 0.0, 10000.0, "Blinn-Phong exponent of the highlight intensity max(0, NoH)^n"};
    // Default 0.02: a slightly soft edge, so bands do not alias into stair steps in renders; 0 gives
    // seed 004's hard quantisation exactly.
    m.params[kWidth] = {"width", 0.02, 0.0, 0.5,
                        "band-edge smoothing: each edge is a smoothstep over [t - width/2, t + width/2]; 0 hard"};
    m.params[kDt1] = {"diffuse_t1", 0.0, -1.0, 1.0, "NoL threshold between diffuse levels 0 and 1"};
    m.params[kDt2] = {"diffuse_t2", 0.35, -1.0, 1.0, "NoL threshold between diffuse levels 1 and 2"};
    m.params[kDt3] = {"diffuse_t3", 0.7, -1.0, 1.0, "NoL threshold between diffuse levels 2 and 3"};
    m.params[kDl0] = {"diffuse_l0", 0.0, 0.0, 1.0, "diffuse level below diffuse_t1 (times albedo)"};
    m.params[kDl1] = {"diffuse_l1", 0.3, 0.0, 1.0, "diffuse level 1"};
    m.params[kDl2] = {"diffuse_l2", 0.6, 0.0, 1.0, "diffuse level 2"};
    m.params[kDl3] = {"diffuse_l3", 1.0, 0.0, 1.0, "diffuse level above diffuse_t3"};
    m.params[kSt1] = {"spec_t1", 0.5, 0.0, 1.0, "highlight threshold (on max(0, NoH)^n) between levels 0 and 1"};
    m.params[kSt2] = {"spec_t2", 0.9, 0.0, 1.0, "highlight threshold between levels 1 and 2"};
    m.params[kSl0] = {"spec_l0", 0.0, 0.0, 1.0, "highlight level below spec_t1 (times specular colour)"};
    m.params[kSl1] = {"spec_l1", 0.5, 0.0, 1.0, "highlight level 1"};
    m.params[kSl2] = {"spec_l2", 1.0, 0.0, 1.0, "highlight level above spec_t2"};
    m.pack = packer<ToonConsts>([](const std::vector<double>& p) {
        require_ascending(p[kDt1], p[kDt2], "diffuse_t1", "diffuse_t2");
        require_ascending(p[kDt2], p[kDt3], "diffuse_t2", "diffuse_t3");
        require_ascending(p[kSt1], p[kSt2], "spec_t1", "spec_t2");
        ToonConsts k{};
        k.n = float(p[kN]);
        k.half_width = float(0.5 * p[kWidth]);
        // The smoothstep's slope, so the kernel's six band edges multiply instead of divide (capped at the
        // largest float: a width below ~3e-39 would otherwise give inf, and 0 * inf at an edge NaN).
        k.inv_width = p[kWidth] > 0.0 ? float(std::min(1.0 / p[kWidth], double(FLT_MAX))) : 0.0f;
        k.t1 = float(p[kDt1]);
        k.t2 = float(p[kDt2]);
        k.t3 = float(p[kDt3]);
        k.d0 = float(p[kDl0]);
        k.dd1 = float(p[kDl1] - p[kDl0]);
        k.dd2 = float(p[kDl2] - p[kDl1]);
        k.dd3 = float(p[kDl3] - p[kDl2]);
        k.u1 = float(p[kSt1]);
        k.u2 = float(p[kSt2]);
        k.s0 = float(p[kSl0]);
        k.ds1 = float(p[kSl1] - p[kSl0]);
        k.ds2 = float(p[kSl2] - p[kSl1]);
        return k;
    });
    m.energy_conserving = false;   // e.g. levels above NoL on most of the lit side, plus the highlight
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {
        {"*", 6.29e-4, 1.5e-3, 6.34e-4, 1.5e-3},
        {"diffuse_l3=0", 6.12e-3, 2e-2, 6.16e-3, 2e-2},
    };
    return m;
}

}  // namespace

// The family as it registers itself (host/models/catalogue.hpp, ModelFamily): rank 40 in the catalogue.
ModelFamily register_banded_toon_family() {
    ModelFamily family{"banded_toon", 40, "banded and toon", "docs/models/banded_toon.md", {}};
    family.models = {
        banded_model(),
        banded_seed001_model(),
        toon_model(),
    };
    // two chains a work-item where measuring each model at one and two found two faster (docs/speed.md,
    // "Two chains")
    use_two_chains(family, {"banded", "banded_seed001", "toon"});
    use_fast_pow(family, {"toon"});   // its highlight's NoH^n: fast mode's own pow (ModelInfo::fast_differs)
    return family;
}

}  // namespace shadelab
