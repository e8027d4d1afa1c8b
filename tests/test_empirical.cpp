// The empirical family (ISIS's MinnaertEmpirical and LunarLambertEmpirical as catalogue models:
// kernels/models/empirical.cl, host/models/empirical.cpp, host/reference/empirical_ref.cpp,
// docs/models/empirical.md). Layers: (1) the spline the table buffer is packed from (host/core/spline.hpp): its
// per-segment cubics are the spline, natural ends, knots interpolated; (2) the kernel against the double reference
// over the standard sweep for tables of 2, 3, 7 and 32 knots, some covering part of the phase range only (phases
// outside the table: the continued end cubics); (3) stability: grazing, g -> 0 and g -> 180, no NaN/Inf; (4) the
// catalogue kernel against ISIS's path (`photometry eval --pvl`, kernels/photometry.cl eval_empirical with the
// splines in double) on the same table; (5) the registration's checks of table parameters.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <random>

#include "core/spline.hpp"
#include "photometry/isis.hpp"
#include "reference/reference.hpp"
#include "support.hpp"

using namespace shadelab;

namespace {

constexpr double kDeg = M_PI / 180.0;

// A table of `n` knots from `first` to `last` degrees: K or L and B smooth functions of phase (a lunar-like
// K rising from 0.5, L falling from 1, B falling from 1).
struct Tables { std::vector<double> phase, param, bright; };
Tables tables(int n, double first, double last, bool minnaert) {
    Tables t;
    for (int j = 0; j < n; ++j) {
        const double g = first + (last - first) * j / (n - 1);
        t.phase.push_back(g);
        t.param.push_back(minnaert ? 0.5 + 0.4 * std::sin(g * kDeg * 0.5) : 1.0 - 0.8 * g / 180.0);
        t.bright.push_back(1.0 / (1.0 + 0.02 * g) + 0.05 * std::cos(0.1 * g));
    }
    return t;
}

Material empirical(bool minnaert, const Tables& t, glm::dvec3 albedo = test::kAlbedo) {
    Material m;
    m.model = minnaert ? "minnaert_empirical" : "lunar_lambert_empirical";
    m.tables = {{"phase_list", t.phase}, {minnaert ? "k_list" : "l_list", t.param}, {"phase_curve_list", t.bright}};
    m.albedo = albedo;
    return resolve_material(m);
}

// Relative errors of one class of values: max and p99.
struct Rel {
    std::vector<double> v;
    double max() const { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }
    double p99() {
        if (v.empty()) return 0.0;
        std::sort(v.begin(), v.end());
        return v[v.size() * 99 / 100];
    }
};

struct Sweep { Rel inside, outside; std::size_t non_finite = 0, zero_mismatch = 0; };

// The kernel (eval_directions) against the reference over the standard sweep: relative error where both cosines
// are >= 0.02 (away from the limb guard's taper), apart for phases inside the table and outside it (where the end
// cubics are continued: their terms cancel, up to 180 degrees from their knot), and exact zeros where the
// reference is 0 behind the horizon.
Sweep kernel_vs_reference(const Material& m) {
    const auto& s = test::sweep();
    const auto& x = m.tables.at("phase_list");
    Shader shader(test::runtime());
    const auto out = shader.eval_directions(m, s.N, s.L, s.V, s.P);
    Sweep r;
    for (std::size_t i = 0; i < s.size(); ++i) {
        const glm::dvec3 ref = ref::eval_material(s.dN[i], s.dL[i], s.dV[i], s.dP[i], m);
        const double NoL = glm::dot(s.dN[i], s.dL[i]), NoV = glm::dot(s.dN[i], s.dV[i]);
        const glm::dvec3 l = glm::normalize(s.dL[i]), v = glm::normalize(s.dV[i]);
        const double g = 2.0 * std::atan2(glm::length(l - v), glm::length(l + v)) / kDeg;
        for (int c = 0; c < 3; ++c) {
            const double k = out[3 * i + std::size_t(c)];
            if (!std::isfinite(k) || !std::isfinite(ref[c])) ++r.non_finite;
            if (ref[c] == 0.0 && (NoL < -1e-6 || NoV < -1e-6) && k != 0.0) ++r.zero_mismatch;
            if (NoL < 0.02 || NoV < 0.02 || std::abs(ref[c]) < 1e-4) continue;
            (g >= x.front() && g <= x.back() ? r.inside : r.outside).v.push_back(std::abs(k - ref[c]) / std::abs(ref[c]));
        }
    }
    return r;
}

}  // namespace

