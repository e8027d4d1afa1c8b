// Wrap family (half-Lambert, seed 001's squared wrap, Filament's energy-conserving wrap): the kernels
// against the double references over the whole sphere and a parameter grid, identities between the
// models, the seed variants' measured deviation, directional albedo against closed forms, reciprocity
// flags and the kernels' values at the known edge points.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>

#include "cl/runtime.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"
#include "support.hpp"

using namespace shadelab;

namespace {

constexpr double kU = 0x1p-24;   // unit roundoff of float
// |float dot(a, b) - dot(a, b)| for unit float vectors: three products and two sums, gamma_3 <= 3u,
// taken as 4u for the |a||b| = 1 +- 1e-7 of float-rounded unit vectors.
constexpr double kDeltaNoL = 4 * kU;
// The tight relative bound where the value is not tiny and well conditioned: the kernel's arithmetic
// after NoL is a handful of roundings (<= ~6u = 3.6e-7); "a few 1e-6".
constexpr double kTightRel = 2e-6;
constexpr double kValueFloor = 1e-3;   // "not tiny"
// Well conditioned: the value moves by at most 1e-6 relative when NoL moves by kDeltaNoL.
constexpr double kCondRel = 1e-6;

// A light direction with NoL = x for N = +z.
glm::dvec3 light_at(double x) { return {std::sqrt(std::max(0.0, 1.0 - x * x)), 0.0, x}; }

// The reference's own sensitivity to a float-rounding change of NoL: every wrap model depends on L only
// through dot(N, L), so moving L by +-kDeltaNoL * N / |N|^2 moves NoL by exactly +-kDeltaNoL. The bound is
// the larger change of the reference value (per channel); it covers the kinks (clamps) as well.
glm::dvec3 nol_sensitivity(const Material& m, const glm::dvec3& N, const glm::dvec3& L, const glm::dvec3& V,
                           const glm::dvec3& P, const glm::dvec3& r) {
    const glm::dvec3 dL = N * (kDeltaNoL / glm::dot(N, N));
    const glm::dvec3 up = ref::eval_material(N, L + dL, V, P, m), dn = ref::eval_material(N, L - dL, V, P, m);
    return glm::max(glm::abs(up - r), glm::abs(dn - r));
}

// The kernel over the standard sweep against the reference, with the NoL sensitivity as the input bound.
test::ConditionedResult check_sweep(const Material& m) {
    return test::check_conditioned(m, {kTightRel, kValueFloor, kCondRel, 0.0}, [&](const test::Compared& v) {
        return nol_sensitivity(m, v.N(), v.L(), v.V(), v.P(), v.reference[v.i]);
    });
}

}  // namespace

TEST_CASE("wrap kernels match the double references over the sphere and the parameter grid", "[wrap][kernel]") {
    std::vector<Material> grid = {test::material("half_lambert"), test::material("half_lambert_seed001")};
    for (double a : {0.5, 0.75, 1.0}) {
        grid.push_back(test::material("wrap", {{"wrap_value", a}}));
        grid.push_back(test::material("wrap_seed001", {{"wrap_value", a}}));
    }
    for (double w : {0.0, 0.5, 1.0}) grid.push_back(test::material("wrap_energy", {{"w", w}}));
    std::cout << "wrap kernels vs double reference, " << test::sweep().size() << " triples; conditioned: |ref| >= "
              << kValueFloor << " and a " << kDeltaNoL << " change of NoL moves it <= " << kCondRel << " relative\n";
    for (const Material& m : grid) {
        const test::ConditionedResult r = check_sweep(m);
        const test::KernelVsReference& e = r.e;
        std::cout << "  " << std::left << std::setw(36) << test::describe(m, true) << std::right << " max abs "
                  << std::setw(10) << e.max_abs << "  max rel " << std::setw(10) << e.max_rel << "  conditioned: " << r.cond
                  << " values, max rel " << r.max_rel_cond << "; rest: " << r.rest << " values, max err/bound "
                  << e.worst_ratio << "\n";
        // |k - r| <= 2e-6 |r| where conditioned, <= 2e-6 |r| + the reference's change over NoL +- 4u elsewhere
        test::expect_within(e, test::sweep().size());
        CHECK(r.cond > 0);
    }
}

