// The empirical family (kernels/models/empirical.cl, docs/models/empirical.md): ISIS3's MinnaertEmpirical and
// LunarLambertEmpirical, Minnaert's K and Lunar-Lambert's L as functions of the phase angle with a phase curve B(g),
// given as tables over phase (ISIS's PhaseList, KList / LList, PhaseCurveList) and interpolated by ISIS's natural
// cubic spline (host/core/spline.hpp). The tables are table-valued parameters (TableSpec): they travel in the
// material's table buffer (kernels/consts/empirical.h), not in the 24 constants. Their reference is
// host/reference/empirical_ref.cpp, their tests tests/test_empirical.cpp.
#include <cstring>

#include "consts/empirical.h"
#include "core/spline.hpp"
#include "models/catalogue.hpp"
#include "models/model_info.hpp"

namespace shadelab {

namespace {

// The default tables: `photometry empirical` fitted to ISIS's HapkeHen unit-test surface (Wh 0.52, B0 1, Hh 1,
// Theta 30, Hg1 0.213, Hg2 1; tests/data/photometry/hapke_hen_isis.pvl) at 7 phases 0, 25, ..., 150 with
// phoempglobal's default limits (`photometry empirical --pvl hapke_hen_isis.pvl --law minnaert|lunar_lambert --nph 7
// --phmin 0 --phmax 150`, docs/models/empirical.md), rounded to 4 significant digits. B(0) = 1.
const std::vector<double> kPhases = {0, 25, 50, 75, 100, 125, 150};
const std::vector<double> kMinnaertK = {0.5066, 0.7014, 0.8074, 0.8897, 0.9187, 0.9523, 1.0304};
const std::vector<double> kMinnaertB = {1.0, 0.8877, 0.6857, 0.5084, 0.3479, 0.2132, 0.1237};
const std::vector<double> kLunarL = {0.9717, 0.5228, 0.3389, 0.1671, 0.04065, -0.02107, -0.03104};
const std::vector<double> kLunarB = {1.0, 0.8943, 0.6917, 0.5173, 0.3750, 0.2416, 0.1253};

// The table buffer: segment j from knot j to j+1 with the cubics of both splines in t = g - x_j, computed in double
// and stored as float; the unused segments start beyond every phase (kernels/consts/empirical.h).
std::vector<float> pack_segments(const Material& m, const char* param_table) {
    const std::vector<double>& x = m.tables.at("phase_list");
    const NaturalSpline p(x, m.tables.at(param_table)), b(x, m.tables.at("phase_curve_list"));
    std::vector<EmpiricalSegment> seg(SL_EMP_MAX_SEGMENTS);
    for (auto& s : seg) s = EmpiricalSegment{SL_EMP_UNUSED, {0, 0, 0, 0}, {0, 0, 0, 0}};
    for (std::size_t j = 0; j + 1 < x.size(); ++j) {
        seg[j].start = float(x[j]);
        const auto pc = p.local_cubic(j), bc = b.local_cubic(j);
        for (int c = 0; c < 4; ++c) {
            seg[j].param[c] = float(pc[std::size_t(c)]);
            seg[j].bright[c] = float(bc[std::size_t(c)]);
        }
    }
    std::vector<float> out(seg.size() * 9);
    std::memcpy(out.data(), seg.data(), out.size() * sizeof(float));
    return out;
}

TableSpec phases() {
    return {"phase_list", "PhaseList", kPhases, 0.0, 180.0,
            "phase angles of the tables, degrees, strictly increasing (ISIS PhaseList)", true, SL_EMP_MAX_KNOTS};
}

TableSpec curve(const std::vector<double>& def) {
    return {"phase_curve_list", "PhaseCurveList", def, 0.0, 10.0,
            "the phase curve B(g) at each phase (ISIS PhaseCurveList); its spline must stay below 20 over 0..180 "
            "(below 0 it is held at 0)",
            false, SL_EMP_MAX_KNOTS, -20.0, 20.0};
}

ModelInfo base(const char* name, const char* summary, const char* eval) {
    ModelInfo m = model_info("models/empirical.cl", name, summary, "", eval);
    // value / NoL = B(g) (mu0 mu)^(K(g)-1) or B(g) ((1 - L(g)) + 2 L(g) / (mu0 + mu)): symmetric in L and V,
    // since g, mu0 mu and mu0 + mu are
    m.reciprocal = true;
    m.energy_conserving = false;
    return m;
}

}  // namespace

// The family as it registers itself (host/models/catalogue.hpp, ModelFamily): rank 95, after ISIS's closed-form
// laws (planetary, 90).
ModelFamily register_empirical_family() {
    ModelFamily family{"empirical", 95, "Empirical (ISIS tables)", "docs/models/empirical.md", {}};
    {
        ModelInfo m = base("minnaert_empirical", "ISIS MinnaertEmpirical: albedo * B(g) mu0 (mu0 mu)^(K(g) - 1), K and B tables over phase",
                           "minnaert_empirical_eval");
        m.source = "Minnaert (1941) ApJ 93:403; ISIS3 MinnaertEmpirical (natural cubic spline of KList, PhaseCurveList)";
        m.tables = {phases(),
                    {"k_list", "KList", kMinnaertK, 0.0, 2.0,
                     "Minnaert's K at each phase (ISIS KList); its spline must stay in [-1, 3] over 0..180", false,
                     SL_EMP_MAX_KNOTS, -1.0, 3.0},
                    curve(kMinnaertB)};
        m.pack_table = [](const Material& r) { return pack_segments(r, "k_list"); };
        // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
        m.precision = {{"*", 8.11e-7, 2.5e-6, 6.21e-6, 2e-5}};   // fast: sl_fast_pow's lower degrees (was 8.11e-7)
        family.models.push_back(m);
    }
    {
        ModelInfo m = base("lunar_lambert_empirical",
                           "ISIS LunarLambertEmpirical: albedo * B(g) mu0 ((1 - L(g)) + 2 L(g) / (mu0 + mu)), L and B tables over phase",
                           "lunar_lambert_empirical_eval");
        m.source = "McEwen (1991) Icarus 92:298; ISIS3 LunarLambertEmpirical (natural cubic spline of LList, PhaseCurveList)";
        m.tables = {phases(),
                    {"l_list", "LList", kLunarL, -1.0, 2.0,
                     "Lunar-Lambert's L at each phase (ISIS LList); its spline must stay in [-3, 4] over 0..180", false,
                     SL_EMP_MAX_KNOTS, -3.0, 4.0},
                    curve(kLunarB)};
        m.pack_table = [](const Material& r) { return pack_segments(r, "l_list"); };
        m.precision = {{"*", 8.76e-7, 2.5e-6, 8.76e-7, 2.5e-6}};   // as above
        family.models.push_back(m);
    }
    // two chains a work-item where measuring each model at one and two found two faster (docs/speed.md,
    // "Two chains")
    use_two_chains(family, {"lunar_lambert_empirical", "minnaert_empirical"});
    use_fast_pow(family, {"minnaert_empirical"});   // its powers of the cosines (ModelInfo::fast_differs)
    return family;
}

}  // namespace shadelab
