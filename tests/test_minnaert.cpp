// The Minnaert family (kernels/models/minnaert.cl): kernels against the double references over the sphere for
// a grid of parameters, the identities between the variants, reciprocity, the white furnace, the places the
// formulas break (limb, pow(0, 0), behind the horizon, V = N) and the zero-phase disc profile end to end.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cl/runtime.hpp"
#include "core/fragment_buffer.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"
#include "support.hpp"

using namespace shadelab;
using glm::dvec3;

namespace {

// The limb guard of the 1941-law models (kernel and reference both define it; this is the documented value).
constexpr double kEps = 1e-3;
// Bound on the error of a float dot product of two float unit vectors (3 products, 2 sums:
// gamma_3 * sum |a_i b_i| <= 3 * 2^-24 * 1.0000002 = 1.8e-7), rounded up.
constexpr double kDotErr = 2e-7;

struct Case {
    std::string model, param;
    double value;
};

// The parameter grid of each model, both ends of each range included.
const std::vector<Case>& grid() {
    static const std::vector<Case> g = [] {
        std::vector<Case> v;
        for (double k : {0.0, 0.25, 0.5, 0.7, 1.0, 1.5, 2.0}) v.push_back({"minnaert_1941", "k", k});
        for (double k : {-1.0, -0.5, -0.25, 0.0, 0.3, 0.5, 1.0}) v.push_back({"minnaert_unity", "k", k});
        for (double d : {0.0, 0.5, 0.9, 1.0, 1.1, 1.5, 2.0}) v.push_back({"minnaert_blender", "darkness", d});
        for (double k : {0.0, 0.3, 0.7, 1.0}) v.push_back({"minnaert_b", "k", k});
        for (double k : {0.0, 0.5, 0.7, 1.0, 2.0}) v.push_back({"minnaert_normalized", "k", k});
        return v;
    }();
    return g;
}

Material make(const std::string& model, const std::string& param, double value, dvec3 albedo = test::kAlbedo) {
    return test::material(model, param.empty() ? std::map<std::string, double>{} : std::map<std::string, double>{{param, value}},
                          albedo);
}

Material make(const Case& c, dvec3 albedo = test::kAlbedo) { return make(c.model, c.param, c.value, albedo); }

std::string label(const Case& c) {
    std::ostringstream s;
    s << c.model << " " << c.param << "=" << c.value;
    return s.str();
}

std::vector<float> flatten(const std::vector<dvec3>& v) {
    std::vector<float> f;
    f.reserve(3 * v.size());
    for (const auto& x : v)
        for (int c = 0; c < 3; ++c) f.push_back(float(x[c]));
    return f;
}

std::vector<float> eval_kernel(const Material& m, const std::vector<dvec3>& N, const std::vector<dvec3>& L,
                               const std::vector<dvec3>& V) {
    Shader shader(test::runtime());
    const auto fN = flatten(N), fL = flatten(L), fV = flatten(V);
    const std::vector<float> fP(fN.size(), 0.0f);
    return shader.eval_directions(m, fN, fL, fV, fP);
}

// The range of reference values over the float rounding of the two dot products: L and V are moved by up to
// kDotErr along N (which moves NoL and NoV by up to kDotErr, and |N - V|^2 / 2 by a relative kDotErr), plus
// the point where a moved cosine crosses the limb guard's kink (the value's maximum in that cosine).
// Every model of this family depends on N, L, V only through NoL, NoV and |N - V|, monotonically in each
// cosine except at that kink, so the extremes over the box are among these points.
void reference_interval(const ref::ModelFn& f, const Material& m, const dvec3& N, const dvec3& L,
                        const dvec3& V, dvec3& lo, dvec3& hi) {
    const double nn = glm::dot(N, N);
    double sl[4] = {-kDotErr, 0.0, kDotErr, 0.0}, sv[4] = {-kDotErr, 0.0, kDotErr, 0.0};
    int nl = 3, nv = 3;
    const double tl = (kEps - glm::dot(N, L)) / nn, tv = (kEps - glm::dot(N, V)) / nn;
    if (std::abs(tl) < kDotErr) sl[nl++] = tl;
    if (std::abs(tv) < kDotErr) sv[nv++] = tv;
    lo = dvec3(std::numeric_limits<double>::infinity());
    hi = -lo;
    const dvec3 P(0.0);
    for (int a = 0; a < nl; ++a)
        for (int b = 0; b < nv; ++b) {
            const dvec3 r = f(N, L + sl[a] * N, V + sv[b] * N, P, m);
            lo = glm::min(lo, r);
            hi = glm::max(hi, r);
        }
}

// (1/pi) * integral over the upper hemisphere of value(L, V) dL (white furnace: directional albedo seen from
// V), from the KERNEL, for albedo 1 (the green channel over the albedo): the furnace of tests/support.hpp with
// mu = t^2 (t midpoints, smooth at grazing for mu^k with small k) and 8 azimuths (the family does not depend on
// azimuth; they only exercise real vectors). Returns one value per view angle. fix_light_instead: the light at
// those angles and the integral over the view hemisphere (of f_r NoV).
std::vector<double> furnace(const Material& m, const std::vector<double>& view_deg, bool fix_light_instead = false) {
    test::Furnace f;
    f.grid = test::Furnace::Grid::cos_theta_squared;
    f.n_theta = 2000;
    f.n_phi = 8;
    f.over_view = fix_light_instead;
    std::vector<dvec3> fixed;
    for (double deg : view_deg) fixed.push_back(test::at_angle(deg));
    std::vector<double> res = test::furnace_kernel(m, fixed, f);
    for (double& a : res) a /= m.albedo.y;
    return res;
}

// integral_0^1 mu * g(mu) dmu for the guarded 1941 law (g(mu) = mu^(k-1) above eps, eps^(k-2) mu below, k < 1).
double guarded_moment(double k) {
    if (k >= 1.0) return 1.0 / (k + 1.0);
    return (1.0 - std::pow(kEps, k + 1.0)) / (k + 1.0) + std::pow(kEps, k + 1.0) / 3.0;
}

}  // namespace

