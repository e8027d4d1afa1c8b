// The multi-light sum of seed 000 through the real shade_fragments kernel (Shader::shade) against
// ref::shade_point:
//   value(P) = sum_i colour_i * intensity_i * atten_i(P) * model(N, L_i, V) + ambient * albedo
// Layers: closed-form spot values (one light of each kind, colours per channel, ambient alone, inverse square,
// the range window); random fragments and lights for 0, 1, 2 and 5 lights with a perspective camera and an
// orthographic view direction, against the reference with a stated bound; the failure points (a point light on
// the surface point, beyond its range).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <random>

#include "cl/runtime.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"
#include "support.hpp"

using namespace shadelab;
using glm::dvec3;

namespace {
// Models the sum is checked with: Lambert, and those of the other families that the catalogue has when the
// test runs (looked up by name, so a family that is not there is skipped, not failed).
std::vector<std::string> sum_models() {
    std::vector<std::string> out;
    for (const char* name : {"lambert", "oren_nayar", "blinn_phong", "cook_torrance"})
        for (const auto& info : model_catalogue())
            if (info.name == name) out.push_back(name);
    return out;
}

dvec3 to_float(const dvec3& v) { return {double(float(v.x)), double(float(v.y)), double(float(v.z))}; }

FragmentBuffer random_fragments(std::size_t n, std::uint64_t seed) {
    std::mt19937_64 g(seed);
    FragmentBuffer fb;
    for (std::size_t i = 0; i < n; ++i) {
        const dvec3 p = 4.0 * test::random_unit(g) * test::unit_double(g);
        const dvec3 nn = test::random_unit(g);
        fb.push_back(float(p.x), float(p.y), float(p.z), float(nn.x), float(nn.y), float(nn.z), int(i), 1.0f);
    }
    return fb;
}

// Alternately directional (given as a non-unit vector: the host normalises it) and point lights, some at
// distance 4.5 from the centre of the fragments' ball of radius 4 (so up to 1/0.25 = 16 times brighter close
// in), every other point light with a range of 5 (the window cuts the far side of the ball). Positions and
// directions are rounded to float, as the kernel receives them, so the reference sees the same lights.
std::vector<Light> make_lights(int count, std::mt19937_64& g) {
    std::vector<Light> ls;
    for (int i = 0; i < count; ++i) {
        Light l;
        l.type = i % 2 ? Light::Type::Point : Light::Type::Directional;
        const double radius = i % 4 == 1 ? 4.5 : 6.0;
        l.vec = to_float(l.type == Light::Type::Point ? radius * test::random_unit(g) : 3.0 * test::random_unit(g));
        if (l.type == Light::Type::Directional) l.vec = 3.0 * to_float(glm::normalize(l.vec));
        l.colour = {0.2 + 0.8 * test::unit_double(g), 0.2 + 0.8 * test::unit_double(g), 0.2 + 0.8 * test::unit_double(g)};
        l.intensity = 0.5 + 10.0 * test::unit_double(g);
        l.range = (l.type == Light::Type::Point && i % 4 == 3) ? 5.0 : 0.0;
        ls.push_back(l);
    }
    return ls;
}

// What light i delivers at P (colour * intensity * atten) and its direction, in double (the reference's own
// formulas are in host/reference/reference.cpp; this only sizes the bound).
dvec3 incident(const Light& l, const dvec3& P, dvec3* L) {
    if (l.type == Light::Type::Directional) {
        *L = glm::normalize(l.vec);
        return l.colour * l.intensity;
    }
    const dvec3 d = l.vec - P;
    const double d2 = std::max(glm::dot(d, d), 1e-12);
    *L = d / std::sqrt(d2);
    double w = 1.0;
    if (l.range > 0.0) {
        const double q = d2 / (l.range * l.range);
        w = std::clamp(1.0 - q * q, 0.0, 1.0);
        w *= w;
    }
    return l.colour * l.intensity * (w / d2);
}

}  // namespace

// ---- closed-form spot values -------------------------------------------------------------------------------