TEST_CASE("empirical: the spline's per-segment cubics (what the table buffer holds) are the spline, with natural "
          "ends, inside and beyond the table", "[empirical]") {
    for (int n : {2, 3, 7, 32}) {
        const Tables t = tables(n, 10.0, 150.0, true);
        const NaturalSpline s(t.phase, t.param);
        double worst = 0.0, knot_err = 0.0;
        for (int q = 0; q <= 1800; ++q) {
            const double g = 0.1 * q;   // 0 .. 180: below, inside and above the table
            std::size_t k = 0;
            while (k + 2 < t.phase.size() && g >= t.phase[k + 1]) ++k;
            const auto c = s.local_cubic(k);
            const double x = g - t.phase[k], v = c[0] + x * (c[1] + x * (c[2] + x * c[3]));
            worst = std::max(worst, std::abs(v - s(g)));
        }
        for (std::size_t j = 0; j < t.phase.size(); ++j) knot_err = std::max(knot_err, std::abs(s(t.phase[j]) - t.param[j]));
        INFO(n << " knots: cubic vs spline " << worst << ", at the knots " << knot_err);
        CHECK(worst <= 1e-12);
        CHECK(knot_err <= 1e-14);
        // natural ends: the second derivative 2 c2 of the first and of the last interval at its outer knot is 0
        const auto c0 = s.local_cubic(0), cl = s.local_cubic(t.phase.size() - 2);
        const double h = t.phase.back() - t.phase[t.phase.size() - 2];
        CHECK(std::abs(2.0 * c0[2]) <= 1e-14);
        CHECK(std::abs(2.0 * cl[2] + 6.0 * cl[3] * h) <= 1e-12);
    }
}

TEST_CASE("empirical: kernel against the double reference over the standard sweep, tables of 2, 3, 7 and 32 knots "
          "(phases outside the table included), no NaN/Inf", "[empirical][kernel]") {
    struct Case { int n; double first, last; };
    const Case cases[] = {{2, 0, 180}, {3, 20, 100}, {7, 0, 150}, {32, 5, 175}, {7, 40, 90}};
    for (bool minnaert : {true, false}) {
        std::vector<Material> ms = {resolve_material(Material{minnaert ? "minnaert_empirical" : "lunar_lambert_empirical",
                                                              {}, {}, test::kAlbedo})};
        for (const Case& c : cases) ms.push_back(empirical(minnaert, tables(c.n, c.first, c.last, minnaert)));
        for (const Material& m : ms) {
            Sweep s = kernel_vs_reference(m);
            const auto& x = m.tables.at("phase_list");
            std::cout << "empirical: " << m.model << " " << x.size() << " knots " << x.front() << ".." << x.back()
                      << ": kernel vs reference, inside the table " << s.inside.v.size() << " values: max rel "
                      << s.inside.max() << ", p99 " << s.inside.p99() << "; outside " << s.outside.v.size()
                      << " values: max rel " << s.outside.max() << ", p99 " << s.outside.p99() << "\n";
            INFO(m.model << " " << x.size() << " knots " << x.front() << ".." << x.back() << ": max rel inside "
                         << s.inside.max() << ", outside " << s.outside.max());
            CHECK(s.inside.v.size() + s.outside.v.size() > 100000);
            CHECK(s.non_finite == 0);
            CHECK(s.zero_mismatch == 0);
            CHECK(s.inside.max() <= 2e-5);
            CHECK(s.inside.p99() <= 2e-6);
            CHECK(s.outside.max() <= 5e-4);   // the continued cubic far from its knot: its terms cancel
            CHECK(s.outside.p99() <= 2e-5);
        }
    }
}

