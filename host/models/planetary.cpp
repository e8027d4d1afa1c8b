// The planetary family (kernels/models/planetary.cl, docs/photometry.md): ISIS3's photometric laws of airless
// bodies (Lommel-Seeliger and Lunar-Lambert are their own family: host/models/lunar_lambert.cpp). Parameter names are shadelab's lower-case forms of ISIS's keywords (Wh -> wh, Hg1 -> hg1, ...);
// host/photometry/isis_pvl.cpp maps ISIS's PVL files onto them. Ranges are ISIS's where ISIS bounds a value, and
// stated bounds where it does not (a fit needs finite ones): docs/photometry.md lists both.
#include <algorithm>
#include <cmath>

#include "consts/planetary.h"
#include "models/catalogue.hpp"
#include "models/model_info.hpp"

namespace shadelab {

namespace {

constexpr double kPi = 3.14159265358979323846;

ModelInfo base(const char* name, const char* summary, const char* source, const char* eval) {
    return model_info("models/planetary.cl", name, summary, source, eval);
}

// McEwen's lunar L(g) cubic (McEwen 1996; ISIS's LunarLambertMcEwen hard-codes these three).
const std::vector<ParamSpec> kMcEwenParams = {
    {"m1", -0.019, -0.05, 0.05, "McEwen's L(g) = 1 + m1 g + m2 g^2 + m3 g^3, g in degrees: linear coefficient"},
    {"m2", 0.000242, -0.001, 0.001, "quadratic coefficient of L(g)"},
    {"m3", -0.00000146, -1e-5, 1e-5, "cubic coefficient of L(g)"},
};

double mcewen_L(const std::vector<double>& p, double g_deg) {
    return 1.0 + p[0] * g_deg + p[1] * g_deg * g_deg + p[2] * g_deg * g_deg * g_deg;
}

// The parameters both Hapke variants share (ISIS's keywords Wh, B0, Hh, Theta; its defaults).
std::vector<ParamSpec> hapke_common() {
    return {
        {"wh", 0.5, 1e-6, 1.0, "single-scattering albedo w (ISIS Wh; ISIS requires 0 < w <= 1)"},
        {"b0", 0.0, 0.0, 10.0, "opposition surge amplitude B0 (ISIS B0 >= 0; 0 = no surge)"},
        {"hh", 0.0, 0.0, 10.0, "opposition surge width h (ISIS Hh >= 0; 0 = no surge, as ISIS)"},
        {"theta", 0.0, 0.0, 90.0, "macroscopic roughness theta-bar, degrees (ISIS Theta; 0 = smooth)"},
    };
}

// The constants every Hapke variant shares (w/4 .. k2 of HapkeConsts), from wh, b0, hh, theta. Computed in
// double; the cot terms capped (kernel: Hapke_E2 says why). The phase function's and hapke_2012's are 0.
HapkeConsts hapke_common_consts(const std::vector<double>& p) {
    const double w = p[0], b0 = p[1], h = p[2], theta = p[3] * kPi / 180.0;
    HapkeConsts c{};
    c.w_over_4 = float(w / 4.0);
    c.gamma = float(std::sqrt(1.0 - w));
    c.b0 = h > 0.0 ? float(b0) : 0.0f;
    c.inv_h = h > 0.0 ? float(1.0 / h) : 0.0f;
    c.rough = theta > 0.0 ? 1.0f : 0.0f;
    if (theta > 0.0) {
        const double tan_t = std::tan(theta), cot_t = 1.0 / tan_t;
        c.chi = float(1.0 / std::sqrt(1.0 + kPi * tan_t * tan_t));
        c.tan_t = float(tan_t);
        c.k1 = float(std::min(2.0 / kPi * cot_t, 1e15));
        c.k2 = float(std::min(cot_t * cot_t / kPi, 1e30));
    }
    return c;
}

// Henyey-Greenstein constants (kernel: Hapke_P_HG2); b = Hg1, cw = Hg2.
HapkeHG2Consts hg2_consts(double b, double cw) {
    const double s = std::abs(b);
    HapkeHG2Consts c{};
    c.a = float((1.0 - s) * (1.0 - s));
    c.two_abs_b = float(2.0 * s);
    c.b_positive = b >= 0.0 ? 1.0f : 0.0f;
    c.one_minus_b2 = float(1.0 - b * b);
    c.c = float(cw);
    c.one_minus_c = float(1.0 - cw);
    return c;
}

// McEwen's m1, m2, m3 as they are (r30, r_floor 0: lunar_lambert_mcewen reads only these).
McEwenConsts mcewen_consts(const std::vector<double>& p) {
    McEwenConsts c{};
    c.m1 = float(p[0]);
    c.m2 = float(p[1]);
    c.m3 = float(p[2]);
    return c;
}

ModelInfo lunar_lambert_mcewen_model() {
    ModelInfo m = base("lunar_lambert_mcewen",
                       "Lunar-Lambert with McEwen's L(g) = 1 + m1 g + m2 g^2 + m3 g^3 (g in degrees)",
                       "McEwen (1996) LPSC 27:841 (lunar L(g)); ISIS3 LunarLambertMcEwen", "lunar_lambert_mcewen_eval");
    m.params = kMcEwenParams;
    m.pack = packer<McEwenConsts>(mcewen_consts);
    m.reciprocal = true;   // L depends on g only, which is symmetric in L and V
    m.energy_conserving = false;
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 2.53e-5, 7e-5, 2.53e-5, 7e-5}};
    return m;
}