// ---- 1. kernel against reference --------------------------------------------------------------------

TEST_CASE("minnaert kernels match the double references over the sphere, parameter grids incl. ends",
          "[minnaert][kernel]") {
    const auto& s = test::sweep();
    std::cout << "minnaert kernel vs reference, " << s.size() << " triples each. 'interval' = the reference's "
              << "range over +-" << kDotErr << " in NoL, NoV (float dot rounding); 'cond' = well-conditioned triples, "
              << "where that range is within 4e-6 of the value (and |value| >= 1e-6)\n";
    std::cout << std::left << std::setw(32) << "model / parameter" << std::right << std::setw(12) << "max abs"
              << std::setw(12) << "max rel" << std::setw(9) << "cond %" << std::setw(13) << "rel (cond)"
              << std::setw(15) << "past interval" << "\n";
    for (const Case& c : grid()) {
        const Material m = make(c);
        const ref::ModelFn& f = ref::reference_for(c.model);
        // Per triple (computed once for its three channels): the reference's range over the input rounding.
        std::size_t interval_of = SIZE_MAX, cond_n = 0, last_cond = SIZE_MAX;
        dvec3 lo(0.0), hi(0.0);
        double cond_rel = 0.0, excess = 0.0;
        // Everywhere (grazing, behind the horizon, V = N, the guard's kink, Blender's clamp, the saturate's
        // clip): the kernel lies in the reference's range over the input rounding, up to its own arithmetic
        // (pow's error, the exponent rounded to float: ln(x) * 3e-8 for x >= 1e-6, a few products): 1e-6 of the
        // range's magnitude past either end. Well conditioned (the dot products' rounding alone can move the
        // value by at most +-2e-6, and |value| >= 1e-6): also within 3e-6 relative of the reference (that plus a
        // few float roundings of its own: pow, the exponent rounded to float).
        const auto e = test::check_kernel_against_reference(m, [&](const test::Compared& v) {
            if (v.i != interval_of) {
                reference_interval(f, m, v.N(), v.L(), v.V(), lo, hi);
                interval_of = v.i;
            }
            const double mag = std::max(std::abs(lo[v.c]), std::abs(hi[v.c]));
            const double past = std::max(lo[v.c] - v.k, v.k - hi[v.c]);
            if (past > 0.0) excess = std::max(excess, mag > 0.0 ? past / mag : 1.0);
            // the allowed distance from r on the side k lies: to the range's end plus 1e-6 of its magnitude
            double allowed = (v.k >= v.r ? hi[v.c] - v.r : v.r - lo[v.c]) + 1e-6 * mag;
            if (std::abs(v.r) >= 1e-6 && hi[v.c] - lo[v.c] <= 4e-6 * std::abs(v.r)) {
                if (last_cond != v.i) { ++cond_n; last_cond = v.i; }
                cond_rel = std::max(cond_rel, v.err() / std::abs(v.r));
                allowed = std::min(allowed, 3e-6 * std::abs(v.r));
            }
            return allowed;
        });
        std::cout << std::left << std::setw(32) << label(c) << std::right << std::setw(12) << e.max_abs
                  << std::setw(12) << e.max_rel << std::setw(9) << std::setprecision(3)
                  << 100.0 * double(cond_n) / double(s.size()) << std::setprecision(6) << std::setw(13) << cond_rel
                  << std::setw(15) << excess << "\n";
        test::expect_within(e, s.size());
        CHECK(cond_n > s.size() / 10);   // the tight bound is not vacuous
    }
}