TEST_CASE("lights: colours per channel, ambient, inverse square and the range window in closed form",
          "[lights][kernel]") {
    Shader shader(test::runtime());
    FragmentBuffer fb;
    fb.push_back(0, 0, 0, 0, 0, 1, 0, 1.0f);   // the origin, normal +z
    ShadeSetup s;
    s.material = resolve_material(Material{});   // Lambert, albedo 0.8
    s.view = {0, 0, 5, 1};
    auto shade = [&](std::vector<Light> lights, dvec3 ambient = dvec3(0.0)) {
        s.lights = std::move(lights);
        s.ambient = ambient;
        return shader.shade(fb, s);   // planes: r, g, b
    };
    // Ambient alone: ambient * albedo, no light needed.
    const auto amb = shade({}, {0.1, 0.2, 0.3});
    CHECK(amb[0] == Approx(0.08).epsilon(1e-6));
    CHECK(amb[1] == Approx(0.16).epsilon(1e-6));
    CHECK(amb[2] == Approx(0.24).epsilon(1e-6));
    // A red directional light head-on (intensity 2, given as a non-unit vector), a blue point light at distance 2
    // (intensity 4, so 4 / 2^2 = 1), a green point light at 60 deg off the normal, distance 1 (NoL = 1/2), plus
    // ambient: r = 0.8 * 2, g = 0.8 * 3 * 0.5 + 0.8 * 0.05, b = 0.8 * 1.
    const auto three = shade({Light{Light::Type::Directional, {0, 0, 7}, {1, 0, 0}, 2.0, 0.0},
                              Light{Light::Type::Point, {0, 0, 2}, {0, 0, 1}, 4.0, 0.0},
                              Light{Light::Type::Point, {std::sqrt(0.75), 0, 0.5}, {0, 1, 0}, 3.0, 0.0}},
                             {0.0, 0.05, 0.0});
    CHECK(three[0] == Approx(1.6).epsilon(1e-6));
    CHECK(three[1] == Approx(0.8 * 1.5 + 0.04).epsilon(1e-6));
    CHECK(three[2] == Approx(0.8).epsilon(1e-6));
    // Inverse square: the same direction (60 deg off the normal) at distances 1.5 and 3.
    const dvec3 dir{std::sqrt(0.75), 0, 0.5};
    const double near = shade({Light{Light::Type::Point, 1.5 * dir, {1, 1, 1}, 1.0, 0.0}})[1];
    const double far = shade({Light{Light::Type::Point, 3.0 * dir, {1, 1, 1}, 1.0, 0.0}})[1];
    CHECK(near == Approx(0.8 * 0.5 / 2.25).epsilon(1e-6));
    CHECK(near / far == Approx(4.0).epsilon(1e-6));
    // The range window (1 - (d/range)^4)^2: at half the range (1 - 1/16)^2; exactly 0 at and beyond the range.
    CHECK(shade({Light{Light::Type::Point, {0, 0, 1}, {1, 1, 1}, 1.0, 2.0}})[1] ==
          Approx(0.8 * std::pow(1.0 - 1.0 / 16.0, 2.0)).epsilon(1e-6));
    CHECK(shade({Light{Light::Type::Point, {0, 0, 2}, {1, 1, 1}, 1.0, 2.0}})[1] == 0.0f);
    CHECK(shade({Light{Light::Type::Point, {0, 0, 2}, {1, 1, 1}, 1.0, 1.9}})[1] == 0.0f);
    // A light beyond its range adds exactly nothing to another light's contribution.
    const float alone = shade({Light{Light::Type::Directional, {0, 0, 1}, {1, 1, 1}, 1.0, 0.0}})[1];
    const float with_far = shade({Light{Light::Type::Directional, {0, 0, 1}, {1, 1, 1}, 1.0, 0.0},
                                  Light{Light::Type::Point, {0, 0, 3}, {1, 1, 1}, 100.0, 2.5}})[1];
    CHECK(with_far == alone);
}

// ---- random fragments against the reference ----------------------------------------------------------------