TEST_CASE("wrap identities: w = 0.5 is half-Lambert, wrap_energy(0) is Lambert, wrap(1) is max(0, NoL)^2",
          "[wrap][kernel][identity]") {
    const auto& s = test::sweep();
    Shader shader(test::runtime());
    auto run = [&](const Material& m) { return shader.eval_directions(m, s.N, s.L, s.V, s.P); };
    const auto half = run(test::material("half_lambert"));
    const auto w05 = run(test::material("wrap", {{"wrap_value", 0.5}}));
    const auto lam = run(test::material("lambert"));
    const auto e0 = run(test::material("wrap_energy", {{"w", 0.0}}));
    const auto w1 = run(test::material("wrap", {{"wrap_value", 1.0}}));
    const glm::dvec3 albedo{0.9, 0.5, 0.25};
    double d_half = 0.0, d_lam = 0.0, d_sq = 0.0;
    for (std::size_t i = 0; i < half.size(); ++i) {
        const double a = albedo[int(i % 3)];
        d_half = std::max(d_half, std::abs(double(half[i]) - double(w05[i])));
        d_lam = std::max(d_lam, std::abs(double(lam[i]) - double(e0[i])));
        // wrap(1) / albedo == (lambert / albedo)^2 up to a few roundings of values <= 1
        d_sq = std::max(d_sq, std::abs(double(w1[i]) / a - std::pow(double(lam[i]) / a, 2.0)));
    }
    std::cout << "wrap identities (kernel): |half_lambert - wrap(0.5)| <= " << d_half
              << ", |lambert - wrap_energy(0)| <= " << d_lam << ", |wrap(1) - NoL+^2| <= " << d_sq << "\n";
    // Same arithmetic except the base clamp, which only acts at NoL < -1 (float unit vectors), where the
    // square is ~1e-14.
    CHECK(d_half <= 1e-12);
    // Identical except where float NoL exceeds 1 by ~1e-7 (the saturate clips it, Lambert does not).
    CHECK(d_lam <= 4 * kU);
    CHECK(d_sq <= 8 * kU);
    // In the references the identities are exact up to double rounding, for every triple.
    double r_half = 0.0, r_lam = 0.0;
    const Material mh = test::material("half_lambert"), mw = test::material("wrap", {{"wrap_value", 0.5}});
    const Material ml = test::material("lambert"), me = test::material("wrap_energy", {{"w", 0.0}});
    for (std::size_t i = 0; i < s.size(); ++i) {
        const auto& N = s.dN[i];
        const auto& L = s.dL[i];
        r_half = std::max(r_half, glm::length(ref::eval_material(N, L, N, N, mh) - ref::eval_material(N, L, N, N, mw)));
        const double NoL = glm::dot(N, L);
        if (NoL <= 1.0)   // saturate's upper clip only for float-rounded NoL > 1
            r_lam = std::max(r_lam, glm::length(ref::eval_material(N, L, N, N, ml) - ref::eval_material(N, L, N, N, me)));
    }
    CHECK(r_half <= 1e-15);
    CHECK(r_lam <= 1e-15);
}