TEST_CASE("minnaert closed-form spot values (computed by hand)", "[minnaert][kernel]") {
    // N = +z. V or L at 60 deg (cos 0.5) or at cos 0.05, in the xz plane.
    const double s60 = std::sqrt(0.75), s05 = std::sqrt(1.0 - 0.05 * 0.05);
    const dvec3 N{0, 0, 1}, Z{0, 0, 1}, A60{s60, 0, 0.5}, A05{-s05, 0, 0.05};
    struct Spot {
        Case c;
        dvec3 L, V;
        double expect;   // value for albedo 1
    };
    const std::vector<Spot> spots = {
        {{"minnaert_1941", "k", 0.5}, A60, Z, std::sqrt(0.5)},         // 0.5^0.5 * 1^-0.5
        {{"minnaert_1941", "k", 2.0}, A60, A60, 0.25 * 0.5},          // 0.5^2 * 0.5^1
        {{"minnaert_1941", "k", 0.0}, Z, A60, 2.0},                   // 1^0 * 0.5^-1
        {{"minnaert_1941", "k", 0.7}, A60, A05, std::pow(0.5, 0.7) * std::pow(0.05, -0.3)},
        {{"minnaert_unity", "k", 0.3}, Z, Z, 1.0},
        {{"minnaert_unity", "k", 0.3}, A60, A60, std::pow(0.5, 1.3) * std::pow(0.5, 0.3)},
        {{"minnaert_unity", "k", -0.5}, A60, A05, 1.0},               // 0.5^0.5 * 0.05^-0.5 = 3.16: clipped
        {{"minnaert_unity", "k", -0.5}, Z, A60, 1.0},                // 1^0.5 * 0.5^-0.5 = 1.41: clipped
        {{"minnaert_unity", "k", -0.25}, A60, Z, std::pow(0.5, 0.75)},  // 0.595: not clipped
        {{"minnaert_blender", "darkness", 0.5}, Z, A05, std::pow(0.1, -0.5)},   // nv nl = 0.05 < 0.1
        {{"minnaert_blender", "darkness", 0.5}, A60, Z, 0.5 * std::pow(0.5, -0.5)},
        {{"minnaert_blender", "darkness", 2.0}, A60, Z, 0.5 * 0.001},           // (1.001 - 1)^1
        {{"minnaert_blender", "darkness", 1.5}, Z, A60, std::pow(0.501, 0.5)},
        {{"minnaert_b", "k", 0.7}, Z, A60, std::pow(0.5, 0.3)},
        {{"minnaert_b", "k", 0.0}, A60, A60, 0.5 * 0.5},
        {{"minnaert_b", "k", 1.0}, A60, A05, 0.25},
        {{"minnaert_normalized", "k", 0.0}, Z, A60, 0.5 * 2.0},
        {{"minnaert_normalized", "k", 2.0}, A60, A60, 1.5 * 0.125},
    };
    for (const Spot& sp : spots) {
        const Material m = make(sp.c, dvec3(1.0));
        const auto out = eval_kernel(m, {N}, {sp.L}, {sp.V});
        const double r = ref::eval_material(N, sp.L, sp.V, N, m).y;
        INFO(label(sp.c) << ": kernel " << out[1] << ", reference " << r << ", by hand " << sp.expect);
        CHECK(out[1] == Approx(sp.expect).epsilon(3e-6));
        CHECK(r == Approx(sp.expect).epsilon(1e-7));   // Blender's clamp is 0.1f
    }
}

// ---- 2. identities ----------------------------------------------------------------------------------

TEST_CASE("minnaert identities: the Lambert points of each variant, and unity(k) = 1941(k+1) where unclipped",
          "[minnaert][identity]") {
    const auto& s = test::sweep();
    Shader shader(test::runtime());
    const Material lam = make("lambert", "", 0.0);
    const auto lambert = shader.eval_directions(lam, s.N, s.L, s.V, s.P);
    struct Id {
        Case c;
        bool needs_visible;   // the 1941-law models are 0 for NoV <= 0, where Lambert (no V) is not
    };
    for (const Id& id : {Id{{"minnaert_1941", "k", 1.0}, true}, Id{{"minnaert_unity", "k", 0.0}, false},
                         Id{{"minnaert_blender", "darkness", 1.0}, false}, Id{{"minnaert_normalized", "k", 1.0}, true}}) {
        const auto out = shader.eval_directions(make(id.c), s.N, s.L, s.V, s.P);
        double worst = 0.0;
        std::size_t used = 0, at = 0;
        for (std::size_t i = 0; i < s.size(); ++i) {
            // 2e-7 > the float dot error: kernel and double agree on the sign of NoV.
            if (id.needs_visible && glm::dot(s.dN[i], s.dV[i]) <= kDotErr) continue;
            ++used;
            for (int ch = 0; ch < 3; ++ch) {
                const double a = out[3 * i + std::size_t(ch)], b = lambert[3 * i + std::size_t(ch)];
                const double d = std::abs(a - b) / std::max(std::abs(b), 1e-30);
                if (d > worst) { worst = d; at = i; }
            }
        }
        std::cout << "identity " << std::setw(30) << std::left << label(id.c) << std::right << " == lambert on "
                  << used << " triples" << (id.needs_visible ? " (NoV > 0)" : " (all)") << ": max rel diff " << worst
                  << "\n";
        INFO(label(id.c) << " worst triple " << at << " (" << s.kind[at] << ")");
        CHECK(used > s.size() / 3);
        CHECK(worst <= 2.5e-7);   // 2 ulp: saturate(NoL) vs NoL where the float NoL is 1 + 1 ulp
    }

    // unity(k) against 1941(k+1): the same function wherever the saturate does not clip and the 1941 limb guard
    // is not active (NoL, NoV >= 1e-3 when k + 1 < 1). Kernels, and the references in double.
    for (double k : {-1.0, -0.5, -0.25, 0.0, 0.3, 1.0}) {
        const Material mu = make("minnaert_unity", "k", k), m41 = make("minnaert_1941", "k", k + 1.0);
        const auto ou = shader.eval_directions(mu, s.N, s.L, s.V, s.P);
        const auto o41 = shader.eval_directions(m41, s.N, s.L, s.V, s.P);
        double worst_k = 0.0, worst_r = 0.0;
        std::size_t used = 0;
        for (std::size_t i = 0; i < s.size(); ++i) {
            const double NoL = glm::dot(s.dN[i], s.dL[i]), NoV = glm::dot(s.dN[i], s.dV[i]);
            if (NoL < kEps || NoV < kEps) continue;
            if (std::pow(NoL, 1.0 + k) * std::pow(NoV, k) > 1.0 - 1e-5) continue;   // clipped (or nearly)
            ++used;
            const double ru = ref::eval_material(s.dN[i], s.dL[i], s.dV[i], s.dP[i], mu).x;
            const double r41 = ref::eval_material(s.dN[i], s.dL[i], s.dV[i], s.dP[i], m41).x;
            worst_r = std::max(worst_r, std::abs(ru - r41) / std::abs(r41));
            worst_k = std::max(worst_k, std::abs(double(ou[3 * i]) - double(o41[3 * i])) / std::abs(r41));
        }
        std::cout << "identity minnaert_unity k=" << k << " == minnaert_1941 k=" << k + 1 << " where unclipped: "
                  << used << " triples, max rel diff kernels " << worst_k << ", references " << worst_r << "\n";
        INFO("unity k " << k);
        if (k == -1.0) {   // NoL^0 NoV^-1 >= 1: the saturate clips every lit point (unity k = -1 is flat)
            CHECK(used == 0);
            continue;
        }
        CHECK(used > 1000);
        CHECK(worst_r < 1e-12);
        CHECK(worst_k < 2e-6);
    }
}

