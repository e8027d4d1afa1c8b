// Planetary family references in double, written from the papers' formulas in their own form (phase angle and
// azimuth as angles through acos, 1 +- cos g as they stand, std::exp, pow(x, 1.5)), computing their constants
// from the parameters. Term functions carry the kernel's names (kernels/models/planetary.cl); no code is shared.
#include "reference/planetary_ref.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.hpp"
#include "reference/reference.hpp"

namespace shadelab::ref {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;


// ---- laws ---------------------------------------------------------------------------------------------
double Pho_LunarLambert(double mu0, double mu, double L) { return mu0 * ((1.0 - L) + 2.0 * L / (mu0 + mu)); }
double Pho_McEwen_L(double g, double m1, double m2, double m3) { return 1.0 + m1 * g + m2 * g * g + m3 * g * g * g; }

// Hapke (1981): H(x) = (1 + 2x) / (1 + 2x sqrt(1 - w)).
double Hapke_H(double x, double w) { return (1.0 + 2.0 * x) / (1.0 + 2.0 * x * std::sqrt(1.0 - w)); }

// Hapke (1986): B(g) = B0 / (1 + tan(g/2) / h); none without a width (h = 0), as ISIS.
double Hapke_B(double g_deg, double b0, double h) {
    if (h == 0.0) return 0.0;
    if (g_deg >= 180.0) return 0.0;   // tan(90 deg) is infinite
    return b0 / (1.0 + std::tan(0.5 * g_deg * kDeg) / h);
}

// ISIS's two-term Henyey-Greenstein function of the phase angle.
double Hapke_P_HG2(double g_deg, double b, double c) {
    const double cg = std::cos(g_deg * kDeg);
    return (1.0 - c) * (1.0 - b * b) / std::pow(1.0 + b * b + 2.0 * b * cg, 1.5) +
           c * (1.0 - b * b) / std::pow(1.0 + b * b - 2.0 * b * cg, 1.5);
}

double Hapke_P_Legendre(double g_deg, double b, double c) {
    const double cg = std::cos(g_deg * kDeg);
    return 1.0 + b * cg + c * (1.5 * cg * cg - 0.5);
}

// pi r of a smooth surface (Hapke 1981 with the 1986 surge).
double Hapke_smooth(double mu0, double mu, double w, double B, double P) {
    return w / 4.0 * mu0 / (mu0 + mu) * ((1.0 + B) * P - 1.0 + Hapke_H(mu0, w) * Hapke_H(mu, w));
}

// Hapke (1984) roughness: the smooth law at the effective cosines times S(i, e, psi), eqs. 46-51 (angles as
// angles: psi = acos(cos psi), f = exp(-2 tan(psi/2))). Two points of the definition shared with the kernel
// (docs/photometry.md): the denominators 2 - E1(x) - (psi/pi) E1(y) are summed as (1 - E1(x)) + (1 - psi/pi) +
// (psi/pi)(1 - E1(y)) with 1 - E1 = -expm1(.), because as printed they cancel to rounding noise (and turn
// negative) at theta-bar -> 90 deg, psi -> 180 deg even in double; and the effective cosines are floored at 0,
// the law 0 where both are 0.
template <typename Smooth>
double Hapke_rough(const PhotometricAngles& a, double theta_deg, Smooth smooth) {
    const double t = theta_deg * kDeg;
    const double tan_t = std::tan(t), cot_t = 1.0 / tan_t;
    const double chi = 1.0 / std::sqrt(1.0 + kPi * tan_t * tan_t);
    const double cot_i = a.mu0 / std::max(a.sin_i, 1e-10), cot_e = a.mu / std::max(a.sin_e, 1e-10);
    auto E1 = [&](double cot_x) { return std::exp(-2.0 / kPi * cot_t * cot_x); };
    auto one_minus_E1 = [&](double cot_x) { return -std::expm1(-2.0 / kPi * cot_t * cot_x); };
    auto E2 = [&](double cot_x) { return std::exp(-1.0 / kPi * cot_t * cot_t * cot_x * cot_x); };
    auto eta = [&](double cos_x, double sin_x, double cot_x) {
        return chi * (cos_x + sin_x * tan_t * E2(cot_x) / (2.0 - E1(cot_x)));
    };
    const double psi = a.psi, cos_psi = std::cos(psi);
    const double one_minus_f = psi >= kPi ? 1.0 : -std::expm1(-2.0 * std::tan(psi / 2.0));   // 1 - f(psi)
    const double s2 = std::pow(std::sin(psi / 2.0), 2.0);
    const double eta_i = eta(a.mu0, a.sin_i, cot_i), eta_e = eta(a.mu, a.sin_e, cot_e);
    double mu0e, mue, q;
    // i <= e; where the cosines are equal (rounded), the sines decide (near i = e = 0)
    if (a.mu0 > a.mu || (a.mu0 == a.mu && a.sin_i <= a.sin_e)) {
        const double den = one_minus_E1(cot_e) + (kPi - psi) / kPi + psi / kPi * one_minus_E1(cot_i);
        mu0e = chi * (a.mu0 + a.sin_i * tan_t * (cos_psi * E2(cot_e) + s2 * E2(cot_i)) / den);
        mue = chi * (a.mu + a.sin_e * tan_t * (E2(cot_e) - s2 * E2(cot_i)) / den);
        q = chi * a.mu0 / eta_i;
    } else {
        const double den = one_minus_E1(cot_i) + (kPi - psi) / kPi + psi / kPi * one_minus_E1(cot_e);
        mu0e = chi * (a.mu0 + a.sin_i * tan_t * (E2(cot_i) - s2 * E2(cot_e)) / den);
        mue = chi * (a.mu + a.sin_e * tan_t * (cos_psi * E2(cot_i) + s2 * E2(cot_e)) / den);
        q = chi * a.mu / eta_e;
    }
    mu0e = std::max(mu0e, 0.0);
    mue = std::max(mue, 0.0);
    if (!(mu0e + mue > 0.0)) return 0.0;
    const double S = mue / eta_e * a.mu0 / eta_i * chi / (one_minus_f + (1.0 - one_minus_f) * q);
    return smooth(mu0e, mue) * S;
}

// Hapke (2002), eq. 13: H(x) = 1 / (1 - w x [r0 + (1 - 2 r0 x)/2 ln((1 + x)/x)]), r0 = (1 - gamma)/(1 + gamma).
double Hapke_H2002(double x, double w) {
    const double g = std::sqrt(1.0 - w), r0 = (1.0 - g) / (1.0 + g);
    const double xl = x > 0.0 ? x * std::log((1.0 + x) / x) : 0.0;
    return 1.0 / (1.0 - w * (x * r0 + 0.5 * (1.0 - 2.0 * r0 * x) * xl));
}

// Hapke (2002) coherent backscatter: B_C(g) = (1 + (1 - exp(-z))/z) / (2 (1 + z)^2), z = tan(g/2)/h_C.
double Hapke_BC(double g_deg, double bc0, double hc) {
    if (hc == 0.0 || bc0 == 0.0) return 0.0;
    if (g_deg >= 180.0) return 0.0;
    const double z = std::tan(0.5 * g_deg * kDeg) / hc;
    const double frac = z == 0.0 ? 1.0 : -std::expm1(-z) / z;
    return bc0 * (1.0 + frac) / (2.0 * (1.0 + z) * (1.0 + z));
}

// Hapke (2008, 2012 eq. 12.55) without roughness: K (w/4) mu0/(mu0 + mu) [P (1 + B_SH) + H(mu0/K) H(mu/K) - 1] (1 + B_CB).
double Hapke2012_smooth(double mu0, double mu, double w, double K, double B_SH, double B_CB, double P) {
    const double M = Hapke_H2002(mu0 / K, w) * Hapke_H2002(mu / K, w) - 1.0;
    return K * w / 4.0 * mu0 / (mu0 + mu) * (P * (1.0 + B_SH) + M) * (1.0 + B_CB);
}

double Hapke_value(const PhotometricAngles& a, const Material& m, double P) {
    const double w = m.params.at("wh"), b0 = m.params.at("b0"), h = m.params.at("hh"), theta = m.params.at("theta");
    const double B = Hapke_B(a.g_deg, b0, h);
    if (theta <= 0.0) return Hapke_smooth(a.mu0, a.mu, w, B, P);
    return Hapke_rough(a, theta, [&](double x0, double x) { return Hapke_smooth(x0, x, w, B, P); });
}

double Hapke2012_value(const PhotometricAngles& a, const Material& m) {
    const double w = m.params.at("wh"), theta = m.params.at("theta"), phi = m.params.at("phi");
    const double P = Hapke_P_HG2(a.g_deg, m.params.at("hg1"), m.params.at("hg2"));
    const double B_SH = Hapke_B(a.g_deg, m.params.at("b0"), m.params.at("hh"));
    const double B_CB = Hapke_BC(a.g_deg, m.params.at("bc0"), m.params.at("hc"));
    // Hapke (2008): K = -ln(1 - 1.209 phi^(2/3)) / (1.209 phi^(2/3)), 1 at phi = 0
    const double y = 1.209 * std::pow(phi, 2.0 / 3.0);
    const double K = phi > 0.0 ? -std::log(1.0 - y) / y : 1.0;
    auto smooth = [&](double x0, double x) { return Hapke2012_smooth(x0, x, w, K, B_SH, B_CB, P); };
    if (theta <= 0.0) return smooth(a.mu0, a.mu);
    return Hapke_rough(a, theta, smooth);
}

double mcewen_L(const Material& m, double g_deg) {
    return Pho_McEwen_L(g_deg, m.params.at("m1"), m.params.at("m2"), m.params.at("m3"));
}

}  // namespace