TEST_CASE("empirical: stable at grazing incidence and emission, at g -> 0 and g -> 180 (finite, the reference's "
          "value, 0 behind the horizon)", "[empirical][edges]") {
    std::vector<float> N, L, V, P;
    std::vector<glm::dvec3> dN, dL, dV;
    auto add = [&](glm::dvec3 n, glm::dvec3 l, glm::dvec3 v) {
        n = glm::normalize(n), l = glm::normalize(l), v = glm::normalize(v);
        for (int c = 0; c < 3; ++c) {
            N.push_back(float(n[c])); L.push_back(float(l[c])); V.push_back(float(v[c])); P.push_back(0.0f);
        }
        dN.push_back(glm::dvec3(float(n.x), float(n.y), float(n.z)));
        dL.push_back(glm::dvec3(float(l.x), float(l.y), float(l.z)));
        dV.push_back(glm::dvec3(float(v.x), float(v.y), float(v.z)));
    };
    for (double e : {0.0, 1e-7, 1e-5, 1e-3, 0.1, 1.0}) {   // radians from grazing / from each other
        add({0, 0, 1}, {std::cos(e), 0, std::sin(e)}, {0, 0, 1});                     // grazing incidence
        add({0, 0, 1}, {0, 0, 1}, {std::cos(e), 0, std::sin(e)});                     // grazing emission
        add({0, 0, 1}, {std::cos(e), 0, std::sin(e)}, {0, std::cos(e), std::sin(e)}); // both grazing
        add({0, 0, 1}, {std::sin(0.3), 0, std::cos(0.3)}, {std::sin(0.3 + e), 0, std::cos(0.3 + e)});   // g -> 0
        add({0, 0, 1}, {std::cos(e), 0, std::sin(e)}, {-std::cos(e), 0, std::sin(e)});  // g -> 180
        add({0, 0, 1}, {1, 0, -e}, {-1, 0, e});                                          // g = 180, L below
    }
    add({0, 0, 1}, {0, 0, 1}, {0, 0, 1});     // g = 0 exactly
    add({0, 0, 1}, {1, 0, 0}, {-1, 0, 0});    // g = 180 exactly, both grazing
    Shader shader(test::runtime());
    for (bool minnaert : {true, false})
        for (const Tables& t : {tables(7, 0, 150, minnaert), tables(3, 30, 60, minnaert)}) {
            const Material m = empirical(minnaert, t, glm::dvec3(1.0));
            const auto out = shader.eval_directions(m, N, L, V, P);
            for (std::size_t i = 0; i < dN.size(); ++i) {
                const double r = ref::eval_material(dN[i], dL[i], dV[i], {}, m).x, k = out[3 * i];
                INFO(m.model << " case " << i << ": kernel " << k << ", reference " << r);
                CHECK(std::isfinite(k));
                CHECK(std::isfinite(r));
                CHECK(std::abs(k - r) <= 1e-5 * std::max(1.0, std::abs(r)));
            }
        }
}

TEST_CASE("empirical: the catalogue kernel agrees with ISIS's path (photometry eval --pvl, the splines in double) "
          "on the same table to float rounding", "[empirical][isis]") {
    const auto dir = test::scratch_dir("empirical-isis");
    std::mt19937_64 gen(29);
    for (bool minnaert : {true, false}) {
        const Tables t = tables(7, 0, 150, minnaert);
        auto list = [](const std::vector<double>& v) {
            std::ostringstream s;
            s.precision(17);
            for (std::size_t j = 0; j < v.size(); ++j) s << (j ? ", " : "(") << v[j];
            return s.str() + ")";
        };
        const std::string pvl = (dir / (minnaert ? "m.pvl" : "l.pvl")).string();
        std::ofstream(pvl) << "Object = PhotometricModel\n  Group = Algorithm\n    Name = "
                           << (minnaert ? "MinnaertEmpirical" : "LunarLambertEmpirical") << "\n    PhaseList = "
                           << list(t.phase) << "\n    " << (minnaert ? "KList" : "LList") << " = " << list(t.param)
                           << "\n    PhaseCurveList = " << list(t.bright) << "\n  End_Group\nEnd_Object\nEnd\n";
        const photometry::Law law = photometry::law_from_pvl_file(pvl);
        const Material m = empirical(minnaert, t, glm::dvec3(1.0));
        // facets with i, e < 87 deg at random azimuths: the geometry in degrees for ISIS's path, vectors for the kernel
        std::vector<photometry::Geometry> rows;
        std::vector<float> N, L, V, P;
        for (int j = 0; j < 20000; ++j) {
            const double i = 87.0 * test::unit_double(gen), e = 87.0 * test::unit_double(gen), psi = 180.0 * test::unit_double(gen);
            const glm::dvec3 l{std::sin(i * kDeg), 0, std::cos(i * kDeg)};
            const glm::dvec3 v{std::sin(e * kDeg) * std::cos(psi * kDeg), std::sin(e * kDeg) * std::sin(psi * kDeg), std::cos(e * kDeg)};
            const double g = 2.0 * std::atan2(glm::length(l - v), glm::length(l + v)) / kDeg;
            rows.push_back({g, i, e});
            for (int c = 0; c < 3; ++c) {
                N.push_back(c == 2 ? 1.0f : 0.0f); L.push_back(float(l[c])); V.push_back(float(v[c])); P.push_back(0.0f);
            }
        }
        const auto isis = photometry::evaluate(test::runtime(), law, rows, Precision::Precise, true);
        Shader shader(test::runtime());
        const auto cat = shader.eval_directions(m, N, L, V, P);
        double max_rel = 0.0;
        for (std::size_t j = 0; j < rows.size(); ++j) {
            const double r = photometry::evaluate_reference(law, rows[j]);
            if (std::abs(r) < 1e-3) continue;
            max_rel = std::max(max_rel, std::abs(double(cat[3 * j]) - isis[j]) / std::abs(r));
        }
        std::cout << "empirical: " << m.model << ": catalogue kernel vs photometry eval --pvl, max rel " << max_rel
                  << " over " << rows.size() << " facets\n";
        INFO(m.model << ": max rel " << max_rel);
        CHECK(max_rel <= 5e-6);
    }
}