TEST_CASE("minnaert_unity's saturate clips a fraction -k of uniformly distributed (L, V) pairs for k < 0",
          "[minnaert][identity]") {
    // For L, V uniform over the upper hemisphere, NoL and NoV are uniform on [0, 1]. For k in (-1, 0) the clip
    // NoL^(1+k) NoV^k > 1 is NoV < NoL^((1+k)/(-k)), of probability 1 / (1 + (1+k)/(-k)) = -k (by hand); for
    // k >= 0 the value never exceeds NoL <= 1. The sweep's "random" triples are uniform on the sphere.
    const auto& s = test::sweep();
    std::cout << "minnaert_unity clipping vs minnaert_1941 (k+1), uniform lit-and-seen (L, V) pairs:\n"
              << "      k  clipped   expect  ratio 1941/unity among clipped: median      p99       max"
              << "   furnace W(V=60deg) unity / 1941\n";
    for (double k : {-1.0, -0.75, -0.5, -0.25, -0.1, 0.0, 0.3}) {
        std::size_t n = 0, clipped = 0;
        std::vector<double> ratio;
        const Material m41 = make("minnaert_1941", "k", k + 1.0, dvec3(1.0));
        for (std::size_t i = 0; i < s.size(); ++i) {
            if (s.kind[i] != "random") continue;
            const double NoL = glm::dot(s.dN[i], s.dL[i]), NoV = glm::dot(s.dN[i], s.dV[i]);
            if (NoL <= 0.0 || NoV <= 0.0) continue;
            ++n;
            const double raw = std::pow(NoL, 1.0 + k) * std::pow(NoV, k);
            if (raw > 1.0) {
                ++clipped;
                ratio.push_back(ref::eval_material(s.dN[i], s.dL[i], s.dV[i], s.dP[i], m41).x);   // / 1 (clipped)
            }
        }
        std::sort(ratio.begin(), ratio.end());
        const double frac = double(clipped) / double(n), expect = k < 0.0 ? -k : 0.0;
        auto q = [&](double p) { return ratio.empty() ? 1.0 : ratio[std::size_t(p * double(ratio.size() - 1))]; };
        const auto wu = furnace(make("minnaert_unity", "k", k, dvec3(1.0)), {60.0});
        const auto w41 = furnace(m41, {60.0});
        std::cout << std::setw(7) << k << std::setw(10) << frac << std::setw(9) << expect << std::setw(36) << q(0.5)
                  << std::setw(9) << q(0.99) << std::setw(10) << q(1.0) << std::setw(15) << wu[0] << " / " << w41[0]
                  << "   (" << n << " pairs)\n";
        INFO("k " << k << ": clipped fraction " << frac << " of " << n);
        CHECK(n > 10000);
        // binomial standard deviation <= 0.5 / sqrt(n) = 0.005; 0.02 is 4 of them
        CHECK(std::abs(frac - expect) < 0.02);
        if (k >= 0.0) CHECK(clipped == 0);
    }
}

