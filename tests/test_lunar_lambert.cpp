// The Lommel-Seeliger and Lunar-Lambert family (kernels/models/lunar_lambert.cl, host/models/lunar_lambert.cpp,
// host/reference/lunar_lambert_ref.cpp, docs/models/lunar_lambert.md). Layers: (1) ISIS3's published values at
// its standard geometries through both of the family's paths (the catalogue kernel at vectors and the kernel at
// photometric angles, kernels/photometry.cl), the degenerate ones included; (2) the kernel against the reference
// over the catalogue's vector sweep and over random (g, i, e) rows; (3) the identities L = 0 Lambert, L = 1
// Lommel-Seeliger, and reciprocity. The planetary tests (tests/test_planetary.cpp) sweep these two laws 1e7 rows
// deep among ISIS's other laws; tests/test_photometry.cpp reads them from ISIS's PVL files.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>

#include "photometry/isis.hpp"
#include "reference/planetary_ref.hpp"
#include "support.hpp"

using namespace shadelab;

namespace {

constexpr double kDeg = M_PI / 180.0;

// N = z, L at incidence i in the xz plane, V at emission e and azimuth psi from L's plane: a facet's geometry.
struct Facet { glm::dvec3 N, L, V; };
Facet facet(double i_deg, double e_deg, double psi_deg) {
    return {{0, 0, 1}, {std::sin(i_deg * kDeg), 0, std::cos(i_deg * kDeg)},
            {std::sin(e_deg * kDeg) * std::cos(psi_deg * kDeg), std::sin(e_deg * kDeg) * std::sin(psi_deg * kDeg),
             std::cos(e_deg * kDeg)}};
}

// The kernel at the given facets (the catalogue entry point, eval_directions), albedo 1: the red channel.
std::vector<double> kernel_at(const Material& m, const std::vector<Facet>& fs) {
    std::vector<float> N, L, V, P;
    for (const Facet& f : fs)
        for (int c = 0; c < 3; ++c) {
            N.push_back(float(f.N[c]));
            L.push_back(float(f.L[c]));
            V.push_back(float(f.V[c]));
            P.push_back(0.0f);
        }
    Shader shader(test::runtime());
    const auto out = shader.eval_directions(m, N, L, V, P);
    std::vector<double> r;
    for (std::size_t i = 0; i < fs.size(); ++i) r.push_back(out[3 * i]);
    return r;
}

}  // namespace

TEST_CASE("lommel_seeliger and lunar_lambert: ISIS3's published values, both kernel paths and the reference",
          "[lunar_lambert]") {
    // ISIS3's unit-test truth (LommelSeeliger.truth, LunarLambert.truth) at (g, i, e) = (0, 0, 0), (60, 45, 30),
    // (180, 90, 90): a facet with i = 45, e = 30 and phase 60 has azimuth psi = acos((cos 60 - cos 45 cos 30) /
    // (sin 45 sin 30)) = 151.4 deg.
    struct Truth { const char* model; double l; double g, i, e; double value; };
    const Truth truths[] = {
        {"lommel_seeliger", 0, 0, 0, 0, 1.0},        {"lommel_seeliger", 0, 60, 45, 30, 0.898979},
        {"lommel_seeliger", 0, 180, 90, 90, 0.0},    {"lunar_lambert", 1.0, 60, 45, 30, 0.898979},
        {"lunar_lambert", 0.0, 60, 45, 30, 0.707107}, {"lunar_lambert", 0.5, 60, 45, 30, 0.803043},
        {"lunar_lambert", 2.0, 60, 45, 30, 1.09085},  {"lunar_lambert", 0.5, 0, 0, 0, 1.0},
        {"lunar_lambert", 2.0, 180, 90, 90, 0.0},
    };
    for (const Truth& t : truths) {
        const std::map<std::string, double> p = t.model == std::string("lunar_lambert") ?
                                                    std::map<std::string, double>{{"l", t.l}} :
                                                    std::map<std::string, double>{};
        const Material m = test::material(t.model, p, glm::dvec3(1.0));
        INFO(t.model << " L " << t.l << " at (g, i, e) = (" << t.g << ", " << t.i << ", " << t.e << ")");
        const double ref = ref::planetary_value(m, ref::angles_from_degrees(t.g, t.i, t.e));
        CHECK(ref == Approx(t.value).margin(5e-7));   // ISIS prints 6 digits
        const auto pho = photometry::evaluate(test::runtime(), photometry::law_from_model(t.model, p),
                                              {{t.g, t.i, t.e}}, Precision::Precise, true);
        CHECK(pho[0] == Approx(t.value).margin(1e-6));
        const double cos_psi = (std::cos(t.g * kDeg) - std::cos(t.i * kDeg) * std::cos(t.e * kDeg)) /
                               std::max(std::sin(t.i * kDeg) * std::sin(t.e * kDeg), 1e-300);
        const double psi = std::sin(t.i * kDeg) * std::sin(t.e * kDeg) > 0 ? std::acos(std::clamp(cos_psi, -1.0, 1.0)) / kDeg : 0.0;
        if (t.i < 90 && t.e < 90) CHECK(kernel_at(m, {facet(t.i, t.e, psi)})[0] == Approx(t.value).margin(1e-6));
    }
}

