// Cook-Torrance references in double, from Cook & Torrance (1982), Beckmann (1963), Schlick (1994),
// Walter et al. (2007). value = kd albedo NoL + ks specular F D G / NoV  (= pi f_r NoL with f_s = FDG/(pi NoL NoV)).
#include <algorithm>
#include <cmath>

#include "reference/reference.hpp"

namespace shadelab::ref {

namespace {

double D_Beckmann(double NoH, double m) {
    const double c2 = NoH * NoH;
    if (c2 == 0.0) return 0.0;   // the limit: exp(-tan^2/m^2) vanishes faster than NoH^4
    const double tan2 = (1.0 - c2) / c2;
    return std::exp(-tan2 / (m * m)) / (M_PI * m * m * c2 * c2);
}

double D_GGX(double NoH, double m) {
    const double a2 = m * m;
    const double d = NoH * NoH * (a2 - 1.0) + 1.0;
    return a2 / (M_PI * d * d);
}

double F_Schlick(double VoH, double f0) { return f0 + (1.0 - f0) * std::pow(1.0 - VoH, 5.0); }

// The angle between V and H, as the seed words it; atan2(|V x H|, V.H) rather than acos(V.H), which is
// ill-conditioned at 0 (and inputs are float-rounded, so |V| differs from 1 by ~6e-8).
double F_SchlickSeedAngle(const dvec3& V, const dvec3& H, double f0) {
    const double theta = std::atan2(glm::length(glm::cross(V, H)), glm::dot(V, H));
    return f0 + (1.0 - f0) * std::pow(1.0 - theta, 5.0);
}

double F_Dielectric(double VoH, double f0) {
    const double eta = (1.0 + std::sqrt(f0)) / (1.0 - std::sqrt(f0));
    const double c = VoH;
    const double g = std::sqrt(eta * eta - 1.0 + c * c);
    const double a = (g - c) / (g + c);
    const double b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    return 0.5 * a * a * (1.0 + b * b);
}

// V-groove G = min(1, 2 NoH NoV / VoH, 2 NoH NoL / VoH), as written in the paper.
double G_VGroove(double NoL, double NoV, double NoH, double VoH) {
    return std::min({1.0, 2.0 * NoH * NoV / VoH, 2.0 * NoH * NoL / VoH});
}

enum class Dist { Beckmann, GGX };
enum class Fres { Schlick, Exact, SeedAngle };

dvec3 cook_torrance(const dvec3& N, const dvec3& L, const dvec3& V, const Material& m, Dist dist, Fres fres) {
    const double rough = m.params.at("m"), f0 = m.params.at("f0"), kd = m.params.at("kd"), ks = m.params.at("ks");
    const double NoL = glm::dot(N, L), NoV = glm::dot(N, V);
    const dvec3 diffuse = kd * m.albedo * std::max(NoL, 0.0);
    const dvec3 s = L + V;
    if (NoL <= 0.0 || NoV <= 0.0 || glm::dot(s, s) <= 1e-12) return diffuse;
    const dvec3 H = glm::normalize(s);
    const double NoH = std::max(glm::dot(N, H), 0.0), VoH = std::max(glm::dot(V, H), 1e-300);
    const double D = dist == Dist::Beckmann ? D_Beckmann(NoH, rough) : D_GGX(NoH, rough);
    const double F = fres == Fres::Schlick ? F_Schlick(VoH, f0) : fres == Fres::Exact ? F_Dielectric(VoH, f0) : F_SchlickSeedAngle(V, H, f0);
    const double G = G_VGroove(NoL, NoV, NoH, VoH);
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
    t["cook_torrance_exact_fresnel"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        return cook_torrance(N, L, V, m, Dist::Beckmann, Fres::Exact);
    };
    t["cook_torrance_seed004"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        return cook_torrance(N, L, V, m, Dist::Beckmann, Fres::SeedAngle);
    };
}

}  // namespace shadelab::ref