TEST_CASE("minnaert_blender (d <= 1) is the 1941 law with k = d outside its 0.1 clamp - the clamp's share",
          "[minnaert][identity]") {
    // Where NoV NoL >= 0.1 Blender's "Real model" NoL (nv nl)^(d-1) is NoL^d NoV^(d-1). For NoL, NoV uniform on
    // [0, 1] the clamp region NoL NoV < 0.1 has probability 0.1 + integral_0.1^1 0.1/x dx = 0.1 (1 + ln 10)
    // = 0.3303 (by hand), whatever d is.
    const auto& s = test::sweep();
    Shader shader(test::runtime());
    const double expect = 0.1 * (1.0 + std::log(10.0));
    std::cout << "minnaert_blender vs minnaert_1941 (k = d), uniform lit-and-seen pairs; clamp share expected "
              << expect << "\n      d  clamped  outside: max rel diff kernels       refs  ratio 1941/blender in "
              << "clamp: median       p99       max\n";
    for (double d : {0.0, 0.5, 0.7, 0.9}) {
        const Material mb = make("minnaert_blender", "darkness", d), m41 = make("minnaert_1941", "k", d);
        const auto ob = shader.eval_directions(mb, s.N, s.L, s.V, s.P);
        const auto o41 = shader.eval_directions(m41, s.N, s.L, s.V, s.P);
        std::size_t n = 0, clamped = 0;
        double worst_k = 0.0, worst_r = 0.0;
        std::vector<double> ratio;
        for (std::size_t i = 0; i < s.size(); ++i) {
            const double NoL = glm::dot(s.dN[i], s.dL[i]), NoV = glm::dot(s.dN[i], s.dV[i]);
            if (NoL <= 0.0 || NoV <= 0.0 || s.kind[i] != "random") continue;
            ++n;
            const double rb = ref::eval_material(s.dN[i], s.dL[i], s.dV[i], s.dP[i], mb).x;
            const double r41 = ref::eval_material(s.dN[i], s.dL[i], s.dV[i], s.dP[i], m41).x;
            if (NoL * NoV < double(0.1f)) {
                ++clamped;
                if (NoL >= kEps && NoV >= kEps) ratio.push_back(r41 / rb);   // outside the 1941 law's guard
                continue;
            }
            if (NoL * NoV < double(0.1f) + 1e-6) continue;   // the float and double sides of the clamp's edge
            worst_r = std::max(worst_r, std::abs(rb - r41) / r41);
            worst_k = std::max(worst_k, std::abs(double(ob[3 * i]) - double(o41[3 * i])) / r41);
        }
        std::sort(ratio.begin(), ratio.end());
        const double frac = double(clamped) / double(n);
        std::cout << std::setw(7) << d << std::setw(9) << frac << std::setw(30) << worst_k << std::setw(13) << worst_r
                  << std::setw(31) << ratio[ratio.size() / 2] << std::setw(10)
                  << ratio[std::size_t(0.99 * double(ratio.size() - 1))] << std::setw(10) << ratio.back() << "\n";
        INFO("darkness " << d);
        CHECK(std::abs(frac - expect) < 0.02);   // binomial sd 0.004
        CHECK(worst_r < 1e-12);
        CHECK(worst_k < 2e-6);
        CHECK(ratio.front() >= 1.0 - 1e-12);   // the clamp only ever darkens the law (d - 1 <= 0)
        CHECK(ratio.size() > 1000);
    }
}

// ---- 3. physics: reciprocity and the white furnace ---------------------------------------------------

