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

// The law names moon takes, each a catalogue model (the catalogue's reference is the one definition).
const std::vector<NamedLaw>& named_laws() {
    static const std::vector<NamedLaw> laws = {
        {"minnaert", "minnaert_1941", "k", "Minnaert 1941", 1.0},
        {"lambert", "lambert", "", "Lambert", 1.0},
        // the catalogue's (ISIS's) Lommel-Seeliger is 2 mu0 / (mu0 + mu): moon's classical form is half of it
        {"lommel_seeliger", "lommel_seeliger", "", "Lommel-Seeliger", 0.5},
        {"lunar_lambert", "lunar_lambert", "l", "Lunar-Lambert", 1.0},
    };
    return laws;
}

const NamedLaw* named_law(const std::string& typed) {
    std::string n = typed;
    std::replace(n.begin(), n.end(), '-', '_');
    for (const NamedLaw& l : named_laws())
        if (l.name == n) return &l;
    return nullptr;
}

double PhotometricModel::value(const glm::dvec3& N, const SunGeometry& sun) const {
    if (!(glm::dot(N, sun.V) > 0.0)) return 0.0;   // the far side is not seen
    const glm::dvec3 v = ref::eval_material(N, sun.L, sun.V, N, material);
    const double grey = (v.x + v.y + v.z) / 3.0;
    // A model's reference may be unbounded at the limb (a Minnaert shader form with k < 0 at mu -> 0); a curve
    // never shows Inf: such a point reads 0, like the kernels' sl_finite_or_zero.
    return std::isfinite(grey) ? grey : 0.0;
}

std::string PhotometricModel::describe() const {
    if (const NamedLaw* l = named_law(kind)) {
        std::string s = l->title;
        if (l->param == "k") s += " k=" + num(k);
        if (l->param == "l") s += " L=" + num(lunar_l);
        return s + " B0=" + num(B0);
    }
    std::string s = material.model;
    for (const auto& [name, v] : material.params) s += " " + name + "=" + num(v);
    return s + " albedo=" + num(material.albedo.y);
}

namespace {
// A named law's parameter (k or L) within its catalogue model's range, else one line naming both.
void check_law_param(const NamedLaw& l, double v) {
    if (l.param.empty()) return;
    for (const ParamSpec& p : find_model(l.model).params) {
        if (p.name != l.param) continue;
        if (std::isfinite(v) && v >= p.lo && v <= p.hi) return;
        const std::string what = l.param == "k" ? "Minnaert k " : "Lunar-Lambert L ";
        const std::string opt = l.param == "k" ? "k" : "L";
        throw Error(what + num(v) + " is out of range: use " + num(p.lo) + " <= " + opt + " <= " + num(p.hi) +
                    " (the catalogue's " + l.model + (l.param == "k" ? "; the Moon: about 0.5 to 0.9)" : ")"));
    }
}

// The catalogue material of a named law: its model, its parameter, grey albedo B0 times the law's scale.
Material law_material(const NamedLaw& l, double k, double lunar_l, double B0) {
    Material mat;
    mat.model = l.model;
    if (!l.param.empty()) mat.params[l.param] = l.param == "k" ? k : lunar_l;
    mat.albedo = glm::dvec3(B0 * l.b0_scale);
    return resolve_material(mat, "--model " + l.name);
}
}  // namespace

PhotometricModel make_photometric_model(const std::string& name, double k, double lunar_l, double B0,
                                        const std::map<std::string, double>& params) {
    if (!std::isfinite(B0) || B0 < 0.0) throw Error("albedo/B0 " + num(B0) + " must be finite and >= 0");
    PhotometricModel m;
    m.B0 = B0;
    m.k = k;
    m.lunar_l = lunar_l;
    if (const NamedLaw* l = named_law(name)) {
        if (!params.empty())
            throw Error("model '" + name + "' is a named law: give its k with --k and L with --lunar-l, not -p");
        check_law_param(*l, l->param == "k" ? k : lunar_l);
        m.kind = l->name;
        m.material = law_material(*l, k, lunar_l, B0);
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