TEST_CASE("wrap closed-form values: half-Lambert is 0 at NoL = -1, terminators of the two wraps coincide",
          "[wrap][kernel][identity]") {
    Shader shader(test::runtime());
    const glm::dvec3 white{1.0, 1.0, 1.0};
    // (model, params, NoL, hand-computed value)
    struct Spot { const char* model; std::map<std::string, double> p; double NoL, expect; };
    const std::vector<Spot> spots = {
        {"half_lambert", {}, -1.0, 0.0},          {"half_lambert", {}, 0.0, 0.25},
        {"half_lambert", {}, 0.5, 0.5625},        {"half_lambert", {}, 1.0, 1.0},
        {"half_lambert", {}, -0.5, 0.0625},       {"half_lambert_seed001", {}, -1.0, 0.25},
        {"half_lambert_seed001", {}, -0.5, 0.25}, {"half_lambert_seed001", {}, 0.5, 0.5625},
        {"wrap", {{"wrap_value", 0.75}}, 0.0, 0.0625},
        {"wrap", {{"wrap_value", 0.75}}, -0.5, 0.0},            // beyond its terminator -1/3
        {"wrap", {{"wrap_value", 0.75}}, 1.0, 1.0},
        {"wrap", {{"wrap_value", 1.0}}, -1.0, 0.0},             // without the clamp: (-1)^2 = 1
        {"wrap", {{"wrap_value", 1.0}}, 0.5, 0.25},
        {"wrap_seed001", {{"wrap_value", 0.75}}, -0.5, 0.0625}, // the seed's flat (1 - a)^2 behind
        {"wrap_energy", {{"w", 0.5}}, 0.0, 0.5 / 2.25},         {"wrap_energy", {{"w", 0.5}}, 1.0, 1.5 / 2.25},
        {"wrap_energy", {{"w", 0.5}}, -0.5, 0.0},               {"wrap_energy", {{"w", 1.0}}, -1.0, 0.0},
        {"wrap_energy", {{"w", 1.0}}, 0.0, 0.25},
    };
    std::vector<float> N, L, V, P;
    for (const Spot& sp : spots) {
        const glm::dvec3 l = light_at(sp.NoL);
        N.insert(N.end(), {0.0f, 0.0f, 1.0f});
        L.insert(L.end(), {float(l.x), float(l.y), float(l.z)});
        V.insert(V.end(), {0.0f, 0.0f, 1.0f});
        P.insert(P.end(), {0.0f, 0.0f, 0.0f});
    }
    for (std::size_t i = 0; i < spots.size(); ++i) {
        const Material m = test::material(spots[i].model, spots[i].p, white);
        const auto out = shader.eval_directions(m, N, L, V, P);
        const double ref = ref::eval_material({0, 0, 1}, light_at(spots[i].NoL), {0, 0, 1}, {}, m).x;
        INFO(test::describe(m, true) << " at NoL = " << spots[i].NoL << ": kernel " << out[3 * i] << ", reference " << ref
                         << ", by hand " << spots[i].expect);
        CHECK(std::abs(out[3 * i] - spots[i].expect) <= 1e-6);
        CHECK(std::abs(ref - spots[i].expect) <= 1e-12);
    }
    // The squared wrap with wrap_value a and Fd_Wrap with w = (1 - a) / a vanish from the same NoL on.
    for (double a : {0.5, 0.6, 0.75, 0.9, 1.0}) {
        const double t = -(1.0 - a) / a;
        const Material ms = test::material("wrap", {{"wrap_value", a}}, white), me = test::material("wrap_energy", {{"w", -t}}, white);
        const glm::dvec3 Nz{0, 0, 1};
        auto val = [&](const Material& m, double x) { return ref::eval_material(Nz, light_at(x), Nz, {}, m).x; };
        INFO("wrap_value " << a << ": terminator at NoL = " << t);
        if (t - 1e-3 >= -1.0) {
            CHECK(val(ms, t - 1e-3) == 0.0);
            CHECK(val(me, t - 1e-3) == 0.0);
        }
        CHECK(val(ms, t + 1e-3) > 0.0);
        CHECK(val(me, t + 1e-3) > 0.0);
    }
}