TEST_CASE("minnaert reciprocity: the 1941 law and its normalised form always, the shader forms only in part",
          "[minnaert][physics]") {
    const auto& s = test::sweep();
    std::vector<std::size_t> idx;
    for (std::size_t i = 0; i < s.size(); ++i)
        if (glm::dot(s.dN[i], s.dL[i]) > 0.0 && glm::dot(s.dN[i], s.dV[i]) > 0.0) idx.push_back(i);
    std::vector<dvec3> N, L, V;
    for (std::size_t i : idx) { N.push_back(s.dN[i]); L.push_back(s.dL[i]); V.push_back(s.dV[i]); }
    std::cout << "reciprocity, value(L,V)/NoL vs value(V,L)/NoV: max rel asymmetry, references over " << idx.size()
              << " lit-and-seen triples (grazing included) / kernels where NoL, NoV >= 0.05\n";
    for (const Case& c : grid()) {
        const Material m = make(c, dvec3(1.0));
        const bool expect = c.model == "minnaert_1941" || c.model == "minnaert_normalized" ||
                            (c.model == "minnaert_unity" && c.value >= 0.0) ||
                            (c.model == "minnaert_blender" && c.value <= 1.0);
        const auto fwd = eval_kernel(m, N, L, V), bwd = eval_kernel(m, N, V, L);
        double asym_ref = 0.0, asym_k = 0.0;
        for (std::size_t j = 0; j < idx.size(); ++j) {
            const double NoL = glm::dot(N[j], L[j]), NoV = glm::dot(N[j], V[j]);
            const double a = ref::eval_material(N[j], L[j], V[j], N[j], m).y / NoL;
            const double b = ref::eval_material(N[j], V[j], L[j], N[j], m).y / NoV;
            // Physical cosines only: the float-rounded vectors give NoL up to 1 + 2e-7, which unity's saturate
            // clips (one-sidedly, 1e-7) - not a property of the model.
            if ((a != 0.0 || b != 0.0) && NoL <= 1.0 && NoV <= 1.0)
                asym_ref = std::max(asym_ref, std::abs(a - b) / std::max(std::abs(a), std::abs(b)));
            if (NoL >= 0.05 && NoV >= 0.05) {
                const double ka = fwd[3 * j + 1] / NoL, kb = bwd[3 * j + 1] / NoV;
                if (ka != 0.0 || kb != 0.0)
                    asym_k = std::max(asym_k, std::abs(ka - kb) / std::max(std::abs(ka), std::abs(kb)));
            }
        }
        std::cout << "  " << std::setw(32) << std::left << label(c) << std::right << std::setw(13) << asym_ref
                  << std::setw(13) << asym_k << (expect ? "   reciprocal\n" : "   not reciprocal\n");
        INFO(label(c) << ": asymmetry reference " << asym_ref << ", kernel " << asym_k);
        if (expect) {
            CHECK(asym_ref < 1e-12);
            // float values (a few ulp) divided by float-vs-double cosines >= 0.05 (2e-7 / 0.05 = 4e-6)
            CHECK(asym_k < 2e-5);
        } else {
            CHECK(asym_ref > 1e-2);
            CHECK(asym_k > 1e-2);
        }
    }
    // The catalogue flag means "reciprocal over the whole parameter range" (per-parameter table in the docs).
    for (const char* name : {"minnaert_1941", "minnaert_normalized"}) CHECK(find_model(name).reciprocal);
    for (const char* name : {"minnaert_unity", "minnaert_blender", "minnaert_b"}) CHECK_FALSE(find_model(name).reciprocal);
}

TEST_CASE("minnaert white furnace: directional albedo vs parameter, closed forms at V = N, flags",
          "[minnaert][physics]") {
    const std::vector<double> deg = {0.0, 30.0, 60.0, 80.0, 89.0};
    std::cout << "white furnace (kernel, albedo 1): (1/pi) integral value dL, view at 0/30/60/80/89 deg; "
              << "closed form at V = N\n";
    std::map<std::string, double> max_w;
    for (const Case& c : grid()) {
        const Material m = make(c, dvec3(1.0));
        const auto w = furnace(m, deg);
        double closed = std::nan("");
        const double k = c.value;
        if (c.model == "minnaert_1941") closed = 2.0 * guarded_moment(k);
        if (c.model == "minnaert_normalized") closed = (k + 1.0) * guarded_moment(k);
        if (c.model == "minnaert_unity") closed = 2.0 / (2.0 + k);   // NoV = 1: min(1, mu^(1+k)) = mu^(1+k)
        if (c.model == "minnaert_blender") {
            const double cl = double(0.1f);   // d <= 1: mu max(mu, 0.1)^(d-1); d > 1: mu 0.001^(d-1)
            closed = k <= 1.0 ? 2.0 * (std::pow(cl, k + 1.0) / 2.0 + (1.0 - std::pow(cl, k + 1.0)) / (k + 1.0))
                              : std::pow(0.001, k - 1.0);
        }
        if (c.model == "minnaert_b") closed = k < 1.0 ? 0.0 : 2.0 / 3.0;   // (1 - NoV)^(1-k) = 0 at V = N
        std::cout << "  " << std::setw(32) << std::left << label(c) << std::right;
        for (double x : w) std::cout << std::setw(11) << x;
        std::cout << "   V=N closed form " << closed << "\n";
        INFO(label(c) << ": furnace at V = N " << w[0] << ", closed form " << closed);
        for (double x : w) CHECK(std::isfinite(x));
        CHECK(w[0] == Approx(closed).epsilon(1e-5).margin(1e-9));
        if (c.model == "minnaert_1941" || c.model == "minnaert_normalized") {
            // Every view angle: 2 g(NoV) I(k) (times (k+1)/2), g the guarded NoV^(k-1) (NoV >= 0.017 > eps here).
            for (std::size_t a = 0; a < deg.size(); ++a) {
                const double mu = std::cos(deg[a] * M_PI / 180.0);
                const double scale = c.model == "minnaert_normalized" ? (k + 1.0) / 2.0 : 1.0;
                CHECK(w[a] == Approx(scale * 2.0 * std::pow(mu, k - 1.0) * guarded_moment(k)).epsilon(1e-5));
            }
        }
        if (c.model == "minnaert_unity" && k == -1.0)
            for (double x : w) CHECK(x == Approx(2.0).epsilon(1e-6));   // saturate(1/NoV) = 1 everywhere lit
        max_w[c.model] = std::max(max_w[c.model], *std::max_element(w.begin(), w.end()));
    }
    for (const auto& [name, mw] : max_w) {
        INFO(name << ": largest directional albedo over the grid " << mw);
        if (find_model(name).energy_conserving)
            CHECK(mw <= 1.0 + 1e-6);
        else
            CHECK(mw > 1.0);
    }
}

