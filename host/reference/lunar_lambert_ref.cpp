// Lommel-Seeliger and Lunar-Lambert references in double, written from the papers' formulas (Seeliger 1888;
// McEwen 1991, Icarus 92:298) in ISIS3's normalisation, sharing no code with kernels/models/lunar_lambert.cl or
// host/models/lunar_lambert.cpp. The term functions carry the kernel's names. Both laws are registered twice: at
// vectors (the catalogue's reference, through the photometric angles of N, L, V) and at photometric angles (what
// planetary_value and the ISIS path, host/photometry/, evaluate).
#include "reference/reference.hpp"

namespace shadelab::ref {

namespace {

// 2 mu0 / (mu0 + mu): Lommel-Seeliger as ISIS returns it (twice the classical mu0 / (mu0 + mu), so that it is 1
// at i = e = 0 like Lambert).
double Pho_LommelSeeliger(double mu0, double mu) { return 2.0 * mu0 / (mu0 + mu); }

// mu0 ((1 - L) + 2 L / (mu0 + mu)): the Lambert and Lommel-Seeliger laws weighted by L.
double Pho_LunarLambert(double mu0, double mu, double L) { return mu0 * ((1.0 - L) + 2.0 * L / (mu0 + mu)); }

// The laws at photometric angles with mu0, mu > 0 (planetary_value returns 0 elsewhere before calling these).
double lommel_seeliger_law(const Material&, const PhotometricAngles& a) { return Pho_LommelSeeliger(a.mu0, a.mu); }
double lunar_lambert_law(const Material& m, const PhotometricAngles& a) {
    return Pho_LunarLambert(a.mu0, a.mu, m.params.at("l"));
}

}  // namespace

void add_lunar_lambert_references(Table& t) {
    t.angles["lommel_seeliger"] = lommel_seeliger_law;
    t.angles["lunar_lambert"] = lunar_lambert_law;
    for (const char* name : {"lommel_seeliger", "lunar_lambert"})
        t[name] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3&, const Material& m) {
            return m.albedo * planetary_value(m, angles_from_vectors(N, L, V));
        };
}

}  // namespace shadelab::ref
