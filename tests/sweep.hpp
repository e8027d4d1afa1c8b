// Direction sweeps shared by the kernel-vs-reference tests: (N, L, V) triples over the whole sphere,
// with the places models break made explicit (grazing, L = V, L = -V, back-facing light and view).
#pragma once
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace shadelab::test {

struct DirectionSweep {
    std::vector<float> N, L, V, P;   // xyz-interleaved, what the kernel reads
    std::vector<glm::dvec3> dN, dL, dV, dP;   // the same float values in double, what the reference reads
    std::vector<std::string> kind;   // which family of case each triple belongs to
    std::size_t size() const { return dN.size(); }
};

// A uniform double in [0, 1) from the generator's bits (std::uniform_real_distribution is not portable).
inline double unit_double(std::mt19937_64& g) { return double(g() >> 11) * (1.0 / 9007199254740992.0); }

inline glm::dvec3 random_unit(std::mt19937_64& g) {
    const double z = 2.0 * unit_double(g) - 1.0;
    const double phi = 2.0 * M_PI * unit_double(g);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// A random unit vector well above the plane z = 0: a uniform one with |z| raised by 0.05, renormalised.
inline glm::dvec3 random_above(std::mt19937_64& g) {
    glm::dvec3 v = random_unit(g);
    v.z = std::abs(v.z) + 0.05;
    return glm::normalize(v);
}

// A unit vector perpendicular to unit v.
inline glm::dvec3 any_perpendicular(const glm::dvec3& v) {
    return glm::normalize(glm::cross(v, std::abs(v.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
}

// A unit vector at polar angle theta from n, random azimuth.
inline glm::dvec3 at_angle(const glm::dvec3& n, double theta, std::mt19937_64& g) {
    glm::dvec3 t = any_perpendicular(n);
    glm::dvec3 b = glm::cross(n, t);
    const double phi = 2.0 * M_PI * unit_double(g);
    return glm::normalize(std::cos(theta) * n + std::sin(theta) * (std::cos(phi) * t + std::sin(phi) * b));
}

// Appends one triple and its point to a sweep: rounded to float as the kernel reads them, and the same
// float values in double for the reference.
inline void add_triple(DirectionSweep& s, const glm::dvec3& n, const glm::dvec3& l, const glm::dvec3& v,
                       const glm::dvec3& p, const char* kind) {
    const glm::dvec3 vs[4] = {n, l, v, p};
    std::vector<float>* fs[4] = {&s.N, &s.L, &s.V, &s.P};
    std::vector<glm::dvec3>* ds[4] = {&s.dN, &s.dL, &s.dV, &s.dP};
    for (int k = 0; k < 4; ++k) {
        glm::dvec3 r;
        for (int c = 0; c < 3; ++c) {
            const float f = float(vs[k][c]);
            fs[k]->push_back(f);
            r[c] = double(f);
        }
        ds[k]->push_back(r);
    }
    s.kind.push_back(kind);
}

// About `count` triples: 60% uniform random over the sphere (so N.L < 0 and N.V < 0 occur), the rest
// special cases: grazing light and/or view at 90 deg +- {0, 1e-6, 1e-5, 1e-4} rad, L = V, L = -V, L = N,
// V = N, L = V = N, plus points P spread over [-10, 10]^3 for position-dependent models.
inline DirectionSweep make_sweep(std::size_t count = 120000, std::uint64_t seed = 12345) {
    std::mt19937_64 g(seed);
    DirectionSweep s;
    auto push = [&](glm::dvec3 n, glm::dvec3 l, glm::dvec3 v, const char* kind) {
        const glm::dvec3 p{20.0 * unit_double(g) - 10.0, 20.0 * unit_double(g) - 10.0, 20.0 * unit_double(g) - 10.0};
        add_triple(s, n, l, v, p, kind);
    };
    const double grazing[] = {0.0, 1e-6, -1e-6, 1e-5, -1e-5, 1e-4, -1e-4};
    const std::size_t random_count = count * 6 / 10;
    for (std::size_t i = 0; i < random_count; ++i) push(random_unit(g), random_unit(g), random_unit(g), "random");
    while (s.size() < count) {
        const glm::dvec3 n = random_unit(g);
        const double eps_l = grazing[g() % 7], eps_v = grazing[g() % 7];
        const glm::dvec3 lg = at_angle(n, M_PI / 2 - eps_l, g), vg = at_angle(n, M_PI / 2 - eps_v, g);
        const glm::dvec3 l = at_angle(n, std::acos(unit_double(g)), g);
        const glm::dvec3 v = at_angle(n, std::acos(unit_double(g)), g);
        push(n, lg, v, "grazing L");
        push(n, l, vg, "grazing V");
        push(n, lg, vg, "grazing L and V");
        push(n, l, l, "L = V");
        push(n, l, -l, "L = -V");
        push(n, n, v, "L = N");
        push(n, l, n, "V = N");
        push(n, n, n, "L = V = N");
    }
    return s;
}

}  // namespace shadelab::test
