// Banded / toon references in double, written from the rules in docs/models/banded_toon.md, sharing no
// code with kernels/models/banded_toon.cl or host/models/banded_toon.cpp. Term functions carry the kernel's
// names. The toon's hard bands are written as a level lookup (count the thresholds passed), the kernel
// as a sum of steps; the smoothed bands are the sum of smoothsteps that defines them.
#include <algorithm>
#include <cmath>

#include "reference/reference.hpp"

namespace shadelab::ref {

namespace {

// NoL+ rounded to the nearest multiple of 1/steps; a value exactly half-way rounds up.
double Band_Round(double NoL, double steps) { return std::floor(std::max(NoL, 0.0) * steps + 0.5) / steps; }

// Seed 001: floor((NdotL * 256 + _LightSteps / 2) / _LightSteps) * (_LightSteps / 256).
double Band_Seed001(double NoL, double t) {
    const double lightBandsMultiplier = t / 256.0;
    const double lightBandsAdditive = t / 2.0;
    return std::floor((std::max(NoL, 0.0) * 256.0 + lightBandsAdditive) / t) * lightBandsMultiplier;
}

// Hermite smoothstep over [e0, e1] (as GLSL / OpenCL define it).
double smoothstep(double e0, double e1, double x) {
    const double s = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return s * s * (3.0 - 2.0 * s);
}

// A band ladder: levels[0] below thresholds[0], levels[k] once x >= thresholds[k-1] (ascending thresholds).
// width 0: the level of the last threshold passed; width > 0: levels[0] + sum of (level jump) *
// smoothstep(t - width/2, t + width/2, x).
template <int K>
double Toon_Ladder(double x, const double (&thresholds)[K], const double (&levels)[K + 1], double width) {
    if (width == 0.0) {
        int passed = 0;
        for (int k = 0; k < K; ++k) passed += x >= thresholds[k] ? 1 : 0;
        return levels[passed];
    }
    double v = levels[0];
    for (int k = 0; k < K; ++k)
        v += (levels[k + 1] - levels[k]) * smoothstep(thresholds[k] - 0.5 * width, thresholds[k] + 0.5 * width, x);
    return v;
}

double Toon_Diffuse(double NoL, const Material& m) {
    const auto& p = m.params;
    const double t[3] = {p.at("diffuse_t1"), p.at("diffuse_t2"), p.at("diffuse_t3")};
    const double l[4] = {p.at("diffuse_l0"), p.at("diffuse_l1"), p.at("diffuse_l2"), p.at("diffuse_l3")};
    return Toon_Ladder<3>(NoL, t, l, p.at("width"));
}

double Toon_Specular(double x, const Material& m) {
    const auto& p = m.params;
    const double t[2] = {p.at("spec_t1"), p.at("spec_t2")};
    const double l[3] = {p.at("spec_l0"), p.at("spec_l1"), p.at("spec_l2")};
    return Toon_Ladder<2>(x, t, l, p.at("width"));
}

// The highlight's side-of-light gate, a band edge at NoL = 0: hard (NoL >= 0) or smoothed like the others.
double Toon_Gate(double NoL, double width) {
    return width == 0.0 ? (NoL >= 0.0 ? 1.0 : 0.0) : smoothstep(-0.5 * width, 0.5 * width, NoL);
}

// Blinn (1977) N.H with H = (L + V) / |L + V|; 0 where H is undefined (L = -V, |L + V| < 1e-10).
double BlinnPhong_NoH(const dvec3& N, const dvec3& L, const dvec3& V) {
    const dvec3 h = L + V;
    const double len = glm::length(h);
    return len > 1e-10 ? glm::dot(N, h) / len : 0.0;
}

// Highlight intensity max(0, NoH)^n, 0 for NoH <= 0 at every n (no pow(0, 0) = 1).
double Spec_Power(double x, double n) { return x > 0.0 ? std::pow(x, n) : 0.0; }

}  // namespace

void add_banded_toon_references(Table& t) {
    t["banded"] = [](const dvec3& N, const dvec3& L, const dvec3&, const dvec3&, const Material& m) {
        return m.albedo * Band_Round(glm::dot(N, L), m.params.at("steps"));
    };
    t["banded_seed001"] = [](const dvec3& N, const dvec3& L, const dvec3&, const dvec3&, const Material& m) {
        return m.albedo * Band_Seed001(glm::dot(N, L), m.params.at("light_steps"));
    };
    t["toon"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const double NoL = glm::dot(N, L);
        const double spec = Toon_Gate(NoL, m.params.at("width")) *
                            Toon_Specular(Spec_Power(BlinnPhong_NoH(N, L, V), m.params.at("n")), m);
        return m.albedo * Toon_Diffuse(NoL, m) + spec * m.specular;
    };
}

}  // namespace shadelab::ref
