// Oren-Nayar family references in double, written from the sources' formulas in their own form (acos, sin,
// tan, normalised projections, the seeds' literal expressions), computing their constants from the
// parameters. Term functions carry the kernel's names (kernels/models/oren_nayar.cl); no code is shared.
//
// Inputs are renormalised in double: the sweep's float-rounded vectors are unit only to ~1e-7, and acos of
// a dot product of two such "parallel" vectors would turn that length error into an angle of ~4e-4 rad.
//
// Conventions shared with the kernels (docs/models/oren_nayar.md): value = pi f_r NoL, 0 for NoL <= 0; for
// the paper-based models a view below the horizon is a grazing view (theta_r = 90 deg) at the same azimuth.
#include <algorithm>
#include <cmath>

#include "reference/reference.hpp"

namespace shadelab::ref {

namespace {

constexpr double kPi = 3.14159265358979323846;

dvec3 unit(const dvec3& v) { return v / std::sqrt(glm::dot(v, v)); }
double safe_acos(double x) { return std::acos(std::clamp(x, -1.0, 1.0)); }
double saturate(double x) { return std::clamp(x, 0.0, 1.0); }

// Directions in the paper's terms: polar angles, and the cosine of the azimuth difference.
struct Angles {
    double NoL, NoV, LoV;
    double theta_i, theta_r;   // theta_r = 90 deg for a view below the horizon
    double cos_dphi;           // 0 when either direction has no azimuth (along +-N)
};

Angles angles(const dvec3& N0, const dvec3& L0, const dvec3& V0) {
    const dvec3 N = unit(N0), L = unit(L0), V = unit(V0);
    Angles a;
    a.NoL = glm::dot(N, L);
    a.NoV = glm::dot(N, V);
    a.LoV = glm::dot(L, V);
    a.theta_i = safe_acos(a.NoL);
    a.theta_r = safe_acos(std::max(a.NoV, 0.0));
    const dvec3 Lt = L - N * a.NoL, Vt = V - N * a.NoV;
    const double ll = glm::length(Lt), lv = glm::length(Vt);
    a.cos_dphi = (ll > 1e-12 && lv > 1e-12) ? std::clamp(glm::dot(Lt, Vt) / (ll * lv), -1.0, 1.0) : 0.0;
    return a;
}

double qon_A(double sigma) { return 1.0 - 0.5 * sigma * sigma / (sigma * sigma + 0.33); }
double qon_B(double sigma) { return 0.45 * sigma * sigma / (sigma * sigma + 0.09); }

// ---- the paper's qualitative model, literally --------------------------------------------------------------
double Fd_OrenNayar(double A, double B, const Angles& a) {
    const double alpha = std::max(a.theta_i, a.theta_r), beta = std::min(a.theta_i, a.theta_r);
    return A + B * std::max(0.0, a.cos_dphi) * std::sin(alpha) * std::tan(beta);
}

// s = LoV - NoL NoV = sin(theta_i) sin(theta_r) cos(phi_i - phi_r), theta_r = 90 deg below the horizon.
double ON_s(const Angles& a) {
    if (a.NoV >= 0.0) return a.LoV - a.NoL * a.NoV;
    return std::sin(a.theta_i) * a.cos_dphi;   // sin(theta_r) = 1
}

double Fd_OrenNayar_st(double A, double B, const Angles& a) {
    return A + B * std::max(0.0, ON_s(a)) / std::max(a.NoL, std::max(a.NoV, 0.0));
}

// ---- the paper's full model ------------------------------------------------------------------------------------
double ON_C2(double sigma, const Angles& a, double alpha, double beta) {
    const double s2 = sigma * sigma;
    const double k = 0.45 * s2 / (s2 + 0.09);
    return a.cos_dphi >= 0.0 ? k * std::sin(alpha) : k * (std::sin(alpha) - std::pow(2.0 * beta / kPi, 3.0));
}
double ON_C3(double sigma, double alpha, double beta) {
    const double s2 = sigma * sigma;
    return 0.125 * (s2 / (s2 + 0.09)) * std::pow(4.0 * alpha * beta / (kPi * kPi), 2.0);
}
double ON_L2(double sigma, const Angles& a, double beta) {
    const double s2 = sigma * sigma;
    return 0.17 * s2 / (s2 + 0.13) * (1.0 - a.cos_dphi * std::pow(2.0 * beta / kPi, 2.0));
}

// ---- Fujii ------------------------------------------------------------------------------------------------------
double ON_s_over_t(const Angles& a) {
    const double s = ON_s(a);
    const double t = s <= 0.0 ? 1.0 : std::max(a.NoL, std::max(a.NoV, 0.0));
    return s / t;
}

// ---- EON ----------------------------------------------------------------------------------------------------------
const double kFonC1 = 0.5 - 2.0 / (3.0 * kPi);
const double kFonC2 = 2.0 / 3.0 - 28.0 / (15.0 * kPi);

// The paper's E_FON_exact: AF + (BF/pi) G, G = S(acos mu - S mu) + 2/3 ((S/mu)(1 - S^3) - S).
double E_FON_exact(double mu, double r) {
    const double AF = 1.0 / (1.0 + kFonC1 * r), BF = r * AF;
    const double S = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    // (S/mu)(1 - S^3) -> 0 as mu -> 0 (1 - S^3 ~ 1.5 mu^2); the limit is used at mu = 0 exactly.
    const double ratio = mu > 0.0 ? (S / mu) * (1.0 - S * S * S) : 0.0;
    const double G = S * (safe_acos(mu) - S * mu) + (2.0 / 3.0) * (ratio - S);
    return AF + (BF / kPi) * G;
}

// The paper's E_FON_approx (its GLSL mat2 of coefficients, written out).
double E_FON_approx(double mu, double r) {
    const double m = 1.0 - mu, m2 = m * m;
    const double GoverPi = (0.0571085289 * m + 0.491881867 * m2) + (-0.332181442 * m + 0.0714429953 * m2) * m2;
    return (1.0 + r * GoverPi) / (1.0 + kFonC1 * r);
}

template <double (*E)(double, double)>
dvec3 eon_value(const Angles& a, const Material& m) {
    const double r = m.params.at("roughness");
    const double AF = 1.0 / (1.0 + kFonC1 * r);
    const dvec3 f_ss = m.albedo * AF * (1.0 + r * ON_s_over_t(a));
    const double Eo = E(std::max(a.NoV, 0.0), r), Ei = E(a.NoL, r);
    const double Ebar = AF * (1.0 + kFonC2 * r);
    dvec3 rho_ms;
    for (int c = 0; c < 3; ++c) {
        const double rho = m.albedo[c];
        // Same floor as the kernel: only reached for albedo > 5.9, where the series diverges.
        rho_ms[c] = rho * rho * Ebar / std::max(1.0 - rho * (1.0 - Ebar), 1e-3);
    }
    // The listing's max(eps, .) guards; at r = 0 (where 1 - Ebar = 0) f_ms is 0 (its limit).
    const dvec3 f_ms = (r > 0.0) ? rho_ms * std::max(0.0, 1.0 - Eo) * std::max(0.0, 1.0 - Ei) / (1.0 - Ebar)
                                 : dvec3(0.0);
    return a.NoL * (f_ss + f_ms);
}

}  // namespace

void add_oren_nayar_references(Table& t) {
    t["oren_nayar"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const Angles a = angles(N, L, V);
        if (a.NoL <= 0.0) return dvec3(0.0);
        const double sigma = m.params.at("sigma");
        return m.albedo * a.NoL * Fd_OrenNayar(qon_A(sigma), qon_B(sigma), a);
    };

    t["oren_nayar_st"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const Angles a = angles(N, L, V);
        if (a.NoL <= 0.0) return dvec3(0.0);
        const double sigma = m.params.at("sigma");
        return m.albedo * a.NoL * Fd_OrenNayar_st(qon_A(sigma), qon_B(sigma), a);
    };

    t["oren_nayar_full"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const Angles a = angles(N, L, V);
        if (a.NoL <= 0.0) return dvec3(0.0);
        const double sigma = m.params.at("sigma");
        const double alpha = std::max(a.theta_i, a.theta_r), beta = std::min(a.theta_i, a.theta_r);
        const double L1 = qon_A(sigma) + a.cos_dphi * ON_C2(sigma, a, alpha, beta) * std::tan(beta) +
                          (1.0 - std::abs(a.cos_dphi)) * ON_C3(sigma, alpha, beta) * std::tan(0.5 * (alpha + beta));
        const double L2 = ON_L2(sigma, a, beta);
        return a.NoL * (m.albedo * L1 + m.albedo * m.albedo * L2);
    };

    // Seed 001, as written: saturate()s, step/lerp division, albedo * NoL * (x + albedo y + z s).
    t["oren_nayar_seed001"] = [](const dvec3& N0, const dvec3& L0, const dvec3& V0, const dvec3&,
                                 const Material& m) {
        const dvec3 N = unit(N0), L = unit(L0), V = unit(V0);
        const double r = m.params.at("sigma"), r2 = r * r;
        const dvec3 fraction = r2 / (dvec3(r2) + dvec3(0.33, 0.13, 0.09));
        const dvec3 on = dvec3(1.0, 0.0, 0.0) + dvec3(-0.5, 0.17, 0.45) * fraction;
        const double cos_ndotl = saturate(glm::dot(N, L));
        const double cos_ndotv = saturate(glm::dot(N, V));
        if (cos_ndotl <= 0.0) return dvec3(0.0);
        double s = saturate(glm::dot(L, V)) - cos_ndotl * cos_ndotv;
        const double step_s0 = (0.0 >= s) ? 1.0 : 0.0;                          // HLSL step(s, 0)
        const double lerp = std::max(cos_ndotl, cos_ndotv) * (1.0 - step_s0) + 1.0 * step_s0;
        s /= lerp;
        return m.albedo * cos_ndotl * (on.x + m.albedo * on.y + on.z * s);
    };

    // Seed 003's HLSL, as written (acos, sin, tan).
    t["oren_nayar_seed003"] = [](const dvec3& N0, const dvec3& L0, const dvec3& V0, const dvec3&,
                                 const Material& m) {
        const dvec3 N = unit(N0), L = unit(L0), V = unit(V0);
        const double NormalLight = saturate(glm::dot(N, L));
        const double NormalView = saturate(glm::dot(N, V));
        if (NormalLight <= 0.0) return dvec3(0.0);
        const double PhiR = glm::length(V - N * NormalView) * glm::length(L - N * NormalLight);
        const double ACosNormalView = std::acos(NormalView), ACosNormalLight = std::acos(NormalLight);
        const double Alpha = std::max(ACosNormalView, ACosNormalLight);
        const double Beta = std::min(ACosNormalView, ACosNormalLight);
        const double Roughness = std::pow(m.params.at("roughness"), 2.0);
        const double A = 1.0 - 0.5 * (Roughness / (Roughness + 0.33));
        const double B = 0.45 * (Roughness / (Roughness + 0.09));
        return m.albedo * (NormalLight * (A + B * std::max(0.0, PhiR) * std::sin(Alpha) * std::tan(Beta)));
    };

    // Seed 004's slide formulas, as written (angles from the raw dot products).
    t["oren_nayar_seed004"] = [](const dvec3& N0, const dvec3& L0, const dvec3& V0, const dvec3&,
                                 const Material& m) {
        const dvec3 n = unit(N0), l = unit(L0), e = unit(V0);
        const double nl = glm::dot(n, l);
        if (nl <= 0.0) return dvec3(0.0);
        const double r2 = std::pow(m.params.at("sigma"), 2.0);
        const double A = 1.0 - 0.5 * r2 / (r2 + 0.57);
        const double B = 0.45 * r2 / (r2 + 0.09);
        const double angle_nv = safe_acos(glm::dot(n, e)), angle_nl = safe_acos(nl);
        const double alpha = std::max(angle_nv, angle_nl), beta = std::min(angle_nv, angle_nl);
        const double C = std::sin(alpha) * std::tan(beta);
        const double gamma = glm::dot(e - n * glm::dot(e, n), l - n * glm::dot(l, n));
        return m.albedo * (std::max(0.0, nl) * (A + B * std::max(0.0, gamma) * C));
    };

    // Blender 2.4x OrenNayar_Diff, as in shadeoutput.c (with nl = the light's dot product).
    t["oren_nayar_blender"] = [](const dvec3& N0, const dvec3& L0, const dvec3& V0, const dvec3&,
                                 const Material& m) {
        const dvec3 n = unit(N0), l = unit(L0), v = unit(V0);
        double nv = glm::dot(n, v);
        if (nv <= 0.0) nv = 0.0;
        const double realnl = glm::dot(n, l);
        if (realnl <= 0.0) return dvec3(0.0);
        const double Lit_A = safe_acos(realnl), View_A = safe_acos(nv);
        auto normalize_v3 = [](dvec3 x) {   // Blender's: a zero vector stays zero
            const double d = glm::length(x);
            return d > 1e-35 ? x / d : dvec3(0.0);
        };
        const dvec3 Lit_B = normalize_v3(l - realnl * n), View_B = normalize_v3(v - nv * n);
        double t_ = glm::dot(Lit_B, View_B);
        if (t_ < 0) t_ = 0;
        double a, b;
        if (Lit_A > View_A) { a = Lit_A; b = View_A; } else { a = View_A; b = Lit_A; }
        const double rough = m.params.at("sigma");
        const double A = 1.0 - (0.5 * ((rough * rough) / ((rough * rough) + 0.33)));
        const double B = 0.45 * ((rough * rough) / ((rough * rough) + 0.09));
        b *= 0.95;
        return m.albedo * (realnl * (A + (B * t_ * std::sin(a) * std::tan(b))));
    };

    t["oren_nayar_fujii"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const Angles a = angles(N, L, V);
        if (a.NoL <= 0.0) return dvec3(0.0);
        const double sp = m.params.at("roughness");                   // sigma'
        const double A = 1.0 / (kPi + (kPi / 2.0 - 2.0 / 3.0) * sp), B = sp * A;
        return kPi * m.albedo * a.NoL * (A + B * ON_s_over_t(a));   // value = pi f_r NoL
    };

    t["oren_nayar_fujii_full"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&,
                                    const Material& m) {
        const Angles a = angles(N, L, V);
        if (a.NoL <= 0.0) return dvec3(0.0);
        const double s2 = std::pow(m.params.at("sigma"), 2.0);
        const dvec3 A = (1.0 / kPi) * (dvec3(1.0 - 0.5 * s2 / (s2 + 0.33)) + 0.17 * m.albedo * s2 / (s2 + 0.13));
        const double B = (1.0 / kPi) * (0.45 * s2 / (s2 + 0.09));
        return kPi * m.albedo * a.NoL * (A + B * ON_s_over_t(a));
    };

    t["eon"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const Angles a = angles(N, L, V);
        return a.NoL <= 0.0 ? dvec3(0.0) : eon_value<E_FON_exact>(a, m);
    };
    t["eon_approx"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
        const Angles a = angles(N, L, V);
        return a.NoL <= 0.0 ? dvec3(0.0) : eon_value<E_FON_approx>(a, m);
    };
}

}  // namespace shadelab::ref
