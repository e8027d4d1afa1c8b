// Phong-family references in double, written from the formulas (docs/models/phong.md), sharing no code
// with kernels/models/phong.cl or host/models/phong.cpp. Term functions carry the kernel's names; the
// vectors R and H are built explicitly here (the kernel uses RoV = 2 NoL NoV - LoV and a guarded H).
#include <cmath>

#include "reference/reference.hpp"

namespace shadelab::ref {

namespace {

// dot(reflect(-L, N), V) with the mirror vector built as in Phong (1975): R = 2 (N.L) N - L.
double Phong_RoV(const dvec3& N, const dvec3& L, const dvec3& V) {
    const dvec3 R = 2.0 * glm::dot(N, L) * N - L;
    return glm::dot(R, V);
}

// N.H, H = (L + V) / |L + V| (Blinn 1977). Undefined for L = -V; taken as 0 there (|L + V| < 1e-10).
double BlinnPhong_NoH(const dvec3& N, const dvec3& L, const dvec3& V) {
    const dvec3 h = L + V;
    const double len = std::sqrt(glm::dot(h, h));
    return len > 1e-10 ? glm::dot(N, h) / len : 0.0;
}

// max(0, x)^n with the n -> 0+ limit at n = 0: x^n for x > 0, 0 for x <= 0 (never pow(0, 0) = 1).
double Spec_Power(double x, double n) { return x > 0.0 ? std::pow(x, n) : 0.0; }

double Spec_Gate(double NoL) { return NoL > 0.0 ? 1.0 : 0.0; }

double Fd_Lambert_cos(double NoL) { return NoL > 0.0 ? NoL : 0.0; }

// Giesen (2009): directional albedo of (K / pi) NoH^n NoL at V = N is 1 for K = (n+2)(n+4) / (8 (2^(-n/2) + n)).
double BlinnPhong_norm_exact(double n) { return (n + 2.0) * (n + 4.0) / (8.0 * (std::pow(2.0, -n / 2.0) + n)); }

// Real-Time Rendering's (n + 8) / (8 pi), times pi.
double BlinnPhong_norm_approx(double n) { return (n + 8.0) / 8.0; }

// Phong's (n + 2) / (2 pi), times pi.
double Phong_norm(double n) { return (n + 2.0) / 2.0; }

// The normalised forms: (1 - ks) albedo NoL+ + ks specular K lobe NoL+.
dvec3 normalized(const Material& m, double NoL, double lobe, double K) {
    const double ks = m.params.at("ks");
    return (1.0 - ks) * m.albedo * Fd_Lambert_cos(NoL) + ks * K * lobe * Fd_Lambert_cos(NoL) * m.specular;
}

}  // namespace

void add_phong_references(Table& t) {
    t["phong"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const double NoL = glm::dot(N, L);
        const double spec = m.params.at("ks") * Spec_Gate(NoL) * Spec_Power(Phong_RoV(N, L, V), m.params.at("n"));
        return m.albedo * Fd_Lambert_cos(NoL) + spec * m.specular;
    };
    t["phong_seed001"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const double n = m.params.at("gloss") / 4.0;   // seed 001: pow(RdotV, _SpecularGloss / 4)
        const double spec = m.params.at("specular_power") * Spec_Power(Phong_RoV(N, L, V), n);
        return m.albedo * Fd_Lambert_cos(glm::dot(N, L)) + spec * m.specular;
    };
    t["phong_normalized"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const double n = m.params.at("n");
        return normalized(m, glm::dot(N, L), Spec_Power(Phong_RoV(N, L, V), n), Phong_norm(n));
    };
    t["blinn_phong"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const double NoL = glm::dot(N, L);
        const double spec = m.params.at("ks") * Spec_Gate(NoL) * Spec_Power(BlinnPhong_NoH(N, L, V), m.params.at("n"));
        return m.albedo * Fd_Lambert_cos(NoL) + spec * m.specular;
    };
    t["blinn_phong_seed001"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const double spec = m.params.at("specular_power") * Spec_Power(BlinnPhong_NoH(N, L, V), m.params.at("gloss"));
        return m.albedo * Fd_Lambert_cos(glm::dot(N, L)) + spec * m.specular;
    };
    t["blinn_phong_normalized"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const double n = m.params.at("n");
        return normalized(m, glm::dot(N, L), Spec_Power(BlinnPhong_NoH(N, L, V), n), BlinnPhong_norm_exact(n));
    };
    t["blinn_phong_normalized_approx"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&,
                                            const Material& m) {
        const double n = m.params.at("n");
        return normalized(m, glm::dot(N, L), Spec_Power(BlinnPhong_NoH(N, L, V), n), BlinnPhong_norm_approx(n));
    };
}

}  // namespace shadelab::ref