ModelInfo lunar_lambert_mcewen_ratio_model() {
    ModelInfo m = base("lunar_lambert_mcewen_ratio",
                       "ISIS LunarLambertMcEwen's value: R30 / r(g, i, e), r Lunar-Lambert with McEwen's L(g)",
                       "McEwen (1996) LPSC 27:841; ISIS3 LunarLambertMcEwen (the normalising form it returns)",
                       "lunar_lambert_mcewen_ratio_eval");
    m.params = kMcEwenParams;
    m.pack = packer<McEwenConsts>([](const std::vector<double>& p) {
        McEwenConsts c = mcewen_consts(p);
        // R30 = r at the standard geometry g = 30, i = 30, e = 0 (mu0 = cos 30, mu = 1), ISIS's choice
        const double L30 = mcewen_L(p, 30.0), c30 = std::cos(30.0 * kPi / 180.0);
        c.r30 = float(2.0 * L30 * c30 / (1.0 + c30) + (1.0 - L30) * c30);
        c.r_floor = 1e-3f;   // floor of r (kernel comment)
        return c;
    });
    m.reciprocal = false;   // a ratio R30 / r, not a reflectance: value / NoL is not symmetric
    m.energy_conserving = false;
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {
        // R30 / r with r near 0 where McEwen's L(g) < 0
        {"*", 2.35e-4, 7e-4, 2.35e-4, 7e-4},
    };
    return m;
}

ModelInfo hapke_hen_model() {
    ModelInfo m = base("hapke_hen",
                       "Hapke 1981/84/86 with two-term Henyey-Greenstein P(g), opposition B(g), roughness theta",
                       "Hapke (1981) JGR 86:3039, (1984) Icarus 59:41, (1986) Icarus 67:264; ISIS3 HapkeHen",
                       "hapke_hen_eval");
    m.params = hapke_common();
    m.params.push_back({"hg1", 0.0, -0.9999, 0.9999,
                        "Henyey-Greenstein asymmetry b (ISIS Hg1, -1 < b < 1): lobe 1 (1 + b^2 + 2b cos g)"});
    m.params.push_back({"hg2", 0.0, 0.0, 1.0,
                        "weight c of the second lobe (1 + b^2 - 2b cos g) (ISIS Hg2, 0 <= c <= 1)"});
    m.pack = packer<HapkeConsts>([](const std::vector<double>& p) {
        HapkeConsts c = hapke_common_consts(p);
        c.phase.hg2 = hg2_consts(p[4], p[5]);
        return c;
    });
    m.reciprocal = true;   // P, B depend on g only; H(mu0) H(mu) and the roughness S are symmetric in i, e
    m.energy_conserving = false;   // the opposition surge adds light (B0 up to 10)
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 4.00e-6, 1.2e-5, 4.00e-6, 1.2e-5}};
    return m;
}

ModelInfo hapke_leg_model() {
    ModelInfo m = base("hapke_leg", "Hapke 1981/84/86 with Legendre P(g) = 1 + b cos g + c (3 cos^2 g - 1)/2",
                       "Hapke (1981) JGR 86:3039, (1984) Icarus 59:41, (1986) Icarus 67:264; ISIS3 HapkeLeg",
                       "hapke_leg_eval");
    m.params = hapke_common();
    m.params.push_back({"bh", 0.0, -1.0, 1.0, "Legendre coefficient b of cos g (ISIS Bh, -1 <= b <= 1)"});
    m.params.push_back({"ch", 0.0, -1.0, 1.0, "Legendre coefficient c of P2(cos g) (ISIS Ch, -1 <= c <= 1)"});
    m.pack = packer<HapkeConsts>([](const std::vector<double>& p) {
        HapkeConsts c = hapke_common_consts(p);
        c.phase.legendre.b = float(p[4]);
        c.phase.legendre.c = float(p[5]);
        return c;
    });
    m.reciprocal = true;
    m.energy_conserving = false;
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 1.07e-5, 3e-5, 1.07e-5, 3e-5}};
    return m;
}

