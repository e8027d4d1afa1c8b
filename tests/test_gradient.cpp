// The gradient blend (kernels/models/gradient.cl): closed-form values with two Lambert children, the blend
// against its children for every model the catalogue has when the test runs (names found at run time, so a
// family that is not there yet is simply not paired), the whole blend against the double reference, and the
// inputs it must reject.
#include <catch2/catch.hpp>

#include <cmath>
#include <iomanip>
#include <iostream>

#include "cl/runtime.hpp"
#include "core/error.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"
#include "support.hpp"

using namespace shadelab;
using glm::dvec3;

namespace {
Material child(const std::string& model, dvec3 albedo) {
    Material m;
    m.model = model;
    m.albedo = albedo;
    m.specular = {0.9, 0.8, 0.7};
    return m;
}

Material gradient(const Material& a, const Material& b, dvec3 g, double period, double phase) {
    Material m;
    m.model = "gradient";
    m.params = {{"gx", g.x}, {"gy", g.y}, {"gz", g.z}, {"period", period}, {"phase", phase}};
    m.children = {a, b};
    return resolve_material(m);
}

// The blend weight in double, from the user's parameters (normalised here, independently of the host pack).
double weight(const dvec3& P, dvec3 g, double period, double phase) {
    g /= glm::length(g);
    return 0.5 + 0.5 * std::cos(2.0 * M_PI * glm::dot(P, g) / period + phase);
}

// N = L = V = +z at the given points, so a Lambert child's value is its albedo.
struct HeadOn {
    std::vector<float> N, L, V, P;
    explicit HeadOn(const std::vector<dvec3>& points) {
        for (const dvec3& p : points) {
            N.insert(N.end(), {0, 0, 1});
            L.insert(L.end(), {0, 0, 1});
            V.insert(V.end(), {0, 0, 1});
            P.insert(P.end(), {float(p.x), float(p.y), float(p.z)});
        }
    }
};
}  // namespace

TEST_CASE("gradient closed form: B on the crest, A in the trough, halfway between, with period and phase",
          "[gradient][kernel]") {
    const Material red = child("lambert", {1, 0, 0}), blue = child("lambert", {0, 0, 1});
    Shader shader(test::runtime());
    // Along y, period 4, phase 0: t = 1 at y = 0 and 8 (B), 0 at y = 2 (A), 1/2 at y = 1 and 3. x and z are
    // across the wave and change nothing.
    const HeadOn h({{3, 0, -1}, {3, 2, -1}, {3, 1, -1}, {-7, 8, 5}, {0, 3, 0}});
    const auto out = shader.eval_directions(gradient(red, blue, {0, 1, 0}, 4.0, 0.0), h.N, h.L, h.V, h.P);
    const double expect_t[] = {1.0, 0.0, 0.5, 1.0, 0.5};
    for (std::size_t i = 0; i < 5; ++i) {
        INFO("point " << i << ": t = " << expect_t[i]);
        CHECK(out[3 * i] == Approx(1.0 - expect_t[i]).margin(2e-6));   // red = (1 - t) * 1
        CHECK(out[3 * i + 1] == 0.0f);
        CHECK(out[3 * i + 2] == Approx(expect_t[i]).margin(2e-6));   // blue = t * 1
    }
    // Phase pi/2 shifts the wave a quarter period back: t = 1/2 - 1/2 sin(2 pi y / T); at y = 1 (T = 4): t = 0.
    // A direction is normalised, so (0, 0.5, 0) is the same wave as (0, 1, 0); (0, -1, 0) mirrors it.
    const HeadOn q({{0, 1, 0}, {0, -1, 0}, {0, 0.5, 0}});
    const auto ph = shader.eval_directions(gradient(red, blue, {0, 0.5, 0}, 4.0, M_PI / 2), q.N, q.L, q.V, q.P);
    CHECK(ph[2] == Approx(0.0).margin(2e-6));
    CHECK(ph[5] == Approx(1.0).epsilon(2e-6));
    CHECK(ph[8] == Approx(0.5 - 0.5 * std::sin(M_PI / 4)).epsilon(2e-6));
    const auto unit = shader.eval_directions(gradient(red, blue, {0, 1, 0}, 4.0, M_PI / 2), q.N, q.L, q.V, q.P);
    const auto flip = shader.eval_directions(gradient(red, blue, {0, -1, 0}, 4.0, M_PI / 2), q.N, q.L, q.V, q.P);
    CHECK(unit == ph);
    CHECK(flip[2] == Approx(1.0).epsilon(2e-6));
    // A tiny direction normalises like any other (the host scales before squaring).
    const auto tiny = shader.eval_directions(gradient(red, blue, {0, 1e-200, 0}, 4.0, M_PI / 2), q.N, q.L, q.V, q.P);
    CHECK(tiny == ph);
}