TEST_CASE("wrap seed variants: measured deviation of the NoL-clamped forms from the references", "[wrap][seed]") {
    const auto& s = test::sweep();
    Shader shader(test::runtime());
    std::cout << "wrap seed variants vs references over " << s.size() << " triples (albedo 0.9 in red):\n";
    for (double a : {0.5, 0.75, 1.0}) {
        const Material ref_m = a == 0.5 ? test::material("half_lambert") : test::material("wrap", {{"wrap_value", a}});
        const Material seed_m = a == 0.5 ? test::material("half_lambert_seed001") : test::material("wrap_seed001", {{"wrap_value", a}});
        const auto kr = shader.eval_directions(ref_m, s.N, s.L, s.V, s.P);
        const auto ks = shader.eval_directions(seed_m, s.N, s.L, s.V, s.P);
        double max_dev = 0.0, front_dev = 0.0, sum_back = 0.0;
        std::size_t differ = 0, back = 0;
        for (std::size_t i = 0; i < s.size(); ++i) {
            const double NoL = glm::dot(s.dN[i], s.dL[i]);
            const double d = std::abs(double(ks[3 * i]) - double(kr[3 * i]));
            if (NoL > kDeltaNoL) front_dev = std::max(front_dev, d);
            if (NoL < 0.0) { ++back; sum_back += d; }
            if (d > 0.0) ++differ;
            max_dev = std::max(max_dev, d);
        }
        // Behind the surface the seed form is the constant (1 - a)^2 while the reference falls to 0.
        const double expect = 0.9 * (1.0 - a) * (1.0 - a);
        std::cout << "  " << std::setw(22) << seed_m.model << " a=" << a << ": max deviation " << max_dev
                  << " (closed form " << expect << " at NoL = -1), mean over back-lit triples "
                  << (back ? sum_back / double(back) : 0.0) << ", " << differ << " triples differ, max deviation on the lit side "
                  << front_dev << "\n";
        CHECK(front_dev == 0.0);   // identical arithmetic once NoL > 0
        CHECK(max_dev <= expect + 1e-6);
        CHECK(max_dev >= expect * 0.999 - 1e-9);   // the sweep reaches NoL close to -1 (and beyond the terminator)
    }
}

TEST_CASE("wrap directional albedo matches the closed forms - only wrap_energy conserves energy",
          "[wrap][physics]") {
    // value depends on NoL only, so (1/pi) * integral over directions = 2 * integral of value dNoL.
    auto albedo = [](const Material& m, double lo) {
        const int cells = 200000;
        double sum = 0.0;
        const glm::dvec3 Nz{0, 0, 1};
        for (int i = 0; i < cells; ++i) {
            const double x = lo + (1.0 - lo) * (i + 0.5) / cells;
            sum += ref::eval_material(Nz, light_at(x), Nz, {}, m).x;
        }
        return 2.0 * sum * (1.0 - lo) / cells;
    };
    const glm::dvec3 white{1, 1, 1};
    struct Row { Material m; double hemi, sphere; };
    std::vector<Row> rows = {{test::material("half_lambert", {}, white), 7.0 / 6.0, 4.0 / 3.0},
                             {test::material("half_lambert_seed001", {}, white), 7.0 / 6.0, 7.0 / 6.0 + 0.5}};
    for (double a : {0.5, 0.75, 1.0}) {
        const double hemi = 2.0 * (1.0 - std::pow(1.0 - a, 3.0)) / (3.0 * a);
        rows.push_back({test::material("wrap", {{"wrap_value", a}}, white), hemi, 2.0 / (3.0 * a)});
        rows.push_back({test::material("wrap_seed001", {{"wrap_value", a}}, white), hemi, hemi + 2.0 * (1.0 - a) * (1.0 - a)});
    }
    for (double w : {0.0, 0.25, 0.5, 1.0})
        rows.push_back({test::material("wrap_energy", {{"w", w}}, white), (1.0 + 2.0 * w) / ((1.0 + w) * (1.0 + w)), 1.0});
    std::map<std::string, double> worst_hemi;
    std::cout << "wrap directional albedo (albedo 1), numerical vs closed form:\n";
    for (const Row& r : rows) {
        const double h = albedo(r.m, 0.0), sp = albedo(r.m, -1.0);
        std::cout << "  " << std::left << std::setw(36) << test::describe(r.m, true) << std::right << " hemisphere " << h << " ("
                  << r.hemi << ")  sphere " << sp << " (" << r.sphere << ")\n";
        INFO(test::describe(r.m, true));
        CHECK(h == Approx(r.hemi).epsilon(1e-6));
        CHECK(sp == Approx(r.sphere).epsilon(1e-6));
        worst_hemi[r.m.model] = std::max(worst_hemi[r.m.model], std::max(h, sp));
    }
    for (const auto& [name, worst] : worst_hemi) {
        INFO(name << ": largest directional albedo over the grid " << worst);
        CHECK(find_model(name).energy_conserving == (worst <= 1.0 + 1e-9));
    }
}