TEST_CASE("lommel_seeliger and lunar_lambert: kernel within 2e-6 of the reference over the vector sweep and random "
          "(g, i, e) rows, no NaN/Inf", "[lunar_lambert][kernel]") {
    for (const auto& [model, p] : std::vector<std::pair<std::string, std::map<std::string, double>>>{
             {"lommel_seeliger", {}}, {"lunar_lambert", {{"l", 0.0}}}, {"lunar_lambert", {{"l", 0.3}}},
             {"lunar_lambert", {{"l", 1.0}}}, {"lunar_lambert", {{"l", 2.0}}}}) {
        const Material m = test::material(model, p);
        // Away from grazing, where both terms are well conditioned (L >= 0: no cancellation): 2e-6 relative.
        const auto vec = test::check_kernel_against_reference(m, [](const test::Compared& v) {
            return v.NoL() < 0.05 || v.NoV() < 0.05 ? test::kExempt : 2e-6 * std::abs(v.r);
        });
        test::expect_within(vec, 10001);   // more than 10,000 values compared
        std::size_t non_finite = 0;
        // Photometric angles: 20,000 random rows a facet can have, through kernels/photometry.cl.
        std::mt19937_64 gen(7);
        std::vector<photometry::Geometry> rows;
        for (int j = 0; j < 20000; ++j) {
            const double i = std::acos(test::unit_double(gen)) / kDeg, e = std::acos(test::unit_double(gen)) / kDeg;
            const double psi = 180.0 * test::unit_double(gen);
            const double cg = std::cos(i * kDeg) * std::cos(e * kDeg) + std::sin(i * kDeg) * std::sin(e * kDeg) * std::cos(psi * kDeg);
            rows.push_back({std::acos(std::clamp(cg, -1.0, 1.0)) / kDeg, i, e});
        }
        const auto pho = photometry::evaluate(test::runtime(), photometry::law_from_model(model, p), rows,
                                              Precision::Precise, true);
        double pho_max_rel = 0.0;
        for (std::size_t j = 0; j < rows.size(); ++j) {
            if (!std::isfinite(pho[j])) ++non_finite;
            const auto a = ref::angles_from_degrees(rows[j].phase, rows[j].incidence, rows[j].emission);
            if (a.mu0 < 0.05 || a.mu < 0.05) continue;
            const double r = ref::planetary_value(test::material(model, p, glm::dvec3(1.0)), a);
            pho_max_rel = std::max(pho_max_rel, std::abs(pho[j] - r) / std::abs(r));
        }
        INFO(model << " l " << (p.count("l") ? p.at("l") : 0.0) << ": photometric rows max rel " << pho_max_rel);
        std::cout << "lunar_lambert family: " << model << " l " << (p.count("l") ? p.at("l") : 0.0)
                  << ": kernel vs reference, vector sweep max rel " << vec.max_rel << ", photometric rows max rel "
                  << pho_max_rel << "\n";
        CHECK(non_finite == 0);
        CHECK(pho_max_rel <= 2e-6);
    }
}

TEST_CASE("lunar_lambert: L = 0 is Lambert, L = 1 is Lommel-Seeliger, and both laws are reciprocal (value / NoL symmetric)",
          "[lunar_lambert]") {
    std::mt19937_64 gen(11);
    const Material lam = test::material("lambert", {}, glm::dvec3(1.0));
    const Material ll0 = test::material("lunar_lambert", {{"l", 0.0}}, glm::dvec3(1.0));
    const Material ll1 = test::material("lunar_lambert", {{"l", 1.0}}, glm::dvec3(1.0));
    const Material ll03 = test::material("lunar_lambert", {{"l", 0.3}}, glm::dvec3(1.0));
    const Material ls = test::material("lommel_seeliger", {}, glm::dvec3(1.0));
    for (int j = 0; j < 20000; ++j) {
        const Facet f = facet(std::acos(test::unit_double(gen)) / kDeg, std::acos(test::unit_double(gen)) / kDeg,
                              360.0 * test::unit_double(gen));
        INFO("L " << f.L.x << " " << f.L.y << " " << f.L.z << ", V " << f.V.x << " " << f.V.y << " " << f.V.z);
        const double NoL = glm::dot(f.N, f.L), NoV = glm::dot(f.N, f.V);
        if (NoL < 1e-6 || NoV < 1e-6) continue;
        CHECK(ref::eval_material(f.N, f.L, f.V, {}, ll0).x == Approx(ref::eval_material(f.N, f.L, f.V, {}, lam).x).margin(1e-15));
        CHECK(ref::eval_material(f.N, f.L, f.V, {}, ll1).x == Approx(ref::eval_material(f.N, f.L, f.V, {}, ls).x).margin(1e-15));
        for (const Material* m : {&ls, &ll03}) {
            const double a = ref::eval_material(f.N, f.L, f.V, {}, *m).x / NoL, b = ref::eval_material(f.N, f.V, f.L, {}, *m).x / NoV;
            CHECK(a == Approx(b).epsilon(1e-12));
        }
    }
    CHECK(find_model("lommel_seeliger").reciprocal);
    CHECK(find_model("lunar_lambert").reciprocal);
}