TEST_CASE("empirical: table parameters are checked with one clear line (ISIS's names accepted)", "[empirical][registration]") {
    auto with = [](std::map<std::string, std::vector<double>> tabs) {
        Material m;
        m.model = "minnaert_empirical";
        m.tables = std::move(tabs);
        return resolve_material(m, "test");
    };
    // ISIS's names, and the defaults for the tables not given
    const Material isis = with({{"PhaseList", {0, 60, 120}}, {"KList", {0.5, 0.6, 0.7}}, {"phasecurvelist", {1, 0.7, 0.4}}});
    CHECK(isis.tables.at("k_list") == std::vector<double>{0.5, 0.6, 0.7});
    CHECK(isis.tables.at("phase_curve_list") == std::vector<double>{1, 0.7, 0.4});
    const Material def = with({});
    CHECK(def.tables.at("phase_list") == find_model("minnaert_empirical").tables.front().def);
    auto fails = [&](std::map<std::string, std::vector<double>> tabs, const std::string& text) {
        INFO("expected: " << text);
        CHECK_THROWS_WITH(with(std::move(tabs)), Catch::Contains(text));
    };
    fails({{"phase_list", {0, 60, 50}}, {"k_list", {0.5, 0.6, 0.7}}, {"phase_curve_list", {1, 0.7, 0.4}}},
          "table 'phase_list' of model 'minnaert_empirical' is not increasing: entry 3 = 50 follows 60");
    fails({{"phase_list", {0, 60, 190}}, {"k_list", {0.5, 0.6, 0.7}}, {"phase_curve_list", {1, 0.7, 0.4}}},
          "entry 3 is 190: allowed range is [0, 180]");
    fails({{"phase_list", {0, 60}}, {"k_list", {0.5, 0.6, 0.7}}, {"phase_curve_list", {1, 0.7}}},
          "table 'k_list' of model 'minnaert_empirical' has 3 entries but 'phase_list' has 2");
    fails({{"phase_list", {0}}, {"k_list", {0.5}}, {"phase_curve_list", {1}}}, "has 1 entries: allowed 2 to 32");
    std::vector<double> many(33);
    for (std::size_t j = 0; j < many.size(); ++j) many[j] = double(j);
    fails({{"phase_list", many}, {"k_list", std::vector<double>(33, 0.5)}, {"phase_curve_list", std::vector<double>(33, 1.0)}},
          "has 33 entries: allowed 2 to 32");
    fails({{"phase_list", {0, 60, 120}}, {"k_list", {0.5, NAN, 0.7}}, {"phase_curve_list", {1, 0.7, 0.4}}},
          "table 'k_list' of model 'minnaert_empirical' entry 2 is nan");
    fails({{"phase_list", {0, 60, 120}}, {"k_list", {0.5, 0.6, 0.7}}, {"bogus", {1, 2, 3}}},
          "model 'minnaert_empirical' has no table parameter 'bogus'");
    // a steep table whose continued end cubic runs out of range before 180 degrees
    fails({{"phase_list", {0, 10, 20}}, {"k_list", {0.2, 1.0, 2.0}}, {"phase_curve_list", {1, 0.9, 0.8}}},
          "table 'k_list' of model 'minnaert_empirical': its spline is");
    // a blend cannot take a table model as a child
    Material g;
    g.model = "gradient";
    g.children = {Material{"minnaert_empirical"}, Material{"lambert"}};
    CHECK_THROWS_WITH(resolve_material(g), Catch::Contains("a blend's children read no table buffer"));
}
