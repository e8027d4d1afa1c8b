// Minnaert family references in double, written from the formulas (docs/models/minnaert.md), sharing no code
// with kernels/models/minnaert.cl or host/models/minnaert.cpp. The term functions carry the kernel's names so
// the two can be read side by side. Each computes its own constants from the material's parameters.
#include <algorithm>
#include <cmath>

#include "reference/reference.hpp"

namespace shadelab::ref {

namespace {

// Limb guard, part of the definition of the 1941-law models: for k < 1 each cosine's power c^(k-1) is held
// at eps^(k-1) below eps = 1e-3 and faded linearly to 0 at c = 0; for k >= 1 the law needs no guard.
constexpr double kLimbEps = 1e-3;

double limb_eps(double k) { return k < 1.0 ? kLimbEps : 0.0; }

// One cosine's power in Minnaert's law, c^(k-1), with the limb guard.
double Minnaert_cos_pow(double c, double k, double eps) {
    if (c >= eps) return std::pow(c, k - 1.0);
    return std::pow(eps, k - 1.0) * (c / eps);
}

// (NoL NoV)^(k-1) with each cosine guarded: the 1941 law divided by Lambert (value = albedo NoL * this).
double Minnaert_limb(double NoL, double NoV, double k) {
    const double eps = limb_eps(k);
    return Minnaert_cos_pow(NoL, k, eps) * Minnaert_cos_pow(NoV, k, eps);
}

// 1 - NoV, written as |N - V|^2 / 2 (equal for unit vectors; the kernel uses the same form to avoid the
// cancellation near V = N, so the two agree on what the formula means for not-quite-unit float vectors).
double Minnaert_one_minus_NoV(const dvec3& N, const dvec3& V) {
    const dvec3 d = N - V;
    return 0.5 * glm::dot(d, d);
}

double saturate(double x) { return std::clamp(x, 0.0, 1.0); }

// Seeds 000/001: saturate(NoL * pow(NoL * NoV, k)), NoL and NoV max(0, .)-clamped by the caller.
// pow(0, k < 0) is +inf and the saturate makes it 1, as in the seeds' HLSL.
double Fd_MinnaertUnity(double NoL, double NoV, double k) {
    const double prod = NoL * NoV;
    if (prod == 0.0 && k < 0.0) return 1.0;   // NoL * inf, saturated (NoL > 0 here)
    return saturate(NoL * std::pow(prod, k));
}

// Blender Minnaert_Diff, darkness <= 1: pow(MAX2(nv*nl, 0.1), darkness - 1). Blender's code holds the
// constants as floats (0.1f); the reference uses the same value so the two models are the same function.
double Minnaert_blender_real(double NoL, double nv, double d) {
    return std::pow(std::max(nv * NoL, double(0.1f)), d - 1.0);
}

// Blender Minnaert_Diff, darkness > 1: pow(1.001 - nv, darkness - 1), 1.001 - nv = 0.001 + (1 - nv).
double Minnaert_blender_nvidia(double one_minus_nv, double d) { return std::pow(0.001 + one_minus_nv, d - 1.0); }

// Seed 002's MinnaertB divided by Lambert: (n.l)^k * (1 - n.v)^(1-k).
double MinnaertB_factor(double NoL, double one_minus_NoV, double k) {
    return std::pow(NoL, k) * std::pow(one_minus_NoV, 1.0 - k);
}

}  // namespace

void add_minnaert_references(Table& t) {
    // Minnaert (1941): B = B0 mu0^k mu^(k-1), here albedo NoL^k NoV^(k-1) = albedo NoL (NoL NoV)^(k-1).
    t["minnaert_1941"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const double k = m.params.at("k");
        const double NoL = glm::dot(N, L), NoV = glm::dot(N, V);
        if (!(NoL > 0.0 && NoV > 0.0)) return dvec3(0.0);
        return m.albedo * (NoL * Minnaert_limb(NoL, NoV, k));
    };
    t["minnaert_unity"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const double k = m.params.at("k");
        const double NoL = std::max(glm::dot(N, L), 0.0), NoV = std::max(glm::dot(N, V), 0.0);
        if (!(NoL > 0.0)) return dvec3(0.0);
        return m.albedo * Fd_MinnaertUnity(NoL, NoV, k);
    };
    t["minnaert_blender"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const double d = m.params.at("darkness");
        const double NoL = glm::dot(N, L), NoV = glm::dot(N, V);
        if (!(NoL > 0.0)) return dvec3(0.0);                 // Blender: if (nl <= 0) return 0
        const double nv = std::max(NoV, 0.0);                  // Blender: if (nv < 0) nv = 0
        const double one_minus_nv = NoV > 0.0 ? Minnaert_one_minus_NoV(N, V) : 1.0;
        const double factor = d <= 1.0 ? Minnaert_blender_real(NoL, nv, d) : Minnaert_blender_nvidia(one_minus_nv, d);
        return m.albedo * (NoL * factor);
    };
    t["minnaert_b"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const double k = m.params.at("k");
        const double NoL = glm::dot(N, L), NoV = glm::dot(N, V);
        if (!(NoL > 0.0)) return dvec3(0.0);
        const double one_minus_NoV = NoV > 0.0 ? Minnaert_one_minus_NoV(N, V) : 1.0;   // NoV clamped to [0, 1]
        return m.albedo * (NoL * MinnaertB_factor(NoL, one_minus_NoV, k));
    };
    // f_r = rho (k+1)/(2 pi) (NoL NoV)^(k-1); value = pi f_r NoL.
    t["minnaert_normalized"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const double k = m.params.at("k");
        const double NoL = glm::dot(N, L), NoV = glm::dot(N, V);
        if (!(NoL > 0.0 && NoV > 0.0)) return dvec3(0.0);
        const double f_r_times_pi = (k + 1.0) / 2.0 * Minnaert_limb(NoL, NoV, k);
        return m.albedo * (f_r_times_pi * NoL);
    };
}

}  // namespace shadelab::ref
