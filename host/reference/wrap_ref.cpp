// Wrap-lighting references in double, written from the formulas (docs/models/wrap.md), sharing no code
// with kernels/models/wrap.cl or host/models/wrap.cpp. Term functions carry the kernel's names so the two
// read side by side; each model computes its own constants from the material's parameters.
#include <algorithm>
#include <cmath>

#include "reference/reference.hpp"

namespace shadelab::ref {

namespace {

// Valve's half-Lambert, Mitchell, McTaggart, Green (2006): (0.5 NoL + 0.5)^2, NoL unclamped.
double Fd_HalfLambert(double NoL) { return std::pow(0.5 * NoL + 0.5, 2.0); }

// Seed 001's diffuse wrap (NoL a + (1 - a))^2, taken as 0 beyond its terminator NoL = -(1 - a) / a where
// the base turns negative (the square would otherwise rise again behind the surface).
double Fd_WrapSquared(double NoL, double a) {
    const double base = NoL * a + (1.0 - a);
    return base > 0.0 ? base * base : 0.0;
}

// Filament's Fd_Wrap: saturate((NoL + w) / (1 + w)^2).
double Fd_Wrap(double NoL, double w) { return std::clamp((NoL + w) / ((1.0 + w) * (1.0 + w)), 0.0, 1.0); }

}  // namespace

void add_wrap_references(Table& t) {
    t["half_lambert"] = [](const dvec3& N, const dvec3& L, const dvec3&, const dvec3&, const Material& m) {
        return m.albedo * Fd_HalfLambert(glm::dot(N, L));
    };
    t["half_lambert_seed001"] = [](const dvec3& N, const dvec3& L, const dvec3&, const dvec3&, const Material& m) {
        const double NoL = glm::dot(N, L);
        return m.albedo * Fd_HalfLambert(NoL > 0.0 ? NoL : 0.0);   // the seed's max(0, NdotL) first
    };
    t["wrap"] = [](const dvec3& N, const dvec3& L, const dvec3&, const dvec3&, const Material& m) {
        return m.albedo * Fd_WrapSquared(glm::dot(N, L), m.params.at("wrap_value"));
    };
    t["wrap_seed001"] = [](const dvec3& N, const dvec3& L, const dvec3&, const dvec3&, const Material& m) {
        const double NoL = glm::dot(N, L);
        return m.albedo * Fd_WrapSquared(NoL > 0.0 ? NoL : 0.0, m.params.at("wrap_value"));
    };
    t["wrap_energy"] = [](const dvec3& N, const dvec3& L, const dvec3&, const dvec3&, const Material& m) {
        return m.albedo * Fd_Wrap(glm::dot(N, L), m.params.at("w"));
    };
}

}  // namespace shadelab::ref
