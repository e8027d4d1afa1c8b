#include "moon/photometry.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"

namespace shadelab::moon {

namespace {
std::string num(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

// acos of a cosine that rounding may have pushed a hair outside [-1, 1].
double acos_deg(double c) { return std::acos(std::clamp(c, -1.0, 1.0)) / kDeg; }
}  // namespace

SunGeometry sun_geometry(double phase_deg, double pa_deg) {
    if (!std::isfinite(phase_deg) || phase_deg < 0.0 || phase_deg > 180.0)
        throw Error("phase angle " + num(phase_deg) + " deg is out of range: it must be in [0, 180] degrees");
    if (!std::isfinite(pa_deg)) throw Error("position angle " + num(pa_deg) + " is not a finite number of degrees");
    SunGeometry s;
    s.phase_deg = phase_deg;
    s.pa_deg = pa_deg;
    const double a = phase_deg * kDeg, p = pa_deg * kDeg;
    s.V = {0.0, 0.0, 1.0};
    s.u = {-std::sin(p), std::cos(p), 0.0};
    s.w = glm::cross(s.V, s.u);
    s.L = std::cos(a) * s.V + std::sin(a) * s.u;
    return s;
}

PhotometricAngles photometric_angles(const glm::dvec3& N, const SunGeometry& sun) {
    PhotometricAngles g;
    g.mu0 = glm::dot(N, sun.L);
    g.mu = glm::dot(N, sun.V);
    g.i_deg = acos_deg(g.mu0);
    g.e_deg = acos_deg(g.mu);
    g.g_deg = acos_deg(glm::dot(sun.L, sun.V));
    g.lambda_deg = std::atan2(glm::dot(N, sun.u), g.mu) / kDeg;
    g.beta_deg = std::asin(std::clamp(glm::dot(N, sun.w), -1.0, 1.0)) / kDeg;
    return g;
}

glm::dvec3 normal_at(double lambda, double beta, const SunGeometry& sun) {
    const double cb = std::cos(beta);
    return cb * std::sin(lambda) * sun.u + std::sin(beta) * sun.w + cb * std::cos(lambda) * sun.V;
}

double minnaert(double mu0, double mu, double k, double B0) {
    if (!(mu0 > 0.0) || !(mu > 0.0)) return 0.0;
    // mu^(k-1) diverges at the limb for k < 1: the floor keeps it finite (see kMuFloor).
    return B0 * std::pow(mu0, k) * std::pow(std::max(mu, kMuFloor), k - 1.0);
}

double lambert(double mu0, double B0) { return mu0 > 0.0 ? B0 * mu0 : 0.0; }

double lommel_seeliger(double mu0, double mu, double B0) {
    if (!(mu0 > 0.0) || !(mu > 0.0)) return 0.0;
    return B0 * mu0 / (mu0 + mu);
}

double lunar_lambert(double mu0, double mu, double L, double B0) {
    if (!(mu0 > 0.0) || !(mu > 0.0)) return 0.0;
    return B0 * mu0 * ((1.0 - L) + 2.0 * L / (mu0 + mu));
}

double PhotometricModel::value(const glm::dvec3& N, const SunGeometry& sun) const {
    const double mu0 = glm::dot(N, sun.L), mu = glm::dot(N, sun.V);
    if (kind == "minnaert") return minnaert(mu0, mu, k, B0);
    if (kind == "lambert") return mu > 0.0 ? lambert(mu0, B0) : 0.0;
    if (kind == "lommel_seeliger") return lommel_seeliger(mu0, mu, B0);
    if (kind == "lunar_lambert") return lunar_lambert(mu0, mu, lunar_l, B0);
    if (kind == "catalogue") {
        if (!(mu > 0.0)) return 0.0;   // the far side is not seen
        const glm::dvec3 v = ref::eval_material(N, sun.L, sun.V, N, material);
        const double grey = (v.x + v.y + v.z) / 3.0;
        // A model's reference may be unbounded at the limb (Minnaert 1941 with k < 1 at mu -> 0); a curve
        // never shows Inf: such a point reads 0, like the kernels' sl_finite_or_zero.
        return std::isfinite(grey) ? grey : 0.0;
    }
    throw Error("internal: unknown photometric model kind '" + kind + "'");
}

std::string PhotometricModel::describe() const {
    if (kind == "minnaert") return "Minnaert 1941 k=" + num(k) + " B0=" + num(B0);
    if (kind == "lambert") return "Lambert B0=" + num(B0);
    if (kind == "lommel_seeliger") return "Lommel-Seeliger B0=" + num(B0);
    if (kind == "lunar_lambert") return "Lunar-Lambert L=" + num(lunar_l) + " B0=" + num(B0);
    std::string s = material.model;
    for (const auto& [name, v] : material.params) s += " " + name + "=" + num(v);
    return s + " albedo=" + num(material.albedo.y);
}

PhotometricModel make_photometric_model(const std::string& name, double k, double lunar_l, double B0,
                                        const std::map<std::string, double>& params) {
    if (!std::isfinite(B0) || B0 < 0.0) throw Error("albedo/B0 " + num(B0) + " must be finite and >= 0");
    PhotometricModel m;
    m.B0 = B0;
    m.k = k;
    m.lunar_l = lunar_l;
    std::string n = name;
    std::replace(n.begin(), n.end(), '-', '_');
    const bool closed = n == "minnaert" || n == "lambert" || n == "lommel_seeliger" || n == "lunar_lambert";
    if (closed) {
        if (!params.empty())
            throw Error("model '" + name + "' is a closed form: give its k with --k and L with --lunar-l, not -p");
        if (n == "minnaert" && (!std::isfinite(k) || k < 0.0 || k > 4.0))
            throw Error("Minnaert k " + num(k) + " is out of range: use 0 <= k <= 4 (the Moon: about 0.5 to 0.9)");
        if (n == "lunar_lambert" && (!std::isfinite(lunar_l) || lunar_l < 0.0 || lunar_l > 1.0))
            throw Error("Lunar-Lambert L " + num(lunar_l) + " is out of range: use 0 <= L <= 1");
        m.kind = n;
        return m;
    }
    m.kind = "catalogue";
    Material mat;
    mat.model = name;
    mat.params = params;
    mat.albedo = glm::dvec3(B0);
    m.material = resolve_material(mat, "--model " + name);
    ref::reference_for(name);   // throws when the model has no double reference
    return m;
}

MinnaertEquivalent minnaert_equivalent(const Material& m) {
    MinnaertEquivalent e;
    const double a = m.albedo.y;
    auto param = [&](const char* name) { return m.params.at(name); };
    if (m.model == "minnaert_1941") {
        e = {true, param("k"), a, "everywhere"};
    } else if (m.model == "minnaert_normalized") {
        e = {true, param("k"), a * (param("k") + 1.0) / 2.0, "everywhere"};
    } else if (m.model == "minnaert_unity") {
        e = {true, param("k") + 1.0, a, param("k") >= 0.0 ? "everywhere" : "where mu0^(k+1) mu^k <= 1 (unclipped)"};
    } else if (m.model == "minnaert_blender") {
        if (param("darkness") <= 1.0)
            e = {true, param("darkness"), a, param("darkness") == 1.0 ? "everywhere" : "where mu mu0 >= 0.1"};
        else
            e = {false, 0.0, 0.0, "darkness > 1 is Blender's 'Nvidia' form mu0 (1.001 - mu)^(d-1), not a 1941 law"};
    } else if (m.model == "lambert") {
        e = {true, 1.0, a, "everywhere"};
    } else if (m.model == "minnaert_b") {
        e = {false, 0.0, 0.0, "MinnaertB mu0^(1+k) (1 - mu)^(1-k) is not a 1941 law"};
    } else {
        e = {false, 0.0, 0.0, "'" + m.model + "' is not in the Minnaert family"};
    }
    return e;
}

double minnaert_variant_value(const Material& m, double mu0, double mu) {
    if (!(mu0 > 0.0) || !(mu > 0.0)) return 0.0;
    const double a = m.albedo.y;
    if (m.model == "minnaert_1941") return minnaert(mu0, mu, m.params.at("k"), a);
    if (m.model == "minnaert_normalized") return minnaert(mu0, mu, m.params.at("k"), a * (m.params.at("k") + 1.0) / 2.0);
    if (m.model == "minnaert_unity") return a * std::min(1.0, minnaert(mu0, mu, m.params.at("k") + 1.0, 1.0));
    if (m.model == "minnaert_blender") {
        const double d = m.params.at("darkness");
        if (d <= 1.0) return a * mu0 * std::pow(std::max(mu * mu0, 0.1), d - 1.0);
        return a * mu0 * std::pow(1.001 - mu, d - 1.0);
    }
    if (m.model == "minnaert_b") {
        const double k = m.params.at("k");
        return a * std::pow(mu0, 1.0 + k) * std::pow(1.0 - mu, 1.0 - k);
    }
    if (m.model == "lambert") return lambert(mu0, a);
    throw Error("model '" + m.model + "' has no closed form in mu0, mu here (the Minnaert family and lambert do)");
}

namespace {
CurvePoint curve_point(const PhotometricModel& m, const SunGeometry& sun, const glm::dvec3& N, double s) {
    CurvePoint c;
    c.s = s;
    const PhotometricAngles a = photometric_angles(N, sun);
    c.lambda_deg = a.lambda_deg;
    c.beta_deg = a.beta_deg;
    c.mu0 = a.mu0;
    c.mu = a.mu;
    c.value = m.value(N, sun);
    return c;
}

void check_count(int n) {
    if (n < 2 || n > 1000000) throw Error("curve sample count " + std::to_string(n) + " must be in [2, 1000000]");
}
}  // namespace

std::vector<CurvePoint> equator_curve(const PhotometricModel& m, const SunGeometry& sun, int n) {
    check_count(n);
    std::vector<CurvePoint> out;
    out.reserve(std::size_t(n));
    for (int j = 0; j < n; ++j) {
        const double s = -1.0 + (j + 0.5) * 2.0 / n;
        // On the equator (beta = 0) the point at image distance s from the centre has sin(lambda) = s.
        const glm::dvec3 N = s * sun.u + std::sqrt(std::max(0.0, 1.0 - s * s)) * sun.V;
        out.push_back(curve_point(m, sun, N, s));
    }
    return out;
}

std::vector<CurvePoint> across_curve(const PhotometricModel& m, const SunGeometry& sun, double offset, int n) {
    check_count(n);
    if (!std::isfinite(offset) || std::abs(offset) >= 1.0)
        throw Error("across-profile offset " + num(offset) + " must be strictly between -1 and 1 disc radii");
    const double half = std::sqrt(1.0 - offset * offset);   // half-length of the chord
    std::vector<CurvePoint> out;
    out.reserve(std::size_t(n));
    for (int j = 0; j < n; ++j) {
        const double s = half * (-1.0 + (j + 0.5) * 2.0 / n);
        const double z = std::sqrt(std::max(0.0, 1.0 - offset * offset - s * s));
        out.push_back(curve_point(m, sun, offset * sun.u + s * sun.w + z * sun.V, s));
    }
    return out;
}

}  // namespace shadelab::moon
