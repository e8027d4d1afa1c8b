#include "color/color.hpp"

#include <cmath>

namespace shadelab {

namespace {
constexpr double kXn = 0.95047, kYn = 1.0, kZn = 1.08883;
constexpr double kDelta = 6.0 / 29.0;   // CIE 1976: the cube-root segment starts at (6/29)^3

double lab_f(double t) {
    return t > kDelta * kDelta * kDelta ? std::cbrt(t) : t / (3.0 * kDelta * kDelta) + 4.0 / 29.0;
}
double lab_f_inv(double f) { return f > kDelta ? f * f * f : 3.0 * kDelta * kDelta * (f - 4.0 / 29.0); }

double deg(double rad) { return rad * (180.0 / M_PI); }
double rad(double deg_) { return deg_ * (M_PI / 180.0); }
}  // namespace

glm::dvec3 xyz_from_linear_srgb(const glm::dvec3& c) {
    return {0.4124564 * c.r + 0.3575761 * c.g + 0.1804375 * c.b,
            0.2126729 * c.r + 0.7151522 * c.g + 0.0721750 * c.b,
            0.0193339 * c.r + 0.1191920 * c.g + 0.9503041 * c.b};
}

glm::dvec3 linear_srgb_from_xyz(const glm::dvec3& x) {
    return {3.2404542 * x.x - 1.5371385 * x.y - 0.4985314 * x.z,
            -0.9692660 * x.x + 1.8760108 * x.y + 0.0415560 * x.z,
            0.0556434 * x.x - 0.2040259 * x.y + 1.0572252 * x.z};
}

glm::dvec3 lab_from_xyz(const glm::dvec3& xyz) {
    const double fx = lab_f(xyz.x / kXn), fy = lab_f(xyz.y / kYn), fz = lab_f(xyz.z / kZn);
    return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

glm::dvec3 xyz_from_lab(const glm::dvec3& lab) {
    const double fy = (lab.x + 16.0) / 116.0;
    const double fx = fy + lab.y / 500.0;
    const double fz = fy - lab.z / 200.0;
    return {kXn * lab_f_inv(fx), kYn * lab_f_inv(fy), kZn * lab_f_inv(fz)};
}

glm::dvec3 lab_from_linear_srgb(const glm::dvec3& rgb) { return lab_from_xyz(xyz_from_linear_srgb(rgb)); }

double delta_e76(const glm::dvec3& a, const glm::dvec3& b) { return glm::length(a - b); }

double delta_e2000(const glm::dvec3& lab1, const glm::dvec3& lab2) {
    const double L1 = lab1.x, a1 = lab1.y, b1 = lab1.z;
    const double L2 = lab2.x, a2 = lab2.y, b2 = lab2.z;
    // (2)-(6): a' with the G correction for neutral colours, C', h' in degrees [0, 360).
    const double Cab = 0.5 * (std::hypot(a1, b1) + std::hypot(a2, b2));
    const double Cab7 = std::pow(Cab, 7.0);
    const double G = 0.5 * (1.0 - std::sqrt(Cab7 / (Cab7 + std::pow(25.0, 7.0))));
    const double ap1 = (1.0 + G) * a1, ap2 = (1.0 + G) * a2;
    const double Cp1 = std::hypot(ap1, b1), Cp2 = std::hypot(ap2, b2);
    auto hue = [](double b, double ap) {
        if (b == 0.0 && ap == 0.0) return 0.0;   // (7): h' = 0 when a' = b = 0
        const double h = deg(std::atan2(b, ap));
        return h < 0.0 ? h + 360.0 : h;
    };
    const double hp1 = hue(b1, ap1), hp2 = hue(b2, ap2);
    // (8)-(10): differences.
    const double dLp = L2 - L1;
    const double dCp = Cp2 - Cp1;
    double dhp = 0.0;
    if (Cp1 * Cp2 != 0.0) {
        dhp = hp2 - hp1;
        if (dhp > 180.0) dhp -= 360.0;
        else if (dhp < -180.0) dhp += 360.0;
    }
    const double dHp = 2.0 * std::sqrt(Cp1 * Cp2) * std::sin(rad(dhp / 2.0));
    // (12)-(22): weighting functions.
    const double Lbp = 0.5 * (L1 + L2);
    const double Cbp = 0.5 * (Cp1 + Cp2);
    double hbp = hp1 + hp2;
    if (Cp1 * Cp2 != 0.0) {
        if (std::abs(hp1 - hp2) <= 180.0) hbp *= 0.5;
        else hbp = (hbp < 360.0) ? 0.5 * (hbp + 360.0) : 0.5 * (hbp - 360.0);
    }
    const double T = 1.0 - 0.17 * std::cos(rad(hbp - 30.0)) + 0.24 * std::cos(rad(2.0 * hbp)) +
                     0.32 * std::cos(rad(3.0 * hbp + 6.0)) - 0.20 * std::cos(rad(4.0 * hbp - 63.0));
    const double dtheta = 30.0 * std::exp(-((hbp - 275.0) / 25.0) * ((hbp - 275.0) / 25.0));
    const double Cbp7 = std::pow(Cbp, 7.0);
    const double RC = 2.0 * std::sqrt(Cbp7 / (Cbp7 + std::pow(25.0, 7.0)));
    const double L50 = (Lbp - 50.0) * (Lbp - 50.0);
    const double SL = 1.0 + 0.015 * L50 / std::sqrt(20.0 + L50);
    const double SC = 1.0 + 0.045 * Cbp;
    const double SH = 1.0 + 0.015 * Cbp * T;
    const double RT = -std::sin(rad(2.0 * dtheta)) * RC;
    const double tL = dLp / SL, tC = dCp / SC, tH = dHp / SH;
    return std::sqrt(tL * tL + tC * tC + tH * tH + RT * tC * tH);
}

}  // namespace shadelab