// Every model of the catalogue that blends nothing, found at run time, paired with its neighbour in the list
// (so each is a child at least once). Two layers:
//  (a) the blend itself: the gradient kernel against (1 - t) kA + t kB, with kA and kB the children's own kernels
//      run alone on the same triples and t in double. The children's values are then the same float numbers, so
//      only the weight and the mix can differ: |t_float - t| <= 0.5 * 3 * 6e-8 * (2 pi sum_i |P_i g_i| / T +
//      |phase| + 1) (the argument's roundings, at the size of its terms, and cos's), and the mix rounds at 6e-8 of
//      |kA| + |kB|. Asserted with a factor 2 of headroom on every triple, grazing ones included.
//  (b) the whole blend against the double reference on plainly conditioned triples (NoL, NoV >= 0.05,
//      LoV > -0.95, value >= 1e-3 of the peak): a check that the right children are blended in the right order;
//      the children's accuracy is their own families' tests' business, so only 1e-3 is asserted here (toon's
//      steep smoothed band edges measured 2.2e-4), the numbers are printed.
TEST_CASE("gradient blends every catalogue model pair: against its children's kernels and the reference",
          "[gradient][kernel]") {
    std::vector<std::string> names;
    for (const auto& info : model_catalogue())
        if (info.children == 0 && !has_tables(info)) names.push_back(info.name);   // a blend's children read no table
    REQUIRE(names.size() >= 1);
    const auto sweep = test::make_sweep(20000, 5);
    const dvec3 g{0.3, -0.5, 0.8};
    const double period = 2.5, phase = 0.7;
    Shader shader(test::runtime());
    std::cout << "gradient over " << names.size() << " catalogue models, " << sweep.size()
              << " triples per pair: blend error in units of its bound / max rel vs reference (conditioned)\n";
    for (std::size_t pi = 0; pi < names.size(); pi += 2) {
        const std::string a = names[pi], b = names[(pi + 1) % names.size()];
        const Material ma = resolve_material(child(a, {0.8, 0.3, 0.2})), mb = resolve_material(child(b, {0.2, 0.5, 0.9}));
        const Material m = gradient(ma, mb, g, period, phase);
        const auto ka = shader.eval_directions(ma, sweep.N, sweep.L, sweep.V, sweep.P);
        const auto kb = shader.eval_directions(mb, sweep.N, sweep.L, sweep.V, sweep.P);
        double peak = -1.0, blend_units = 0.0;
        std::size_t worst = 0;
        // (b) against the reference: 1e-3 relative where plainly conditioned, value >= 1e-3 of the peak. (a) rides
        // on the same kernel values: the blend against its children's kernels, within its bound everywhere.
        const auto e = test::check_kernel_against_reference(m, [&](const test::Compared& v) {
            if (peak < 0.0) {
                peak = 0.0;
                for (const dvec3& r : v.reference) peak = std::max({peak, std::abs(r.x), std::abs(r.y), std::abs(r.z)});
            }
            const double t = weight(v.P(), g, period, phase);
            // The float dot product P.g rounds at the size of its terms, not of its (possibly cancelled) sum.
            const dvec3 gn = glm::normalize(g);
            const double arg = 2.0 * M_PI * glm::dot(glm::abs(v.P()), glm::abs(gn)) / period + std::abs(phase);
            const double dt = 0.5 * 3.0 * 6e-8 * (arg + 1.0);
            const std::size_t j = 3 * v.i + std::size_t(v.c);
            const double A = ka[j], B = kb[j], expect = (1.0 - t) * A + t * B;
            const double bound = 2.0 * (dt * std::abs(B - A) + 6e-8 * (std::abs(A) + std::abs(B))) + 1e-30;
            if (std::abs(v.k - expect) / bound > blend_units) { blend_units = std::abs(v.k - expect) / bound; worst = v.i; }
            const bool plain = v.NoL() >= 0.05 && v.NoV() >= 0.05 && v.LoV() > -0.95;
            return plain && std::abs(v.r) >= 1e-3 * peak ? 1e-3 * std::abs(v.r) : test::kExempt;
        }, {&sweep});
        std::cout << "  " << std::left << std::setw(50) << (a + " + " + b) << std::right << " blend " << std::setw(10)
                  << blend_units << "  vs reference " << e.max_rel << " (" << e.compared << " values)\n";
        test::expect_within(e, 1001);   // more than 1000 values compared
        INFO(a << " + " << b << ": worst blend triple " << worst << " (" << sweep.kind[worst] << ")");
        CHECK(blend_units <= 1.0);
    }
}

TEST_CASE("gradient rejects a zero direction, blends of blends and a wrong child count, with clear messages",
          "[gradient]") {
    Material m;
    m.model = "gradient";
    m.params = {{"gx", 0.0}, {"gy", 0.0}, {"gz", 0.0}};
    m.children = {child("lambert", {1, 1, 1}), child("lambert", {0, 0, 0})};
    // Each component is in range, so resolving succeeds; the direction as a whole is rejected where it is
    // normalised, before any launch - also through the shader, which is what a scene or the CLI reaches.
    const Material resolved = resolve_material(m);
    REQUIRE_THROWS_WITH(pack_material(resolved), Catch::Contains("gradient direction") && Catch::Contains("(0, 0, 0)"));
    Shader shader(test::runtime());
    const std::vector<float> one = {0, 0, 1};
    REQUIRE_THROWS_AS(shader.eval_directions(resolved, one, one, one, one), Error);
    REQUIRE_THROWS_WITH(ref::eval_material({0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 0}, resolved),
                        Catch::Contains("gradient direction"));
    Material out_of_range = m;
    out_of_range.params["gx"] = 2.0;
    REQUIRE_THROWS_WITH(resolve_material(out_of_range), Catch::Contains("gx") && Catch::Contains("[-1, 1]"));
    Material zero_period = m;
    zero_period.params = {{"period", 0.0}};
    REQUIRE_THROWS_WITH(resolve_material(zero_period), Catch::Contains("period"));
    Material nested;
    nested.model = "gradient";
    nested.children = {m, child("lambert", {1, 1, 1})};
    REQUIRE_THROWS_WITH(resolve_material(nested), Catch::Contains("cannot blend"));
    Material single;
    single.model = "gradient";
    single.children = {child("lambert", {1, 1, 1})};
    REQUIRE_THROWS_WITH(resolve_material(single), Catch::Contains("blends 2 other models but 1 were given"));
}