double cos_deg(double deg) {
    const double r = std::remainder(deg, 360.0);   // [-180, 180]
    if (std::abs(r) == 90.0) return 0.0;
    return std::cos(r * kDeg);
}

double sin_deg(double deg) {
    const double r = std::remainder(deg, 360.0);
    if (r == 0.0 || std::abs(r) == 180.0) return 0.0;
    return std::sin(r * kDeg);
}

PhotometricAngles angles_from_degrees(double g, double i, double e) {
    PhotometricAngles a;
    a.mu0 = cos_deg(i);
    a.mu = cos_deg(e);
    a.sin_i = sin_deg(i);
    a.sin_e = sin_deg(e);
    a.g_deg = g;
    if (a.sin_i * a.sin_e == 0.0) return a;   // psi = 0
    const double s = sin_deg(0.5 * (g + i - e)) * sin_deg(0.5 * (g - i + e));
    const double c = sin_deg(0.5 * (i + e + g)) * sin_deg(0.5 * (i + e - g));
    a.psi = s <= 0.0 ? 0.0 : (c <= 0.0 ? kPi : 2.0 * std::atan2(std::sqrt(s), std::sqrt(c)));
    return a;
}

PhotometricAngles angles_from_vectors(const glm::dvec3& N0, const glm::dvec3& L0, const glm::dvec3& V0) {
    const glm::dvec3 N = glm::normalize(N0), L = glm::normalize(L0), V = glm::normalize(V0);
    const glm::dvec3 nl = glm::cross(N, L), nv = glm::cross(N, V);
    PhotometricAngles a;
    a.mu0 = glm::dot(N, L);
    a.mu = glm::dot(N, V);
    a.sin_i = glm::length(nl);
    a.sin_e = glm::length(nv);
    a.g_deg = std::atan2(glm::length(glm::cross(L, V)), glm::dot(L, V)) / kDeg;
    // the angle between N x L and N x V: atan2(|a x b|, a . b), accurate at 0 and pi
    a.psi = a.sin_i * a.sin_e > 0.0 ? std::atan2(glm::length(glm::cross(nl, nv)), glm::dot(nl, nv)) : 0.0;
    return a;
}