TEST_CASE("minnaert_normalized: directional albedo at normal incidence is the albedo for every k",
          "[minnaert][physics]") {
    // Fix L = N and integrate f_r NoV over the view hemisphere: (k+1)/2 * 2 * integral mu^k dmu = 1, less the
    // limb guard's share (k+1) * eps^(k+1) * (1/(k+1) - 1/3) (6.7e-4 at k = 0, < 3.5e-5 for k >= 0.5).
    // At oblique incidence mu_i the same integral is mu_i^(k-1): only normal incidence is normalised.
    std::cout << "minnaert_normalized directional albedo, light at 0 / 60 / 85 deg (kernel), vs mu_i^(k-1):\n";
    for (double k : {0.0, 0.25, 0.5, 0.7, 1.0, 1.5, 2.0}) {
        const auto a = furnace(make("minnaert_normalized", "k", k, dvec3(1.0)), {0.0, 60.0, 85.0}, true);
        const double guarded = (k + 1.0) * guarded_moment(k);
        std::cout << "  k=" << std::setw(5) << std::left << k << std::right << std::setw(12) << a[0] << std::setw(12)
                  << a[1] << " (" << std::pow(0.5, k - 1.0) << ")" << std::setw(12) << a[2] << " ("
                  << std::pow(std::cos(85.0 * M_PI / 180.0), k - 1.0) << ")\n";
        INFO("k " << k);
        CHECK(a[0] == Approx(guarded).epsilon(1e-5));
        CHECK(std::abs(a[0] - 1.0) < 7e-4);
        CHECK(a[1] == Approx(guarded * std::pow(0.5, k - 1.0)).epsilon(1e-5));
    }
}

// ---- 4. stability: where the formulas break ----------------------------------------------------------

TEST_CASE("minnaert limb: NoV -> 0 with k < 1 stays finite, held at eps^(k-1) and faded to 0", "[minnaert][stability]") {
    const dvec3 N{0, 0, 1}, L{0, 0, 1};
    const std::vector<double> nov = {0.1, 1e-2, 2e-3, 1e-3, 5e-4, 1e-4, 1e-6, 1e-9, 0.0, -1e-6, -1e-3};
    std::vector<dvec3> Ns, Ls, Vs;
    for (double c : nov) {
        Ns.push_back(N);
        Ls.push_back(L);
        Vs.push_back({std::sqrt(1.0 - c * c), 0.0, c});
    }
    std::cout << "limb, L = N, NoV = ";
    for (double c : nov) std::cout << std::setw(10) << c;
    std::cout << "\n";
    for (const Case& c : grid()) {
        const Material m = make(c, dvec3(1.0));
        const auto out = eval_kernel(m, Ns, Ls, Vs);
        std::cout << "  " << std::setw(30) << std::left << label(c) << std::right;
        for (std::size_t i = 0; i < nov.size(); ++i) std::cout << std::setw(10) << out[3 * i + 1];
        std::cout << "\n";
        for (std::size_t i = 0; i < nov.size(); ++i) {
            const double v = out[3 * i + 1], cv = double(float(nov[i]));   // N = z: the dot is exact
            INFO(label(c) << " at NoV " << cv << ": kernel " << v);
            REQUIRE(std::isfinite(v));
            const double k = c.value;
            double expect = 0.0;   // what the documentation says each model returns at the limb
            if (c.model == "minnaert_1941" || c.model == "minnaert_normalized") {
                const double scale = c.model == "minnaert_normalized" ? (k + 1.0) / 2.0 : 1.0;
                const double e = k < 1.0 ? kEps : 0.0;
                if (cv > 0.0) expect = scale * (cv >= e ? std::pow(cv, k - 1.0) : std::pow(e, k - 1.0) * cv / e);
                if (k < 1.0) CHECK(v <= scale * std::pow(kEps, k - 1.0) * (1.0 + 1e-6));   // the bound
            } else if (c.model == "minnaert_unity") {
                const double nv = std::max(cv, 0.0);
                expect = nv > 0.0 ? std::min(1.0, std::pow(nv, k)) : (k > 0.0 ? 0.0 : 1.0);   // seed: pow(0, k)
            } else if (c.model == "minnaert_blender") {
                const double nv = std::max(cv, 0.0);
                expect = k <= 1.0 ? std::pow(std::max(nv, double(0.1f)), k - 1.0) : std::pow(1.001 - nv, k - 1.0);
            } else if (c.model == "minnaert_b") {
                expect = std::pow(1.0 - std::max(cv, 0.0), 1.0 - k);
            }
            CHECK(v == Approx(expect).epsilon(2e-6).margin(1e-30));
        }
    }
}