ModelInfo hapke_2012_model() {
    ModelInfo m = base("hapke_2012",
                       "Hapke 2002/2012: better H function, porosity K, coherent backscatter; HG2 P(g), roughness",
                       "Hapke (2002) Icarus 157:523, (2008) Icarus 195:918, (2012) Theory of Reflectance and "
                       "Emittance Spectroscopy, eq. 12.55",
                       "hapke_2012_eval");
    m.params = hapke_common();
    m.params.push_back({"hg1", 0.0, -0.9999, 0.9999, "Henyey-Greenstein asymmetry b, as hapke_hen"});
    m.params.push_back({"hg2", 0.0, 0.0, 1.0, "weight of the second Henyey-Greenstein lobe, as hapke_hen"});
    m.params.push_back({"phi", 0.0, 0.0, 0.75,
                        "filling factor phi (porosity 1 - phi): K = -ln(1 - 1.209 phi^(2/3)) / (1.209 phi^(2/3)); 0: K = 1"});
    m.params.push_back({"bc0", 0.0, 0.0, 10.0, "coherent-backscatter amplitude B_C0 (0: none)"});
    m.params.push_back({"hc", 0.0, 0.0, 10.0, "coherent-backscatter width h_C (0: none)"});
    m.pack = packer<HapkeConsts>([](const std::vector<double>& p) {
        HapkeConsts c = hapke_common_consts(p);
        c.phase.hg2 = hg2_consts(p[4], p[5]);
        const double w = p[0], gamma = std::sqrt(1.0 - w), phi = p[6], bc0 = p[7], hc = p[8];
        const double y = 1.209 * std::pow(phi, 2.0 / 3.0);
        c.w = float(w);
        c.r0 = float((1.0 - gamma) / (1.0 + gamma));
        c.K = float(phi > 0.0 ? -std::log1p(-y) / y : 1.0);
        c.bc0 = hc > 0.0 ? float(bc0) : 0.0f;
        c.inv_hc = hc > 0.0 ? float(1.0 / hc) : 0.0f;
        return c;
    });
    m.reciprocal = true;   // K, H(mu0/K) H(mu/K), B_SH, B_CB, P and S are all symmetric in i and e
    m.energy_conserving = false;
    // kernel vs reference, tests/test_precision.cpp: {probe, precise seen, bound, fast seen, bound}
    m.precision = {{"*", 1.52e-6, 6e-6, 1.52e-6, 6e-6}};
    return m;
}

}  // namespace

// The family as it registers itself (host/models/catalogue.hpp, ModelFamily): rank 90 in the catalogue.
ModelFamily register_planetary_family() {
    ModelFamily family{"planetary", 90, "planetary (ISIS3's photometric laws)", "docs/photometry.md", {}};
    family.models = {
        lunar_lambert_mcewen_model(),
        lunar_lambert_mcewen_ratio_model(),
        hapke_hen_model(),
        hapke_leg_model(),
        hapke_2012_model(),
    };
    // two chains a work-item where measuring each model at one and two found two faster (docs/speed.md,
    // "Two chains"; hapke_leg lost 8% at 16M fragments with two)
    use_two_chains(family, {"hapke_hen", "hapke_2012"});
    // and on AVX2 hosts McEwen's laws (1.25-1.43x: docs/speed.md, "Chains on AVX2"; hapke_leg 1.03x at 16M there)
    use_two_chains_on_avx2(family, {"lunar_lambert_mcewen", "lunar_lambert_mcewen_ratio"});
    // sixteen lanes on AVX2 hosts where they gained at least 1.10x at 1M and 16M fragments (the median of eight
    // alternating rounds, an AMD Zen 3: docs/speed.md, "Sixteen lanes on AVX2"): hapke_leg 1.25x and 1.14x at
    // one chain, lunar_lambert_mcewen_ratio 1.10x and 1.21x at two (lunar_lambert_mcewen 1.10x and 1.09x: not)
    use_sixteen_lanes_on_avx2(family, {"hapke_leg"}, 1);
    use_sixteen_lanes_on_avx2(family, {"lunar_lambert_mcewen_ratio"}, 2);
    // plain stores at every size where streaming stores measured slower (docs/speed.md, "Streaming stores")
    use_plain_stores(family, {"hapke_leg", "hapke_2012"});
    return family;
}

}  // namespace shadelab