TEST_CASE("wrap models are not reciprocal (flags say so) - wrap_energy at w = 0 is Lambert and is", "[wrap][physics]") {
    const glm::dvec3 Nz{0, 0, 1};
    const glm::dvec3 L = light_at(0.2), V = glm::dvec3(-std::sqrt(1 - 0.81), 0.0, 0.9);
    const glm::dvec3 white{1, 1, 1};
    auto asym = [&](const Material& m) {
        const double a = ref::eval_material(Nz, L, V, {}, m).x / L.z, b = ref::eval_material(Nz, V, L, {}, m).x / V.z;
        return std::abs(a - b) / std::max(a, b);
    };
    for (const char* name : {"half_lambert", "half_lambert_seed001", "wrap", "wrap_seed001", "wrap_energy"}) {
        INFO(name);
        CHECK_FALSE(find_model(name).reciprocal);
        CHECK(asym(test::material(name, {}, white)) > 0.1);
    }
    CHECK(asym(test::material("wrap_energy", {{"w", 0.0}}, white)) < 1e-15);
}

TEST_CASE("wrap kernels at the edge points: NoL = -1, NoL just beyond +-1 (float unit vectors), invalid input",
          "[wrap][stability]") {
    Shader shader(test::runtime());
    const float below = -1.0000001f, above = 1.0000001f;
    // N = +z; L = -z (exactly behind), L = (0, 0, -1 - 1ulp), (0, 0, 1 + 1ulp), grazing, zero vector.
    const std::vector<float> N = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const std::vector<float> L = {0, 0, -1, 0, 0, below, 0, 0, above, 1, 0, 0, 0, 0, 0};
    const std::vector<float> V = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const std::vector<float> P(N.size(), 0.0f);
    const char* what[] = {"NoL = -1", "NoL = -1 - 1ulp", "NoL = 1 + 1ulp", "NoL = 0", "L = 0"};
    for (const Material& m : {test::material("half_lambert"), test::material("half_lambert_seed001"), test::material("wrap", {{"wrap_value", 0.75}}),
                              test::material("wrap_seed001", {{"wrap_value", 1.0}}), test::material("wrap_energy", {{"w", 1.0}})}) {
        const auto out = shader.eval_directions(m, N, L, V, P);
        std::cout << "  " << std::left << std::setw(32) << test::describe(m, true) << std::right;
        for (std::size_t i = 0; i < 5; ++i) {
            std::cout << "  " << what[i] << ": " << out[3 * i];
            INFO(test::describe(m, true) << " " << what[i] << " -> " << out[3 * i]);
            CHECK(std::isfinite(out[3 * i]));
            CHECK(out[3 * i] >= 0.0f);
            CHECK(out[3 * i] <= 0.9f * 1.000001f);
        }
        std::cout << "\n";
    }
    const auto hl = shader.eval_directions(test::material("half_lambert"), N, L, V, P);
    CHECK(hl[0] == 0.0f);                // exactly 0 with the light exactly behind
    CHECK(hl[3] < 1e-13f);               // (0.5 (-1 - 1ulp) + 0.5)^2 ~ 4e-15: not clamped, not visible
    CHECK(hl[12] == Approx(0.9 * 0.25).epsilon(1e-7));   // L = 0: NoL = 0, finite
}
