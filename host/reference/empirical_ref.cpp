// The empirical family's references in double (ISIS3's MinnaertEmpirical and LunarLambertEmpirical), written from
// the laws (Minnaert 1941; McEwen 1991, Icarus 92:298) and ISIS's interpolation, the natural cubic spline of each
// table evaluated in double (host/core/spline.hpp, the same spline ISIS's path host/photometry/isis.cpp uses; the
// kernel reads float cubics per segment packed by host/models/empirical.cpp and finds the segment itself). Shares
// no code with kernels/models/empirical.cl. Registered at vectors and at photometric angles, like the Lunar-Lambert
// family (reference/lunar_lambert_ref.cpp).
#include <algorithm>
#include <cmath>

#include "core/spline.hpp"
#include "reference/reference.hpp"

namespace shadelab::ref {

namespace {

// The table `name` of phase, by ISIS's spline (continued beyond the table by the end cubics).
double spline_at(const Material& m, const char* name, double g_deg) {
    return NaturalSpline(m.tables.at("phase_list"), m.tables.at(name))(g_deg);
}

// The phase curve B(g), held at 0 where the continued spline falls below it (ISIS does not hold it).
double brightness_at(const Material& m, double g_deg) { return std::max(spline_at(m, "phase_curve_list", g_deg), 0.0); }

// Minnaert's 1941 law mu0 (mu0 mu)^(K - 1) with the catalogue's limb guard: for K < 1 each cosine below
// eps = 1e-3 is held at eps in the power and faded linearly to 0 (docs/models/minnaert.md).
double minnaert_guarded(double mu0, double mu, double K) {
    const double eps = K < 1.0 ? 1e-3 : 0.0;
    auto c = [&](double x) { return x >= eps ? std::pow(x, K - 1.0) : std::pow(eps, K - 1.0) * x / eps; };
    return mu0 * c(mu0) * c(mu);
}

// mu0, mu > 0 (planetary_value returns 0 elsewhere before calling these).
double minnaert_empirical_law(const Material& m, const PhotometricAngles& a) {
    return brightness_at(m, a.g_deg) * minnaert_guarded(a.mu0, a.mu, spline_at(m, "k_list", a.g_deg));
}

double lunar_lambert_empirical_law(const Material& m, const PhotometricAngles& a) {
    const double L = spline_at(m, "l_list", a.g_deg);
    return brightness_at(m, a.g_deg) * a.mu0 * ((1.0 - L) + 2.0 * L / (a.mu0 + a.mu));
}

}  // namespace

void add_empirical_references(Table& t) {
    t.angles["minnaert_empirical"] = minnaert_empirical_law;
    t.angles["lunar_lambert_empirical"] = lunar_lambert_empirical_law;
    for (const char* name : {"minnaert_empirical", "lunar_lambert_empirical"})
        t[name] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
            return m.albedo * planetary_value(m, angles_from_vectors(N, L, V));
        };
}

}  // namespace shadelab::ref