TEST_CASE("minnaert pow(0, 0), exactly grazing and below-horizon light, V = N", "[minnaert][stability]") {
    const dvec3 N{0, 0, 1};
    // NoL = 0 exactly (pow(0, 0) at k = 0), NoL = 1e-30, NoL < 0; V = N exactly; NoL NoV = 1e-40 (underflow).
    const std::vector<dvec3> L = {{1, 0, 0}, {1, 0, 1e-30}, {0.6, 0, -0.8}, {0, 0, 1}, {1, 0, 1e-25}};
    const std::vector<dvec3> V = {{0, 0.6, 0.8}, {0, 0.6, 0.8}, {0, 0.6, 0.8}, {0, 0, 1}, {1, 0, 1e-15}};
    const std::vector<dvec3> Ns(L.size(), N);
    std::cout << "stability: NoL = 0 | NoL = 1e-30 | NoL = -0.8 | L = V = N | NoL NoV = 1e-40\n";
    for (const Case& c : grid()) {
        const Material m = make(c, dvec3(1.0));
        const auto out = eval_kernel(m, Ns, L, V);
        std::cout << "  " << std::setw(30) << std::left << label(c) << std::right;
        for (std::size_t i = 0; i < L.size(); ++i) std::cout << std::setw(13) << out[3 * i + 1];
        std::cout << "\n";
        INFO(label(c));
        for (float x : out) CHECK(std::isfinite(x));
        CHECK(out[0 * 3 + 1] == 0.0f);   // NoL = 0: 0 (pow(0, 0) = 1 never reaches the result)
        CHECK(out[2 * 3 + 1] == 0.0f);   // light below the horizon
        // Light 1e-30 above the horizon and the 1e-40 product: what the formula says, to float precision
        // (denormal results may be flushed, hence the margin). Unity at k = -1 gives 1 there: its value
        // saturate(NoL^0 NoV^-1) has no terminator falloff at all (the 1941 k = 0 law, unguarded).
        for (std::size_t i : {std::size_t(1), std::size_t(4)}) {
            const double r = ref::eval_material(N, L[i], V[i], N, m).y;
            CHECK(out[3 * i + 1] == Approx(r).epsilon(1e-5).margin(1e-37));
        }
        const double k = c.value;
        double at_normal = 1.0;   // L = V = N
        if (c.model == "minnaert_blender" && k > 1.0) at_normal = std::pow(0.001, k - 1.0);
        if (c.model == "minnaert_b") at_normal = k < 1.0 ? 0.0 : 1.0;
        if (c.model == "minnaert_normalized") at_normal = (k + 1.0) / 2.0;
        CHECK(out[3 * 3 + 1] == Approx(at_normal).epsilon(1e-6).margin(1e-30));
        CHECK(out[4 * 3 + 1] >= 0.0f);
        CHECK(out[4 * 3 + 1] <= 1.0f);
    }
}

// ---- 5. the planetary view: zero-phase disc profile, end to end ------------------------------------

TEST_CASE("minnaert_1941 at zero phase gives the disc profile mu^(2k-1), end to end through shade()",
          "[minnaert][e2e]") {
    // A unit sphere seen orthographically along +z, lit from the viewer (zero phase): at disc radius r the
    // normal has NoL = NoV = mu = sqrt(1 - r^2), and Minnaert's law gives I(r) = B0 E mu^(2k-1).
    FragmentBuffer fb;
    const int n = 160;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const double px = 2.0 * (x + 0.5) / n - 1.0, py = 2.0 * (y + 0.5) / n - 1.0, r2 = px * px + py * py;
            if (r2 >= 1.0) continue;
            const glm::vec3 nrm = glm::normalize(glm::vec3(float(px), float(py), float(std::sqrt(1.0 - r2))));
            fb.push_back(nrm.x, nrm.y, nrm.z, nrm.x, nrm.y, nrm.z, y * n + x, 1.0f);
        }
    fb.width = fb.height = n;
    const double E = 1.7, B0 = 0.12;
    Shader shader(test::runtime());
    std::cout << "zero-phase disc, " << fb.size() << " pixels: max rel error vs B0 E mu^(2k-1) (mu >= 0.02)\n";
    for (double k : {0.3, 0.5, 0.7, 1.0, 1.3}) {
        ShadeSetup setup;
        setup.material = make("minnaert_1941", "k", k, dvec3(B0));
        setup.lights = {Light{Light::Type::Directional, {0, 0, 1}, {1, 1, 1}, E, 0.0}};
        setup.view = glm::dvec4(0.0, 0.0, 1.0, 0.0);
        const auto rgb = shader.shade(fb, setup);
        double worst = 0.0, centre = 0.0, edge = 0.0, edge_mu = 2.0;
        for (std::size_t i = 0; i < fb.size(); ++i) {
            const double mu = double(fb.nz[i]);   // N.z of the float normal: NoL = NoV exactly
            const double expect = B0 * E * std::pow(mu, 2.0 * k - 1.0);
            REQUIRE(std::isfinite(rgb[fb.size() + i]));
            if (mu >= 0.02) worst = std::max(worst, std::abs(rgb[fb.size() + i] - expect) / expect);
            if (mu > 0.999) centre = rgb[fb.size() + i];
            if (mu < edge_mu) { edge_mu = mu; edge = rgb[fb.size() + i]; }
        }
        std::cout << "  k=" << k << ": max rel err " << worst << "; centre " << centre << ", outermost pixel (mu "
                  << edge_mu << ") " << edge << "\n";
        INFO("k " << k);
        CHECK(worst < 5e-6);
        if (k == 0.5) CHECK(edge == Approx(centre).epsilon(1e-5));   // the flat disc
    }
}
