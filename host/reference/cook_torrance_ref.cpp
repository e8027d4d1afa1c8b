// Cook-Torrance references in double, written from the papers' formulas as printed (angles through tan alpha,
// Gc with LoH, the Fresnel equation with eta): Cook & Torrance (1982), Beckmann (1963) in the slides' normalised
// form, Walter et al. (2007) eq. 33 for GGX, Schlick (1994), Blinn (1977) for the V-groove G.
//   f_s   = F D G / (pi NoL NoV)                                   (the 1982 specular BRDF)
//   value = kd albedo max(NoL, 0) + ks specular * pi f_s NoL       (pi f_r NoL, the value convention)
// The model is defined for unit vectors: the (float-rounded) inputs are normalised here in double.
#include <algorithm>
#include <cmath>

#include "reference/reference.hpp"

namespace shadelab::ref {

namespace {

dvec3 unit(const dvec3& v) {
    const double len = glm::length(v);
    return len > 0.0 ? v / len : v;   // a zero vector (a point light on the surface point) stays zero
}

// Beckmann: D = exp(-(tan alpha / m)^2) / (pi m^2 cos^4 alpha), alpha the angle between N and H.
double D_Beckmann(double cos_alpha, double tan_alpha, double m) {
    if (!(cos_alpha > 0.0)) return 0.0;   // H on or below the horizon
    const double e = std::exp(-(tan_alpha / m) * (tan_alpha / m));
    if (e == 0.0) return 0.0;             // the limit at the horizon: exp vanishes faster than cos^4
    const double c2 = cos_alpha * cos_alpha;
    return e / (M_PI * m * m * c2 * c2);
}

// GGX (Walter et al. 2007, eq. 33): D = m^2 / (pi cos^4 alpha (m^2 + tan^2 alpha)^2).
double D_GGX(double cos_alpha, double tan_alpha, double m) {
    // At the horizon cos^4 (m^2 + tan^2)^2 -> 1 (sin^4); the product is formed as (cos^2 (m^2 + tan^2))^2,
    // which only overflows for cos < 1e-150 (and NoH >= (NoL + NoV) / 2 wherever the lobe is evaluated).
    if (!(cos_alpha > 1e-150)) return m * m / M_PI;
    const double c2 = cos_alpha * cos_alpha;
    const double q = c2 * (m * m + tan_alpha * tan_alpha);
    return m * m / (M_PI * q * q);
}

// Schlick (1994): F = f0 + (1 - f0) (1 - cos theta)^5, cos theta = VoH.
double F_Schlick(double VoH, double f0) { return f0 + (1.0 - f0) * std::pow(1.0 - VoH, 5.0); }

// Seed 004 read literally: (1 - theta)^5 with theta the angle between H and V in radians (atan2 of |V x H| and
// V.H: well conditioned at theta = 0, where acos is not).
double F_SchlickSeedAngle(const dvec3& V, const dvec3& H, double f0) {
    const double theta = std::atan2(glm::length(glm::cross(V, H)), glm::dot(V, H));
    return f0 + (1.0 - f0) * std::pow(1.0 - theta, 5.0);
}

// Fresnel equation for unpolarised light (Cook & Torrance 1982), c = VoH, eta from f0 = ((eta - 1)/(eta + 1))^2:
//   g = sqrt(eta^2 + c^2 - 1),  F = 1/2 (g - c)^2 / (g + c)^2 (1 + (c (g + c) - 1)^2 / (c (g - c) + 1)^2).
double F_Dielectric(double c, double f0) {
    if (f0 >= 1.0) return 1.0;   // eta -> infinity: a perfect mirror, F = 1 at every angle (the limit)
    const double eta = (1.0 + std::sqrt(f0)) / (1.0 - std::sqrt(f0));
    const double g = std::sqrt(eta * eta + c * c - 1.0);
    const double a = (g - c) / (g + c);
    const double b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    return 0.5 * a * a * (1.0 + b * b);
}

// V-groove: G = min(1, 2 NoH NoV / VoH, 2 NoH NoL / LoH), as the paper and the slides print it.
double G_VGroove(double NoL, double NoV, double NoH, double VoH, double LoH) {
    return std::min({1.0, 2.0 * NoH * NoV / VoH, 2.0 * NoH * NoL / LoH});
}

enum class Dist { Beckmann, GGX };
enum class Fres { Schlick, Exact, SeedAngle };

dvec3 cook_torrance(const dvec3& N_, const dvec3& L_, const dvec3& V_, const Material& m, Dist dist, Fres fres) {
    const double rough = m.params.at("m"), f0 = m.params.at("f0"), kd = m.params.at("kd"), ks = m.params.at("ks");
    const dvec3 N = unit(N_), L = unit(L_), V = unit(V_);
    const double NoL = glm::dot(N, L), NoV = glm::dot(N, V);
    const dvec3 diffuse = kd * m.albedo * std::max(NoL, 0.0);
    // No specular term with light or view below the surface, nor where H is undefined (L = -V; with NoL, NoV > 0
    // only within |L + V| <= 1e-6 of the horizon, the model's own definition there, as in the kernel).
    const dvec3 s = L + V;
    if (!(NoL > 0.0) || !(NoV > 0.0) || !(glm::dot(s, s) > 1e-12)) return diffuse;
    const dvec3 H = glm::normalize(s);
    const double NoH = glm::dot(N, H), VoH = glm::dot(V, H), LoH = glm::dot(L, H);
    const double tan_alpha = glm::length(glm::cross(N, H)) / NoH;   // NoH >= (NoL + NoV) / 2 > 0 here
    const double D = dist == Dist::Beckmann ? D_Beckmann(NoH, tan_alpha, rough) : D_GGX(NoH, tan_alpha, rough);
    const double F = fres == Fres::Schlick ? F_Schlick(VoH, f0)
                     : fres == Fres::Exact ? F_Dielectric(VoH, f0)
                                           : F_SchlickSeedAngle(V, H, f0);
    const double G = G_VGroove(NoL, NoV, NoH, VoH, LoH);
    const double f_s = F * D * G / (M_PI * NoL * NoV);   // the paper's specular BRDF
    return diffuse + ks * m.specular * (M_PI * f_s * NoL);
}

}  // namespace

void add_cook_torrance_references(Table& t) {
    t["cook_torrance"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        return cook_torrance(N, L, V, m, Dist::Beckmann, Fres::Schlick);
    };
    t["cook_torrance_ggx"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        return cook_torrance(N, L, V, m, Dist::GGX, Fres::Schlick);
    };
    t["cook_torrance_exact_fresnel"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&,
                                          const Material& m) {
        return cook_torrance(N, L, V, m, Dist::Beckmann, Fres::Exact);
    };
    t["cook_torrance_seed004"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        return cook_torrance(N, L, V, m, Dist::Beckmann, Fres::SeedAngle);
    };
}

}  // namespace shadelab::ref