// Bound per fragment and channel, with E_i = colour * intensity * atten of light i, v_i the model's value and r
// the reference:
//   |k - r| <= 4e-6 (sum_i |E_i v_i| + ambient albedo) + 1e-7 sum_i E_i    the arithmetic (atten, the sum,
//                                                                           the model's own few roundings)
//            + sum_i E_i * 4 * 6e-8 * slope_i                              where that is not enough: four
//                                                                           roundings of L_i and V (test::slope
//                                                                           in support.hpp)
// The lights' positions and directions are float already (make_lights), as are the fragments.
TEST_CASE("multi-light sum: shade_fragments against ref::shade_point for 0, 1, 2 and 5 lights, both view modes",
          "[lights][kernel]") {
    Shader shader(test::runtime());
    std::mt19937_64 g(21);
    const FragmentBuffer fb = random_fragments(50000, 3);
    const std::size_t n = fb.size();
    std::cout << "multi-light sum, " << n << " random fragments: max abs error / incident light; worst error / "
                 "arithmetic part of the bound; values beyond it and the worst of those in units of the full bound\n";
    for (const std::string& model : sum_models())
        for (int count : {0, 1, 2, 5})
            for (double w : {1.0, 0.0}) {
                ShadeSetup s;
                s.material.model = model;
                s.material.albedo = {0.7, 0.5, 0.3};
                s.material.specular = {0.9, 0.9, 0.9};
                s.material = resolve_material(s.material);
                s.lights = make_lights(count, g);
                s.ambient = {0.05, 0.04, 0.03};
                s.view = w == 1.0 ? glm::dvec4(0.5, 7.0, 9.0, 1.0)
                                  : glm::dvec4(to_float(glm::normalize(dvec3(0.2, 0.3, 1.0))), 0.0);
                const auto out = shader.shade(fb, s);
                double units = 0.0, rel_to_light = 0.0, worst_min_cos = 0.0, over_base = 0.0;
                std::size_t nonfinite = 0, worst = 0, beyond = 0;
                for (std::size_t i = 0; i < n; ++i) {
                    const dvec3 P{fb.px[i], fb.py[i], fb.pz[i]}, N{fb.nx[i], fb.ny[i], fb.nz[i]};
                    const dvec3 V = w == 1.0 ? glm::normalize(dvec3(s.view) - P) : dvec3(s.view);
                    const dvec3 r = ref::shade_point(P, N, V, s.material, s.lights, s.ambient);
                    dvec3 scale = s.ambient * s.material.albedo, light(0.0);
                    std::vector<dvec3> Ls, Es;
                    for (const Light& l : s.lights) {
                        dvec3 L;
                        const dvec3 E = incident(l, P, &L);
                        scale += glm::abs(E * ref::eval_material(N, L, V, P, s.material));
                        light += E;
                        Ls.push_back(L);
                        Es.push_back(E);
                    }
                    for (int c = 0; c < 3; ++c) {
                        const double k = out[std::size_t(c) * n + i];
                        if (!std::isfinite(k)) { ++nonfinite; continue; }
                        const double e = std::abs(k - r[c]);
                        const double base = 4e-6 * scale[c] + 1e-7 * light[c] + 1e-30;
                        over_base = std::max(over_base, e / base);
                        rel_to_light = std::max(rel_to_light, e / (light[c] + s.ambient[c]));
                        if (e <= base) continue;
                        ++beyond;
                        double bound = base;
                        for (std::size_t li = 0; li < Ls.size(); ++li)
                            bound += Es[li][c] * 4.0 * 6e-8 * test::slope(N, Ls[li], V, s.material, c);
                        if (e / bound > units) {
                            units = e / bound;
                            worst = i;
                            worst_min_cos = std::abs(glm::dot(N, V));
                            for (const dvec3& L : Ls) worst_min_cos = std::min(worst_min_cos, std::abs(glm::dot(N, L)));
                        }
                    }
                }
                std::cout << "  " << std::left << std::setw(14) << model << std::right << count << " lights, "
                          << (w == 1.0 ? "perspective " : "orthographic") << "  abs / light " << std::setw(11)
                          << rel_to_light << "  arithmetic " << std::setw(9) << over_base << "  beyond it "
                          << std::setw(4) << beyond << ", worst " << units << "\n";
                INFO(model << ", " << count << " lights, view w " << w << ": worst fragment " << worst << " P ("
                           << fb.px[worst] << ", " << fb.py[worst] << ", " << fb.pz[worst] << ") N (" << fb.nx[worst]
                           << ", " << fb.ny[worst] << ", " << fb.nz[worst] << "), smallest |NoL_i|, |NoV| "
                           << worst_min_cos);
                CHECK(nonfinite == 0);
                CHECK(units <= 1.0);
            }
}

// ---- failure points ----------------------------------------------------------------------------------------

// A point light exactly on the surface point has no direction: light_incident floors d^2 at 1e-12, so L = 0
// and the light's factor is 1e12 times its radiance; the model sees NoL = 0. A directional light beside it must
// survive: for Lambert (0 at NoL = 0) the value is exactly the directional light's, so the light on the point
// adds nothing and did not turn the sum into Inf/NaN (which shade.cl would write as 0).
TEST_CASE("lights: a point light on the surface point gives a finite value for every model", "[lights][stability]") {
    Shader shader(test::runtime());
    FragmentBuffer fb;
    fb.push_back(1, 2, 3, 0, 0, 1, 0, 1.0f);
    fb.push_back(1, 2, 3, 0, 1, 0, 1, 1.0f);
    for (const std::string& model : sum_models()) {
        ShadeSetup s;
        s.material.model = model;
        s.material = resolve_material(s.material);
        s.view = {1, 2, 8, 1};
        s.lights = {Light{Light::Type::Point, {1, 2, 3}, {1, 1, 1}, 1.0, 0.0},
                    Light{Light::Type::Directional, {0, 0, 1}, {1, 1, 1}, 1.0, 0.0}};
        const auto out = shader.shade(fb, s);
        for (float v : out) CHECK(std::isfinite(v));
        if (model == "lambert") CHECK(out[2] == Approx(0.8).epsilon(1e-6));   // green plane, fragment 0
        std::cout << "point light on the surface point, " << model << ": " << out[0] << " " << out[1] << "\n";
    }
}
