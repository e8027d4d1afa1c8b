// The multi-light sum of seed 000 through the real shade_fragments kernel against ref::shade_point:
//   value = sum_i colour_i * intensity_i * atten_i(P) * model(N, L_i, V) + ambient * albedo
#include <catch2/catch.hpp>

#include <cmath>
#include <iostream>
#include <random>

#include "cl/runtime.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"
#include "sweep.hpp"

using namespace shadelab;

namespace {
Runtime& runtime() {
    static Runtime rt;
    return rt;
}

FragmentBuffer random_fragments(std::size_t n, std::uint64_t seed) {
    std::mt19937_64 g(seed);
    FragmentBuffer fb;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 p = 4.0 * test::random_unit(g) * test::unit_double(g);
        const glm::dvec3 nn = test::random_unit(g);
        fb.push_back(float(p.x), float(p.y), float(p.z), float(nn.x), float(nn.y), float(nn.z), int(i), 1.0f);
    }
    return fb;
}

std::vector<Light> make_lights(int count, std::mt19937_64& g) {
    std::vector<Light> ls;
    for (int i = 0; i < count; ++i) {
        Light l;
        l.type = i % 2 ? Light::Type::Point : Light::Type::Directional;
        l.vec = l.type == Light::Type::Point ? 6.0 * test::random_unit(g) : test::random_unit(g) * 3.0;
        l.colour = {0.2 + 0.8 * test::unit_double(g), 0.2 + 0.8 * test::unit_double(g), 0.2 + 0.8 * test::unit_double(g)};
        l.intensity = 0.5 + 10.0 * test::unit_double(g);
        l.range = (l.type == Light::Type::Point && i % 4 == 3) ? 5.0 : 0.0;
        ls.push_back(l);
    }
    return ls;
}
}  // namespace

TEST_CASE("multi-light sum: kernel against reference for 0, 1, 2 and 5 lights, both view modes", "[lights][kernel]") {
    Shader shader(runtime());
    std::mt19937_64 g(21);
    const FragmentBuffer fb = random_fragments(50000, 3);
    for (const char* model : {"lambert", "oren_nayar", "blinn_phong"})
        for (int count : {0, 1, 2, 5})
            for (double w : {1.0, 0.0}) {
                ShadeSetup s;
                s.material.model = model;
                s.material.albedo = {0.7, 0.5, 0.3};
                s.material = resolve_material(s.material);
                s.lights = make_lights(count, g);
                s.ambient = {0.05, 0.04, 0.03};
                s.view = w == 1.0 ? glm::dvec4(0.5, 7.0, 9.0, 1.0) : glm::dvec4(glm::normalize(glm::dvec3(0.2, 0.3, 1.0)), 0.0);
                const auto out = shader.shade(fb, s);
                const std::size_t n = fb.size();
                double rel = 0.0;
                std::size_t nonfinite = 0;
                for (std::size_t i = 0; i < n; ++i) {
                    const glm::dvec3 P{fb.px[i], fb.py[i], fb.pz[i]}, N{fb.nx[i], fb.ny[i], fb.nz[i]};
                    const glm::dvec3 V = w == 1.0 ? glm::normalize(glm::dvec3(s.view) - P) : glm::dvec3(s.view);
                    const glm::dvec3 r = ref::shade_point(P, N, V, s.material, s.lights, s.ambient);
                    for (int c = 0; c < 3; ++c) {
                        const double k = out[std::size_t(c) * n + i];
                        if (!std::isfinite(k)) { ++nonfinite; continue; }
                        // Relative to the value plus the ambient floor: grazing inputs are the models' own tests.
                        rel = std::max(rel, std::abs(k - r[c]) / (std::abs(r[c]) + 0.05));
                    }
                }
                INFO(model << ", " << count << " lights, view w " << w);
                CHECK(nonfinite == 0);
                CHECK(rel < 1e-3);
                if (count == 5 && w == 1.0) std::cout << "lights: " << model << " with 5 lights, max error / (|value| + 0.05) " << rel << "\n";
            }
}

TEST_CASE("point lights: inverse square, exact zero beyond range, finite at the surface point", "[lights]") {
    Shader shader(runtime());
    FragmentBuffer fb;
    // Normal +z at the origin; points at distance 1 and 2 straight above, then the light on the point itself.
    fb.push_back(0, 0, 0, 0, 0, 1, 0, 1.0f);
    ShadeSetup s;
    s.material = resolve_material(Material{});
    s.view = {0, 0, 5, 1};
    auto value_at = [&](glm::dvec3 pos, double range) {
        s.lights = {Light{Light::Type::Point, pos, {1, 1, 1}, 1.0, range}};
        return shader.shade(fb, s)[0];
    };
    const double v1 = value_at({0, 0, 1}, 0.0), v2 = value_at({0, 0, 2}, 0.0);
    CHECK(v1 == Approx(0.8).epsilon(1e-6));       // albedo 0.8, distance 1
    CHECK(v1 / v2 == Approx(4.0).epsilon(1e-6));  // inverse square
    CHECK(value_at({0, 0, 2}, 1.9) == 0.0f);      // beyond range: exactly 0
    CHECK(value_at({0, 0, 2}, 2.0) == 0.0f);      // at range: the window reaches 0 exactly
    const float windowed = value_at({0, 0, 1}, 2.0);
    CHECK(windowed == Approx(0.8 * std::pow(1.0 - 1.0 / 16.0, 2.0)).epsilon(1e-5));   // (1 - (d/r)^4)^2
    const float at_point = value_at({0, 0, 0}, 0.0);
    CHECK(std::isfinite(at_point));
}