bool is_planetary_model(const std::string& model) { return angle_reference_for(model) != nullptr; }

double planetary_value(const Material& m, const PhotometricAngles& a) {
    const AngleFn* f = angle_reference_for(m.model);
    if (!f) throw Error("model '" + m.model + "' is not one of the planetary laws (it has no form in photometric angles)");
    if (!(a.mu0 > 0.0 && a.mu > 0.0)) return 0.0;
    return (*f)(m, a);
}

namespace {
// The planetary family's laws at photometric angles (mu0, mu > 0: planetary_value checks), one function per law,
// so that an evaluation does not compare the model's name.
double mcewen_law(const Material& m, const PhotometricAngles& a) {
    return Pho_LunarLambert(a.mu0, a.mu, mcewen_L(m, a.g_deg));
}
double mcewen_ratio_law(const Material& m, const PhotometricAngles& a) {
    // R30: the law at g = 30, i = 30, e = 0; 0 where r <= 0; r floored at 1e-3 (kernel comment).
    const double c30 = std::cos(30.0 * kDeg);
    const double r30 = Pho_LunarLambert(c30, 1.0, mcewen_L(m, 30.0));
    const double r = Pho_LunarLambert(a.mu0, a.mu, mcewen_L(m, a.g_deg));
    return r > 0.0 ? r30 / std::max(r, 1e-3) : 0.0;
}
double hapke_2012_law(const Material& m, const PhotometricAngles& a) { return Hapke2012_value(a, m); }
double hapke_hen_law(const Material& m, const PhotometricAngles& a) {
    return Hapke_value(a, m, Hapke_P_HG2(a.g_deg, m.params.at("hg1"), m.params.at("hg2")));
}
double hapke_leg_law(const Material& m, const PhotometricAngles& a) {
    return Hapke_value(a, m, Hapke_P_Legendre(a.g_deg, m.params.at("bh"), m.params.at("ch")));
}
}  // namespace

void add_planetary_references(Table& t) {
    using Law = double (*)(const Material&, const PhotometricAngles&);
    const std::pair<const char*, Law> laws[] = {{"lunar_lambert_mcewen", mcewen_law},
                                                {"lunar_lambert_mcewen_ratio", mcewen_ratio_law},
                                                {"hapke_hen", hapke_hen_law},
                                                {"hapke_leg", hapke_leg_law},
                                                {"hapke_2012", hapke_2012_law}};
    for (const auto& [name, law] : laws) {
        t.angles[name] = law;
        // planetary_value's rule (0 where unlit or unseen) with the law itself, not looked up by name per call
        t[name] = [law = law](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
            const PhotometricAngles a = angles_from_vectors(N, L, V);
            return m.albedo * (a.mu0 > 0.0 && a.mu > 0.0 ? law(m, a) : 0.0);
        };
    }
}

}  // namespace shadelab::ref
