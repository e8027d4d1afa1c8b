// The moon tools (host/moon/, docs/moon.md): geometry conventions, analytic curves, rendered discs against the
// analytic curves (exact sphere normals and icosphere meshes), Minnaert fits, profiles, FITS, plots, bad input.
//
// Thresholds used throughout: "well inside the disc" means mu >= 0.05 and mu0 >= 0.05 (2.9 deg above the limb
// and the terminator). There a float kernel on float normals is within a few 1e-6 relative of the double law:
// the normal's rounding (~6e-8) moves mu by ~1e-7, and mu^(k-1) turns that into |k-1| 1e-7 / mu <= 2e-6.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <tuple>
#include <iostream>
#include <random>

#include "cl/runtime.hpp"
#include "core/csv.hpp"
#include "core/error.hpp"
#include "models/catalogue.hpp"
#include "moon/disc.hpp"
#include "moon/fit.hpp"
#include "image/fits.hpp"
#include "moon/photometry.hpp"
#include "moon/plot.hpp"
#include "plot/gnuplot.hpp"
#include "reference/reference.hpp"
#include "support.hpp"

using namespace shadelab;
using namespace shadelab::moon;
using shadelab::plot::find_gnuplot;
using shadelab::plot::run_gnuplot;
namespace fs = std::filesystem;

namespace {

Material material(const std::string& model, const std::map<std::string, double>& params, double albedo) {
    return test::material(model, params, glm::dvec3(albedo));
}

constexpr int kSize = 256;
const Disc kDisc{128.0, 128.0, 120.0};

Image render(const Material& m, double phase, double pa, int mesh_level = -1, double noise = 0.0,
             std::uint64_t seed = 1, DiscRenderReport* rep = nullptr, const Disc& d = kDisc, int size = kSize) {
    DiscRenderOptions o;
    o.width = o.height = size;
    o.disc = d;
    o.material = m;
    o.sun = sun_geometry(phase, pa);
    o.mesh_level = mesh_level;
    o.noise_sigma = noise;
    o.noise_seed = seed;
    return render_disc(test::runtime(), o, rep);
}

// Max relative error of the image against a closed form over pixels well inside the disc.
struct Err {
    double max_rel = 0.0;
    std::size_t n = 0;
    double at_mu = 0.0, at_mu0 = 0.0;
};
template <typename F>
Err image_vs(const Image& img, const SunGeometry& sun, F&& expect, double mu_min = 0.05, double mu0_min = 0.05,
             const Disc& d = kDisc) {
    Err e;
    for (const DiscPixel& p : disc_pixels(img, d, sun)) {
        if (p.a.mu < mu_min || p.a.mu0 < mu0_min) continue;
        const double v = expect(p.a.mu0, p.a.mu);
        if (!(v > 1e-6)) continue;
        const double rel = std::abs(p.I - v) / v;
        if (rel > e.max_rel) {
            e.max_rel = rel;
            e.at_mu = p.a.mu;
            e.at_mu0 = p.a.mu0;
        }
        ++e.n;
    }
    return e;
}

// The catalogue's reference of a Minnaert-family model at photometric cosines mu0, mu (N = +z, V in the xz plane,
// L at any azimuth: the family depends on N, L, V through NoL, NoV and |N - V| alone).
double reference_at(const Material& m, double mu0, double mu) {
    const glm::dvec3 N{0, 0, 1}, V{std::sqrt(std::max(0.0, 1.0 - mu * mu)), 0, mu};
    const glm::dvec3 L{0, std::sqrt(std::max(0.0, 1.0 - mu0 * mu0)), mu0};
    return ref::eval_material(N, L, V, N, m).y;
}

// Minnaert (1941), ApJ 93:403, as the paper writes it (no limb guard): B0 mu0^k mu^(k-1), 0 unlit or unseen.
double minnaert_1941_paper(double mu0, double mu, double k, double B0) {
    return mu0 > 0.0 && mu > 0.0 ? B0 * std::pow(mu0, k) * std::pow(mu, k - 1.0) : 0.0;
}

std::size_t non_finite(const Image& img) {
    std::size_t n = 0;
    for (float v : img.pixels) n += std::isfinite(v) ? 0 : 1;
    return n;
}

}  // namespace

// ------------------------------------------------------------------------------------------ conventions

TEST_CASE("moon geometry: sun direction, photometric frame and angles follow the documented conventions", "[moon]") {
    // pa 0: the sun is up the image (north); pa 90: left (east). Phase 0: L = V; phase 90: L in the image plane.
    const SunGeometry s0 = sun_geometry(0.0, 0.0);
    CHECK(s0.L.z == Approx(1.0));
    CHECK(s0.u.y == Approx(1.0));
    const SunGeometry s90 = sun_geometry(90.0, 90.0);
    CHECK(s90.L.x == Approx(-1.0));
    CHECK(std::abs(s90.L.z) < 1e-15);
    CHECK(s90.w.y == Approx(-1.0));   // w = V x u: 90 deg counter-clockwise from u (u left -> w down)
    CHECK(glm::dot(glm::cross(s90.u, s90.w), s90.V) == Approx(1.0));   // (u, w, V) right-handed

    // mu0 = cos(beta) cos(lambda - alpha), mu = cos(beta) cos(lambda), and the angles round trip.
    std::mt19937_64 g(7);
    for (int t = 0; t < 1000; ++t) {
        const double alpha = 180.0 * double(g() % 1000) / 1000.0, pa = 360.0 * double(g() % 1000) / 1000.0;
        const SunGeometry s = sun_geometry(alpha, pa);
        const double lambda = (double(g() % 1000) / 1000.0 - 0.5) * kPi * 0.99;
        const double beta = (double(g() % 1000) / 1000.0 - 0.5) * kPi * 0.99;
        const glm::dvec3 N = normal_at(lambda, beta, s);
        const PhotometricAngles a = photometric_angles(N, s);
        INFO("alpha " << alpha << " pa " << pa << " lambda " << lambda << " beta " << beta);
        CHECK(a.mu0 == Approx(std::cos(beta) * std::cos(lambda - alpha * kDeg)).margin(1e-13));
        CHECK(a.mu == Approx(std::cos(beta) * std::cos(lambda)).margin(1e-13));
        CHECK(a.lambda_deg == Approx(lambda / kDeg).margin(1e-9));
        CHECK(a.beta_deg == Approx(beta / kDeg).margin(1e-9));
        CHECK(a.g_deg == Approx(alpha).margin(1e-6));
    }
}

TEST_CASE("moon curves: zero-phase law, flat disc at k = 0.5, Lambert at k = 1, lunar-like references", "[moon]") {
    const SunGeometry s0 = sun_geometry(0.0, 0.0);
    for (double k : {0.0, 0.3, 0.5, 0.7, 1.0, 1.5}) {
        const auto c = equator_curve(make_photometric_model("minnaert", k, 0, 0.8), s0, 201);
        double worst = 0.0;
        for (const CurvePoint& p : c) {
            const double mu = std::sqrt(1.0 - p.s * p.s);   // I(r) = B0 mu^(2k-1), mu = sqrt(1 - r^2 / R^2)
            const double expect = 0.8 * std::pow(mu, 2.0 * k - 1.0);
            REQUIRE(std::isfinite(p.value));
            worst = std::max(worst, std::abs(p.value - expect) / expect);
        }
        INFO("k " << k);
        CHECK(worst < 1e-13);
    }
    // k = 0.5 at zero phase: flat at B0 along both profiles.
    for (const auto& c : {equator_curve(make_photometric_model("minnaert", 0.5, 0, 0.3), s0, 101),
                          across_curve(make_photometric_model("minnaert", 0.5, 0, 0.3), s0, 0.4, 101)})
        for (const CurvePoint& p : c) CHECK(p.value == Approx(0.3).epsilon(1e-13));
    // k = 1 is Lambert at any phase; Lunar-Lambert L = 0 is Lambert and L = 1 twice Lommel-Seeliger;
    // Lommel-Seeliger is flat (B0/2) at zero phase.
    for (double phase : {0.0, 30.0, 60.0, 90.0, 150.0}) {
        const SunGeometry s = sun_geometry(phase, 10.0);
        const auto m1 = equator_curve(make_photometric_model("minnaert", 1.0, 0, 0.5), s, 301);
        const auto la = equator_curve(make_photometric_model("lambert", 0, 0, 0.5), s, 301);
        const auto ll0 = equator_curve(make_photometric_model("lunar_lambert", 0, 0.0, 0.5), s, 301);
        const auto ll1 = equator_curve(make_photometric_model("lunar-lambert", 0, 1.0, 0.5), s, 301);
        const auto ls = equator_curve(make_photometric_model("lommel-seeliger", 0, 0, 0.5), s, 301);
        for (std::size_t i = 0; i < m1.size(); ++i) {
            CHECK(m1[i].value == Approx(la[i].value).margin(1e-15));
            CHECK(ll0[i].value == Approx(la[i].value).margin(1e-15));
            CHECK(ll1[i].value == Approx(2.0 * ls[i].value).margin(1e-15));
            CHECK(la[i].value == Approx(0.5 * std::max(0.0, la[i].mu0)).margin(1e-15));
        }
    }
    for (const CurvePoint& p : equator_curve(make_photometric_model("lommel_seeliger", 0, 0, 0.5), s0, 101))
        CHECK(p.value == Approx(0.25).epsilon(1e-13));
    // At phase alpha the terminator on the equator is at s = -cos(alpha): dark beyond, lit inside.
    const SunGeometry s60 = sun_geometry(60.0, 0.0);
    for (const CurvePoint& p : equator_curve(make_photometric_model("minnaert", 0.7, 0, 1.0), s60, 400)) {
        if (p.s < -0.5 - 1e-9) CHECK(p.value == 0.0);
        if (p.s > -0.5 + 1e-9) CHECK(p.value > 0.0);
    }
}

TEST_CASE("moon's Minnaert equivalents: each variant's catalogue reference is the 1941 law with the k and B0 "
          "minnaert_equivalent states, where it says", "[moon]") {
    struct Case { const char* model; const char* param; std::vector<double> values; };
    const std::vector<Case> cases = {{"minnaert_1941", "k", {0.0, 0.3, 0.5, 1.0, 2.0}},
                                     {"minnaert_normalized", "k", {0.0, 0.3, 0.5, 1.0, 2.0}},
                                     {"minnaert_unity", "k", {-1.0, -0.5, 0.0, 0.5, 1.0}},
                                     {"minnaert_blender", "darkness", {0.0, 0.3, 0.5, 1.0, 1.5, 2.0}},
                                     {"minnaert_b", "k", {0.0, 0.3, 0.7, 1.0}}};
    std::mt19937_64 g(3);
    std::size_t total = 0;
    for (const Case& c : cases)
        for (double v : c.values) {
            const Material m = material(c.model, {{c.param, v}}, 0.7);
            const MinnaertEquivalent e = minnaert_equivalent(m);
            INFO(c.model << " " << c.param << " = " << v << ": " << e.where);
            if (!e.exists) continue;
            // where the mapping claims to hold and the limb guard (mu, mu0 < 1e-3) is not involved: 2000 random
            // cosines, and a grid
            double worst = 0.0;
            std::size_t compared = 0;
            auto check_at = [&](double mu0, double mu) {
                const double law = minnaert_1941_paper(mu0, mu, e.k, e.B0);
                if (std::string(c.model) == "minnaert_unity" && law > 0.7) return;   // clipped by the saturate
                if (std::string(c.model) == "minnaert_blender" && mu * mu0 < double(0.1f)) return;   // its clamp (float 0.1f)
                worst = std::max(worst, std::abs(reference_at(m, mu0, mu) - law) / law);
                ++compared;
            };
            for (int t = 0; t < 2000; ++t) check_at(1e-3 + (1.0 - 1e-3) * test::unit_double(g), 1e-3 + (1.0 - 1e-3) * test::unit_double(g));
            for (double mu0 : {0.35, 0.6, 0.9})
                for (double mu : {0.35, 0.6, 0.9}) check_at(mu0, mu);
            total += compared;   // (unity at k = -1 clips everywhere: its 1941 law 0.7 / mu is > 0.7)
            CHECK(worst < 1e-12);
        }
    CHECK(total > 20000);
    CHECK(minnaert_equivalent(material("minnaert_unity", {{"k", -0.3}}, 1.0)).k == Approx(0.7));
    CHECK(minnaert_equivalent(material("minnaert_blender", {{"darkness", 0.6}}, 1.0)).k == Approx(0.6));
    CHECK(minnaert_equivalent(material("minnaert_normalized", {{"k", 0.6}}, 1.0)).B0 == Approx(0.8));
    CHECK_FALSE(minnaert_equivalent(material("minnaert_b", {{"k", 0.6}}, 1.0)).exists);
}

TEST_CASE("moon's named laws are the catalogue's references - the Minnaert limb guard is the one difference from "
          "the paper's law, measured on the curves", "[moon]") {
    // Every named law's value is its catalogue model's double reference at the same N, L, V.
    std::mt19937_64 g(5);
    for (const auto& [name, k, l] : std::vector<std::tuple<std::string, double, double>>{
             {"minnaert", 0.7, 0.0}, {"minnaert", 0.3, 0.0}, {"lambert", 0.0, 0.0}, {"lommel_seeliger", 0.0, 0.0},
             {"lunar_lambert", 0.0, 0.6}, {"lunar-lambert", 0.0, -0.5}}) {
        const PhotometricModel pm = make_photometric_model(name, k, l, 0.4);
        const NamedLaw* law = named_law(name);
        REQUIRE(law != nullptr);
        CHECK(pm.material.model == law->model);
        for (int t = 0; t < 500; ++t) {
            const SunGeometry s = sun_geometry(179.0 * test::unit_double(g), 360.0 * test::unit_double(g));
            const glm::dvec3 N = glm::normalize(test::random_unit(g));
            const glm::dvec3 r = ref::eval_material(N, s.L, s.V, N, pm.material);
            const double want = glm::dot(N, s.V) > 0.0 ? (r.x + r.y + r.z) / 3.0 : 0.0;   // grey: the channels' mean
            INFO(name << " at N (" << N.x << ", " << N.y << ", " << N.z << ")");
            CHECK(pm.value(N, s) == want);
        }
    }
    // The paper's forms written out: Lommel-Seeliger B0 mu0 / (mu0 + mu), Lunar-Lambert, Lambert, Minnaert (guard
    // aside), at cosines >= 1e-3.
    const SunGeometry s40 = sun_geometry(40.0, 0.0);
    for (const CurvePoint& p : equator_curve(make_photometric_model("lommel_seeliger", 0, 0, 0.5), s40, 1001))
        if (p.mu0 > 0.0) CHECK(p.value == Approx(0.5 * p.mu0 / (p.mu0 + p.mu)).epsilon(1e-13));
    for (const CurvePoint& p : equator_curve(make_photometric_model("lunar_lambert", 0, 0.6, 0.5), s40, 1001))
        if (p.mu0 > 0.0) CHECK(p.value == Approx(0.5 * p.mu0 * (0.4 + 1.2 / (p.mu0 + p.mu))).epsilon(1e-13));
    // The limb guard: for k < 1 the catalogue's Minnaert holds each cosine's power below 1e-3, fades it to 0, and
    // the paper's law does not. Measured along the equator (1e6 samples, the finest moon curve takes) at phases
    // 0-150 and k = 0.3, 0.5, 0.7, 0.9 (and k = 1, 1.5, where there is no guard): which points change, by how much.
    std::cout << "moon minnaert vs the paper's law (no guard), equator, 1e6 samples:\n";
    for (double k : {0.3, 0.5, 0.7, 0.9, 1.0, 1.5})
        for (double phase : {0.0, 30.0, 60.0, 90.0, 150.0}) {
            const SunGeometry s = sun_geometry(phase, 0.0);
            std::size_t changed = 0, lit = 0, outside_band = 0;
            double max_abs = 0.0, max_rel = 0.0, last_s = -2.0;
            for (const CurvePoint& p : equator_curve(make_photometric_model("minnaert", k, 0, 1.0), s, 1000000)) {
                const double paper = minnaert_1941_paper(p.mu0, p.mu, k, 1.0);
                lit += paper > 0.0 ? 1 : 0;
                if (p.value == paper || std::abs(p.value - paper) <= 1e-15 * paper) continue;
                ++changed;
                if (p.mu0 >= 1e-3 && p.mu >= 1e-3) ++outside_band;
                max_abs = std::max(max_abs, std::abs(p.value - paper));
                max_rel = std::max(max_rel, std::abs(p.value - paper) / paper);
                last_s = p.s;
            }
            std::cout << "  k " << k << " phase " << std::setw(3) << phase << ": " << changed << " of " << lit
                      << " lit points changed, max abs " << max_abs << ", max rel " << max_rel << "\n";
            INFO("k " << k << " phase " << phase << " last changed s " << last_s);
            CHECK(outside_band == 0);                  // only where a cosine is below 1e-3
            if (k >= 1.0) CHECK(changed == 0);         // no guard for k >= 1
            // k < 1 away from zero phase: the terminator's band (the limb's samples never reach mu < 1e-3 here)
            if (k < 1.0 && phase > 0.0) CHECK(changed > 0);
        }
}

// ------------------------------------------------------------------------------------------ rendered discs

TEST_CASE("moon rendered discs with exact sphere normals match the analytic curves (every Minnaert variant)",
          "[moon][kernel]") {
    struct Case { const char* model; const char* param; std::vector<double> values; };
    // k < 0.5, 0.5, 1 (and around) in each variant's own parameter: unity's k = k_1941 - 1.
    const std::vector<Case> cases = {{"minnaert_1941", "k", {0.2, 0.5, 0.7, 1.0}},
                                     {"minnaert_normalized", "k", {0.2, 0.5, 0.7, 1.0}},
                                     {"minnaert_unity", "k", {-0.8, -0.5, -0.3, 0.0}},
                                     {"minnaert_blender", "darkness", {0.2, 0.5, 1.0, 1.5}},
                                     {"minnaert_b", "k", {0.2, 0.5, 0.7, 1.0}}};
    std::cout << "moon: analytic-normal discs " << kSize << " px, radius " << kDisc.radius
              << " px; max relative error over mu, mu0 >= 0.05\n";
    double overall = 0.0;
    for (const Case& c : cases)
        for (double v : c.values) {
            const Material m = material(c.model, {{c.param, v}}, 0.8);
            std::cout << "  " << std::setw(20) << std::left << c.model << c.param << " = " << std::setw(5) << v;
            for (double phase : {0.0, 30.0, 60.0, 90.0}) {
                const SunGeometry sun = sun_geometry(phase, 25.0);
                const Image img = render(m, phase, 25.0);
                REQUIRE(non_finite(img) == 0);
                const Err e = image_vs(img, sun, [&](double mu0, double mu) { return reference_at(m, mu0, mu); });
                std::cout << "  phase " << std::setw(2) << phase << ": " << std::setw(9) << std::setprecision(3)
                          << e.max_rel;
                INFO(c.model << " " << c.param << " = " << v << " phase " << phase << ": max rel " << e.max_rel
                             << " at mu " << e.at_mu << " mu0 " << e.at_mu0 << " over " << e.n << " pixels");
                CHECK(e.n > 5000);
                CHECK(e.max_rel < 3e-5);
                overall = std::max(overall, e.max_rel);
            }
            std::cout << std::setprecision(6) << "\n";
        }
    std::cout << "  worst of all: " << overall << "\n";
}

TEST_CASE("moon discs: k = 0.5 at zero phase is flat, k = 1 is Lambert, Unity and Blender k map onto the 1941 k",
          "[moon][kernel]") {
    const SunGeometry s0 = sun_geometry(0.0, 0.0);
    // Flat disc: max/min - 1 over the disc (mu >= 0.05).
    for (const Material& m : {material("minnaert_1941", {{"k", 0.5}}, 0.6), material("minnaert_normalized", {{"k", 0.5}}, 0.6),
                              material("minnaert_unity", {{"k", -0.5}}, 0.6)}) {
        const Image img = render(m, 0.0, 0.0);
        double lo = 1e9, hi = 0.0;
        for (const DiscPixel& p : disc_pixels(img, kDisc, s0))
            if (p.a.mu >= 0.05) {
                lo = std::min(lo, p.I);
                hi = std::max(hi, p.I);
            }
        INFO(m.model << ": min " << lo << " max " << hi);
        CHECK(hi / lo - 1.0 < 2e-5);
        std::cout << "moon: " << m.model << " k=0.5 (1941) at phase 0: max/min - 1 = " << hi / lo - 1.0 << "\n";
    }
    // Pixel by pixel against the lambert kernel and against the 1941 kernel with the mapped k.
    for (double phase : {0.0, 40.0, 80.0}) {
        const SunGeometry s = sun_geometry(phase, 60.0);
        const Image lam = render(material("lambert", {}, 0.6), phase, 60.0);
        auto same = [&](const Image& a, const Image& b, double min_mumu0) {
            double worst = 0.0;
            const auto pa = disc_pixels(a, kDisc, s), pb = disc_pixels(b, kDisc, s);
            REQUIRE(pa.size() == pb.size());
            for (std::size_t i = 0; i < pa.size(); ++i) {
                if (pa[i].a.mu < 0.05 || pa[i].a.mu0 < 0.05 || pa[i].a.mu * pa[i].a.mu0 < min_mumu0) continue;
                worst = std::max(worst, std::abs(pa[i].I - pb[i].I) / pb[i].I);
            }
            return worst;
        };
        CHECK(same(render(material("minnaert_1941", {{"k", 1.0}}, 0.6), phase, 60.0), lam, 0.0) < 2e-6);
        CHECK(same(render(material("minnaert_unity", {{"k", 0.0}}, 0.6), phase, 60.0), lam, 0.0) < 2e-6);
        CHECK(same(render(material("minnaert_blender", {{"darkness", 1.0}}, 0.6), phase, 60.0), lam, 0.0) < 2e-6);
        CHECK(same(render(material("minnaert_normalized", {{"k", 1.0}}, 0.6), phase, 60.0), lam, 0.0) < 2e-6);
        for (double k : {0.6, 0.8, 1.3}) {
            const Image k1941 = render(material("minnaert_1941", {{"k", k}}, 0.6), phase, 60.0);
            // Unity's k = k_1941 - 1 (where its saturate does not clip: the 1941 law at albedo 1 stays <= 1 for
            // k_1941 >= 1; for k < 1 compare where mu0^k mu^(k-1) <= 1, i.e. away from the bright limb).
            const Image unity = render(material("minnaert_unity", {{"k", k - 1.0}}, 0.6), phase, 60.0);
            double worst_unity = 0.0;
            const auto pu = disc_pixels(unity, kDisc, s), p1 = disc_pixels(k1941, kDisc, s);
            for (std::size_t i = 0; i < pu.size(); ++i) {
                if (pu[i].a.mu < 0.05 || pu[i].a.mu0 < 0.05 || minnaert_1941_paper(pu[i].a.mu0, pu[i].a.mu, k, 1.0) > 0.999) continue;
                worst_unity = std::max(worst_unity, std::abs(pu[i].I - p1[i].I) / p1[i].I);
            }
            INFO("phase " << phase << " k_1941 " << k);
            CHECK(worst_unity < 1e-5);
            // Blender's darkness d = k_1941 for d <= 1, where mu mu0 >= 0.1 (its clamp).
            if (k <= 1.0) CHECK(same(render(material("minnaert_blender", {{"darkness", k}}, 0.6), phase, 60.0), k1941, 0.1) < 1e-5);
        }
    }
}

TEST_CASE("moon mesh discs: the error against the analytic curve shrinks with subdivision", "[moon][kernel][mesh]") {
    // An icosphere's facets lie inside the sphere. The pixel at disc position (X, Y) sees the facet point under
    // it, whose interpolated normal (vertex normals are the exact sphere normals) is normalize(facet point):
    // off the sphere's normal under that pixel by about h tan(e), where h <= a^2 / 6 is the facet's radial gap
    // for edge angle a (circumradius a / sqrt(3)). The value then moves by (|k-1| tan(e) + k tan(i)) times that
    // angle. Bound used, over mu >= m, mu0 >= m:  (|k-1| / m + k / m) (a^2 / 6) / m. It is a first-order
    // estimate, asserted where the normal error (a^2 / 6) / m is below m / 10 (levels >= 4 at m = 0.1); the
    // coarser levels only have to show the trend.
    const double k = 0.3, m_min = 0.1;
    const Material m = material("minnaert_1941", {{"k", k}}, 0.8);
    const SunGeometry sun = sun_geometry(30.0, 20.0);
    double previous = 1e9, bound = 0.0;
    std::cout << "moon: icosphere discs, minnaert_1941 k = 0.3, phase 30, max relative error over mu, mu0 >= 0.1\n";
    for (int level : {2, 3, 4, 5, 6}) {
        DiscRenderReport rep;
        const Image img = render(m, 30.0, 20.0, level, 0.0, 1, &rep);
        REQUIRE(non_finite(img) == 0);
        const Err e = image_vs(img, sun, [&](double mu0, double mu) { return reference_at(m, mu0, mu); }, m_min, m_min);
        const double a = 1.1071487 / std::pow(2.0, level);   // icosahedron edge angle / 2^level
        bound = (std::abs(k - 1.0) / m_min + k / m_min) * (a * a / 6.0) / m_min;
        std::cout << "  level " << level << " (" << rep.triangles << " triangles, edge " << std::setprecision(3) << a
                  << " rad): " << e.n << " pixels, max rel error " << e.max_rel << " (bound " << bound << ")"
                  << std::setprecision(6) << "\n";
        INFO("level " << level << " max rel " << e.max_rel << " at mu " << e.at_mu << " mu0 " << e.at_mu0 << ", previous "
                      << previous << ", bound " << bound);
        CHECK(e.n > 10000);
        CHECK(e.max_rel < previous);   // finer mesh, smaller error
        if (a * a / 6.0 / m_min < 0.1 * m_min) CHECK(e.max_rel < bound);
        previous = e.max_rel;
    }
    CHECK(previous < 5e-3);   // the finest level, 81920 triangles (bound 5.0e-3)
}

// ------------------------------------------------------------------------------------------ fits

TEST_CASE("moon fit recovers k and B0 from noise-free rendered discs to within 0.002", "[moon][kernel][fit]") {
    FitOptions o;   // mu, mu0 >= 0.2
    std::cout << "moon: Minnaert fit on noise-free discs (|k_fit - k|, |B0_fit/B0 - 1|)\n";
    double worst_k = 0.0, worst_b = 0.0;
    for (double k : {0.3, 0.5, 0.7, 1.0, 1.3})
        for (double phase : {0.0, 30.0, 60.0, 90.0}) {
            for (const char* model : {"minnaert_1941", "minnaert_normalized"}) {
                const Material m = material(model, {{"k", k}}, 0.12);
                const MinnaertEquivalent eq = minnaert_equivalent(m);
                const SunGeometry sun = sun_geometry(phase, 140.0);
                const Image img = render(m, phase, 140.0);
                const MinnaertFit f = fit_minnaert(disc_pixels(img, kDisc, sun), sun, o);
                INFO(model << " k " << k << " phase " << phase << ": k_fit " << f.k << " B0_fit " << f.B0);
                CHECK(std::abs(f.k - k) < 0.002);
                CHECK(std::abs(f.B0 / eq.B0 - 1.0) < 0.002);
                worst_k = std::max(worst_k, std::abs(f.k - k));
                worst_b = std::max(worst_b, std::abs(f.B0 / eq.B0 - 1.0));
            }
        }
    // The shader forms: Unity at zero phase (no clipping inside the thresholds for k_1941 >= 0.5) and Blender
    // inside its unclamped region (mu, mu0 >= 0.32 keeps mu mu0 >= 0.1).
    for (double k : {-0.5, -0.2, 0.0, 0.4}) {
        const SunGeometry sun = sun_geometry(0.0, 0.0);
        const MinnaertFit f = fit_minnaert(disc_pixels(render(material("minnaert_unity", {{"k", k}}, 0.3), 0.0, 0.0), kDisc, sun), sun, o);
        INFO("unity k " << k << ": k_fit " << f.k);
        CHECK(std::abs(f.k - (k + 1.0)) < 0.002);
        CHECK(std::abs(f.B0 / 0.3 - 1.0) < 0.002);
    }
    FitOptions ob;
    ob.mu_min = ob.mu0_min = 0.32;
    for (double d : {0.3, 0.6, 0.9}) {
        const SunGeometry sun = sun_geometry(30.0, 0.0);
        const MinnaertFit f = fit_minnaert(disc_pixels(render(material("minnaert_blender", {{"darkness", d}}, 0.3), 30.0, 0.0), kDisc, sun), sun, ob);
        INFO("blender d " << d << ": k_fit " << f.k);
        CHECK(std::abs(f.k - d) < 0.002);
    }
    std::cout << "  worst |dk| " << worst_k << ", worst |dB0/B0| " << worst_b << "\n";
}

TEST_CASE("moon fit under noise: k and B0 within their reported standard errors over several seeds",
          "[moon][kernel][fit]") {
    // Gaussian noise on a B0 = 0.12, k = 0.65 disc at phase 40, 8 fixed seeds; pull = (fit - truth) / reported
    // sigma. The fit on I itself is unbiased: every pull within 3. The Minnaert plot (least squares on
    // logarithms) is unbiased only to first order, E[ln(I + e)] = ln I - sigma^2 / (2 I^2): its bias grows like
    // sigma^2 and its standard error like sigma. At S/N ~ 120 on the centre (sigma 0.001) the bias is ~0.3
    // sigma (measured over 40 seeds: mean pull of k 0.28, rms 1.16), so its pulls are checked against 4 per
    // seed and their rms against 1.6; at sigma 0.004 the bias is ~1.4 sigma and the fit says so. (Over 200
    // seeds the fit on I at sigma 0.004 gave rms pulls 0.92 for k and 0.98 for B0: its sigmas are right.)
    const Material m = material("minnaert_1941", {{"k", 0.65}}, 0.12);
    const SunGeometry sun = sun_geometry(40.0, 300.0);
    struct Case { FitMethod method; double sigma; double per_seed; };
    for (const Case c : {Case{FitMethod::Intensity, 0.004, 3.0}, Case{FitMethod::MinnaertPlot, 0.001, 4.0},
                         Case{FitMethod::Weighted, 0.001, 4.0}}) {
        FitOptions o;
        o.method = c.method;
        double worst = 0.0, sum2 = 0.0, sum_k = 0.0;
        const int seeds = 8;
        for (std::uint64_t seed = 1; seed <= std::uint64_t(seeds); ++seed) {
            const Image img = render(m, 40.0, 300.0, -1, c.sigma, seed);
            const MinnaertFit f = fit_minnaert(disc_pixels(img, kDisc, sun), sun, o);
            const double pull_k = (f.k - 0.65) / f.se_k, pull_b = (f.B0 - 0.12) / f.se_B0;
            INFO(to_string(c.method) << ", sigma " << c.sigma << ", seed " << seed << ": k " << f.k << " +- " << f.se_k
                                     << ", B0 " << f.B0 << " +- " << f.se_B0);
            REQUIRE(std::isfinite(f.se_k));
            CHECK(f.se_k > 0.0);
            CHECK(std::abs(pull_k) < c.per_seed);
            CHECK(std::abs(pull_b) < c.per_seed);
            worst = std::max({worst, std::abs(pull_k), std::abs(pull_b)});
            sum2 += pull_k * pull_k + pull_b * pull_b;
            sum_k += pull_k;
            if (seed == 1)
                std::cout << "moon: noise sigma " << c.sigma << ", " << to_string(c.method) << ", seed 1: k = " << f.k
                          << " +- " << f.se_k << ", B0 = " << f.B0 << " +- " << f.se_B0 << " (" << f.used << " px)\n";
        }
        const double rms = std::sqrt(sum2 / (2.0 * seeds)), mean_k = sum_k / seeds;
        std::cout << "      pulls over " << seeds << " seeds: largest " << worst << ", rms " << rms << ", mean (k) "
                  << mean_k << "\n";
        INFO(to_string(c.method) << ": rms pull " << rms << " mean pull of k " << mean_k);
        CHECK(rms > 0.5);   // the reported sigma is not inflated either
        CHECK(rms < 1.6);
        CHECK(std::abs(mean_k) < 1.0);
    }
    // The bias the fit on I removes, at sigma 0.004: the Minnaert plot's own second-order estimate of it
    // (bias_k, from the residual scatter) must match what the seeds show, and the fit must warn.
    FitOptions plot;
    double mean_dk = 0.0, mean_bias = 0.0, se = 0.0;
    const int seeds = 8;
    for (std::uint64_t seed = 1; seed <= std::uint64_t(seeds); ++seed) {
        const MinnaertFit f = fit_minnaert(disc_pixels(render(m, 40.0, 300.0, -1, 0.004, seed), kDisc, sun), sun, plot);
        mean_dk += (f.k - 0.65) / seeds;
        mean_bias += f.bias_k / seeds;
        se = f.se_k;
        CHECK(f.noise_sigma == Approx(0.004).epsilon(0.03));   // the noise, from neighbouring pixels
        if (seed == 1) CHECK_FALSE(f.warnings.empty());
    }
    std::cout << "moon: noise sigma 0.004, Minnaert plot over " << seeds << " seeds: mean k - 0.65 = " << mean_dk
              << ", predicted log bias " << mean_bias << ", sigma of k " << se << "\n";
    CHECK(mean_bias > 0.0);   // dim pixels are pulled down most: the slope k goes up
    CHECK(std::abs(mean_dk - mean_bias) < 3.0 * se / std::sqrt(double(seeds)));
    // A noise-free surface that is not a Minnaert law (Lunar-Lambert): the residual is misfit, not noise, so
    // the noise estimate stays near 0, there is no bias warning, and the fit says the law does not fit.
    DiscRenderOptions ll;
    ll.width = ll.height = kSize;
    ll.disc = kDisc;
    ll.sun = sun_geometry(60.0, 0.0);
    const Image lli = render_law_disc(ll, make_photometric_model("lunar_lambert", 0, 0.6, 0.12));
    const MinnaertFit g = fit_minnaert(disc_pixels(lli, kDisc, ll.sun), ll.sun, plot);
    INFO("Lunar-Lambert: k " << g.k << " noise " << g.noise_sigma << " rms " << g.rms);
    CHECK(g.rms > 0.01);              // a visible misfit ...
    CHECK(g.noise_sigma < 1e-4);      // ... that is not taken for noise
    REQUIRE(g.warnings.size() == 1);
    CHECK_THAT(g.warnings[0], Catch::Contains("does not describe this disc"));
}

TEST_CASE("moon fit refuses meaningless inputs with one clear line", "[moon][fit]") {
    const Image img = render(material("minnaert_1941", {{"k", 0.7}}, 0.5), 30.0, 0.0);
    const SunGeometry sun = sun_geometry(30.0, 0.0);
    FitOptions o;
    // Too few pixels: thresholds that leave almost nothing.
    FitOptions strict = o;
    strict.min_pixels = 100000;
    CHECK_THROWS_WITH(fit_minnaert(disc_pixels(img, kDisc, sun), sun, strict), Catch::Contains("pixels") && Catch::Contains("at least 100000"));
    // A tiny disc.
    CHECK_THROWS_WITH(fit_minnaert(disc_pixels(img, Disc{128, 128, 3.0}, sun), sun, o), Catch::Contains("the fit needs at least"));
    // Disc off the image: centre outside, disc past the edge, radius too small or not finite.
    CHECK_THROWS_WITH(disc_pixels(img, Disc{300, 128, 50}, sun), Catch::Contains("outside the 256x256 image"));
    CHECK_THROWS_WITH(disc_pixels(img, Disc{-1, 128, 50}, sun), Catch::Contains("outside"));
    CHECK_THROWS_WITH(disc_pixels(img, Disc{200, 128, 100}, sun), Catch::Contains("extends past the edge") && Catch::Contains("--allow-partial"));
    CHECK_NOTHROW(disc_pixels(img, Disc{200, 128, 100}, sun, true));
    CHECK_THROWS_WITH(disc_pixels(img, Disc{128, 128, 1.0}, sun), Catch::Contains("at least 2 pixels"));
    CHECK_THROWS_WITH(disc_pixels(img, Disc{128, 128, std::nan("")}, sun), Catch::Contains("radius"));
    // Phase near 180: nothing can pass mu, mu0 >= 0.2 beyond 2 acos(0.2) = 156.9 deg.
    const SunGeometry s170 = sun_geometry(170.0, 0.0);
    const Image crescent = render(material("minnaert_1941", {{"k", 0.7}}, 0.5), 170.0, 0.0);
    CHECK_THROWS_WITH(fit_minnaert(disc_pixels(crescent, kDisc, s170), s170, o),
                      Catch::Contains("phase 170") && Catch::Contains("meaningless"));
    // Phase out of range.
    CHECK_THROWS_WITH(sun_geometry(181.0, 0.0), Catch::Contains("phase angle 181") && Catch::Contains("[0, 180]"));
    CHECK_THROWS_WITH(sun_geometry(-5.0, 0.0), Catch::Contains("out of range"));
    CHECK_THROWS_AS(sun_geometry(std::nan(""), 0.0), Error);
    CHECK_THROWS_AS(sun_geometry(10.0, INFINITY), Error);
    // Too narrow a spread of ln(mu mu0): a small patch at the centre, phase 0.
    std::vector<DiscPixel> patch;
    const SunGeometry s0 = sun_geometry(0.0, 0.0);
    for (const DiscPixel& p : disc_pixels(render(material("minnaert_1941", {{"k", 0.7}}, 0.5), 0.0, 0.0), kDisc, s0))
        if (p.X * p.X + p.Y * p.Y < 0.04) patch.push_back(p);
    CHECK_THROWS_WITH(fit_minnaert(patch, s0, o), Catch::Contains("too narrow"));
    // Bad options.
    FitOptions bad = o;
    bad.mu_min = 1.5;
    CHECK_THROWS_WITH(fit_minnaert(disc_pixels(img, kDisc, sun), sun, bad), Catch::Contains("--mu-min"));
    // A crescent at phase 130 still fits, with a warning.
    const SunGeometry s130 = sun_geometry(130.0, 0.0);
    FitOptions low = o;
    low.mu_min = low.mu0_min = 0.1;
    const MinnaertFit f = fit_minnaert(disc_pixels(render(material("minnaert_1941", {{"k", 0.7}}, 0.5), 130.0, 0.0), kDisc, s130), s130, low);
    CHECK(std::abs(f.k - 0.7) < 0.002);
    CHECK_FALSE(f.warnings.empty());
}

TEST_CASE("moon bad input: unreadable images, missing files, bad FITS", "[moon]") {
    const fs::path dir = test::scratch_dir("moon");
    CHECK_THROWS_WITH(read_any_image((dir / "missing.exr").string()), Catch::Contains("not found"));
    CHECK_THROWS_WITH(read_any_image((dir / "missing.fits").string()), Catch::Contains("not found"));
    {
        std::ofstream((dir / "junk.png").string()) << "this is not a png";
        std::ofstream((dir / "junk.fits").string()) << "this is not a fits file";
        std::ofstream((dir / "short.fits").string()) << std::string(100, ' ');
    }
    CHECK_THROWS_AS(read_any_image((dir / "junk.png").string()), Error);
    CHECK_THROWS_WITH(read_any_image((dir / "junk.fits").string()), Catch::Contains("FITS"));
    CHECK_THROWS_WITH(read_any_image((dir / "short.fits").string()), Catch::Contains("truncated"));
    CHECK_THROWS_WITH(make_photometric_model("no_such_model", 0.5, 0, 1.0), Catch::Contains("unknown model"));
    CHECK_THROWS_WITH(make_photometric_model("minnaert", -1.0, 0, 1.0), Catch::Contains("k -1"));
    // the ranges are the catalogue's: minnaert_1941 k in [0, 2], lunar_lambert l in [-1, 2]
    CHECK_THROWS_WITH(make_photometric_model("minnaert", 2.5, 0, 1.0), Catch::Contains("k 2.5 is out of range: use 0 <= k <= 2"));
    CHECK_THROWS_WITH(make_photometric_model("lunar_lambert", 0, 3.0, 1.0), Catch::Contains("L 3"));
    CHECK_NOTHROW(make_photometric_model("lunar_lambert", 0, 2.0, 1.0));
    CHECK_THROWS_WITH(make_photometric_model("minnaert", 0.5, 0, 1.0, {{"k", 0.5}}), Catch::Contains("--k"));
    fs::remove_all(dir);
}

// ------------------------------------------------------------------------------------------ stability

TEST_CASE("moon limb stability: k < 0.5 near the limb gives finite values in renders, curves, fits, tables",
          "[moon][kernel]") {
    // A disc whose rightmost pixel centres lie 1e-7 px inside the limb: mu ~ 4.5e-5 there.
    const Disc edge{128.5, 128.5, 100.0 + 1e-7};
    for (double k : {0.0, 0.2, 0.45}) {
        for (const char* model : {"minnaert_1941", "minnaert_normalized"}) {
            const Material m = material(model, {{"k", k}}, 0.5);
            DiscRenderReport rep;
            const Image img = render(m, 0.0, 0.0, -1, 0.0, 1, &rep, edge);
            INFO(model << " k " << k << ": min mu " << rep.min_mu << " max value " << rep.max_value);
            CHECK(non_finite(img) == 0);
            CHECK(rep.min_mu < 1e-4);
            // The kernel's limb guard (docs/models/minnaert.md): each cosine's power is held at 1e-3^(k-1) and
            // faded to 0 below 1e-3, so the value never exceeds albedo * 1e-3^(k-1) (normalised: times (k+1)/2).
            CHECK(rep.max_value <= 0.5 * std::pow(1e-3, k - 1.0) * (1.0 + 1e-6));
            if (k == 0.0 && std::string(model) == "minnaert_1941")
                std::cout << "moon: minnaert_1941 k=0 at phase 0, smallest mu " << rep.min_mu << ": largest value "
                          << rep.max_value << " (law at mu 0.05 would be " << minnaert_1941_paper(0.05, 0.05, 0.0, 0.5) << ")\n";
            // The fit with no limb threshold still returns finite numbers (the guard pixels pull k; the default
            // thresholds keep them out).
            FitOptions open;
            open.mu_min = open.mu0_min = 0.0;
            const SunGeometry s0 = sun_geometry(0.0, 0.0);
            const MinnaertFit f = fit_minnaert(disc_pixels(img, edge, s0), s0, open);
            CHECK(std::isfinite(f.k));
            CHECK(std::isfinite(f.se_k));
            CHECK(std::isfinite(f.B0));
        }
        // Analytic curves right up to the limb (mu of the outermost sample ~ 1.4e-3 for 1e6 samples).
        for (const CurvePoint& p : equator_curve(make_photometric_model("minnaert", k, 0, 1.0), sun_geometry(0.0, 0.0), 1000000))
            REQUIRE(std::isfinite(p.value));
        // The law at cosines down to the smallest denormal: finite, and 0 on the limb itself.
        const PhotometricModel law = make_photometric_model("minnaert", k, 0, 1.0);
        const SunGeometry s0 = sun_geometry(0.0, 0.0);
        for (double mu : {1e-300, 4.9e-324, 0.0}) {
            const glm::dvec3 N = std::sqrt(1.0 - mu * mu) * s0.u + mu * s0.V;
            CHECK(std::isfinite(law.value(N, s0)));
            if (mu == 0.0) CHECK(law.value(N, s0) == 0.0);
        }
    }
    // The limb mask drops pixels below the given mu (alpha 0), so fits and profiles skip them.
    DiscRenderOptions o;
    o.width = o.height = kSize;
    o.disc = kDisc;
    o.material = material("minnaert_1941", {{"k", 0.2}}, 0.5);
    o.sun = sun_geometry(20.0, 0.0);
    o.limb_mask_mu = 0.1;
    DiscRenderReport rep;
    const Image masked = render_disc(test::runtime(), o, &rep);
    CHECK(rep.masked > 0);
    for (const DiscPixel& p : disc_pixels(masked, kDisc, o.sun)) CHECK(p.a.mu >= 0.1 - 1e-12);
    // Tables refuse NaN/Inf outright.
    CsvTable t({"a"});
    t.row();
    CHECK_THROWS_WITH(t.add(std::nan("")), Catch::Contains("non-finite"));
}

// ------------------------------------------------------------------------------------------ profiles, bins

TEST_CASE("moon profiles: pixels on the line, exact geometry, values on the analytic curve", "[moon][kernel]") {
    const Material m = material("minnaert_1941", {{"k", 0.62}}, 0.4);
    for (double pa : {0.0, 37.0, 90.0, 211.0}) {
        const SunGeometry sun = sun_geometry(50.0, pa);
        const Image img = render(m, 50.0, pa);
        const auto eq = equator_profile(img, kDisc, sun);
        const auto ac = across_profile(img, kDisc, sun, 0.3);
        REQUIRE(eq.size() > 200);
        REQUIRE(ac.size() > 150);
        double worst = 0.0;
        for (std::size_t i = 0; i < eq.size(); ++i) {
            const ProfilePixel& p = eq[i];
            INFO("pa " << pa << " s " << p.s << " offset " << p.offset);
            CHECK(std::abs(p.offset) <= 0.7072 / kDisc.radius);   // the nearest pixel centre is within half a diagonal
            if (i) CHECK(p.s >= eq[i - 1].s);
            // On the equator lambda = asin(s) up to the pixel's offset, and beta ~ offset.
            CHECK(std::abs(p.p.a.beta_deg) <= std::asin(0.7072 / kDisc.radius / std::sqrt(std::max(1e-9, 1 - p.s * p.s))) / kDeg + 1e-9);
            if (p.p.a.mu >= 0.05 && p.p.a.mu0 >= 0.05) {
                const double law = minnaert_1941_paper(p.p.a.mu0, p.p.a.mu, 0.62, 0.4);
                worst = std::max(worst, std::abs(p.p.I - law) / law);
            }
        }
        for (const ProfilePixel& p : ac) CHECK(std::abs(p.offset) <= 0.7072 / kDisc.radius);
        // The across line at 0.3 crosses the equator 0.3 radii towards the sun: lambda = asin(0.3) at beta = 0.
        for (const ProfilePixel& p : ac)
            if (std::abs(p.s) < 0.5 / kDisc.radius) CHECK(p.p.a.lambda_deg == Approx(std::asin(0.3) / kDeg).margin(0.6));
        CHECK(worst < 3e-5);
        // The sun side is where lambda > 0: the bright limb is at s -> +1 on the equator.
        CHECK(eq.back().p.a.lambda_deg > 80.0);
        CHECK(eq.front().p.a.lambda_deg < -80.0);
    }
}

TEST_CASE("moon k map and longitude bins of a uniform Minnaert disc are flat", "[moon][kernel][fit]") {
    const Material m = material("minnaert_1941", {{"k", 0.75}}, 0.2);
    const SunGeometry sun = sun_geometry(45.0, 120.0);
    const auto pixels = disc_pixels(render(m, 45.0, 120.0), kDisc, sun);
    FitOptions o;
    const MinnaertFit whole = fit_minnaert(pixels, sun, o);
    FitOptions fixed = o;
    fixed.fixed_ln_B0 = whole.ln_B0;
    int ok = 0;
    for (const auto& b : fit_longitude_bins(pixels, sun, fixed, 6)) {
        INFO("bin " << b.lo << " .. " << b.hi << ": " << (b.ok ? std::to_string(b.fit.k) : b.why));
        REQUIRE(b.ok);
        CHECK(std::abs(b.fit.k - 0.75) < 0.002);
        ++ok;
    }
    CHECK(ok == 6);
    int cells = 0;
    for (const auto& c : fit_grid(pixels, sun, fixed, 6)) {
        if (!c.ok) continue;
        ++cells;
        INFO("cell " << c.i << "," << c.j << ": k " << c.fit.k);
        CHECK(std::abs(c.fit.k - 0.75) < 0.002);
    }
    CHECK(cells >= 20);
    // With B0 free per cell the cells near the sub-solar point are refused (too narrow a range), not wrong.
    for (const auto& c : fit_grid(pixels, sun, o, 6))
        if (c.ok) CHECK(std::abs(c.fit.k - 0.75) < 0.002);
}

// ------------------------------------------------------------------------------------------ files, plots

TEST_CASE("moon FITS files are standard (bottom row first, 2880-byte blocks) and round trip - fits agree across formats",
          "[moon][kernel][image]") {
    const fs::path dir = test::scratch_dir("moon");
    const Material m = material("minnaert_1941", {{"k", 0.58}}, 0.35);
    const SunGeometry sun = sun_geometry(35.0, 75.0);
    const Image img = render(m, 35.0, 75.0);
    const std::string fits = (dir / "disc.fits").string();
    write_any_image(fits, img, {{"PHASE", "35"}, {"MODEL", "minnaert_1941"}});
    // The file: a multiple of 2880 bytes; the first stored row is the image's bottom row (big-endian float).
    std::ifstream in(fits, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    CHECK(bytes.size() % 2880 == 0);
    REQUIRE(std::string(bytes.data(), 6) == "SIMPLE");
    std::size_t data = 0;
    for (std::size_t c = 0; c < bytes.size(); c += 80)
        if (std::string(bytes.data() + c, 3) == "END") {
            data = (c / 2880 + 1) * 2880;
            break;
        }
    REQUIRE(data > 0);
    auto stored = [&](int x, int row_in_file) {
        unsigned char b[4];
        for (int j = 0; j < 4; ++j) b[j] = static_cast<unsigned char>(bytes[data + (std::size_t(row_in_file) * kSize + x) * 4 + std::size_t(3 - j)]);
        float v;
        std::memcpy(&v, b, 4);
        return v;
    };
    CHECK(stored(128, 0) == img.at(128, kSize - 1, 0));
    CHECK(stored(100, 200) == img.at(100, kSize - 1 - 200, 0));
    std::map<std::string, std::string> kw;
    const Image back = read_any_image(fits, &kw);
    CHECK(kw["PHASE"] == "35");
    CHECK(kw["MODEL"] == "minnaert_1941");
    REQUIRE(back.width == kSize);
    REQUIRE(back.channels == 2);
    double worst = 0.0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) worst = std::max(worst, double(std::abs(back.at(x, y, 0) - img.at(x, y, 0))));
    CHECK(worst == 0.0);

    // A FITS file as observatories write them: BITPIX 16 with BZERO/BSCALE and a BLANK value.
    {
        std::string h;
        auto card = [&](const std::string& s) { std::string c = s; c.resize(80, ' '); h += c; };
        card("SIMPLE  =                    T");
        card("BITPIX  =                   16");
        card("NAXIS   =                    2");
        card("NAXIS1  =                    3");
        card("NAXIS2  =                    2");
        card("BZERO   =              32768.0");
        card("BSCALE  =                 0.5");
        card("BLANK   =               -32768");
        card("END");
        h.resize(2880, ' ');
        std::string d;
        const int16_t raw[6] = {-32768, 0, 100, -32767, 2, 4};   // stored bottom row first
        for (int16_t r : raw) {
            d += char((uint16_t(r) >> 8) & 0xff);
            d += char(uint16_t(r) & 0xff);
        }
        d.resize(2880, '\0');
        std::ofstream((dir / "obs.fits").string(), std::ios::binary) << h << d;
    }
    const Image obs = read_any_image((dir / "obs.fits").string());
    REQUIRE(obs.width == 3);
    REQUIRE(obs.height == 2);
    // value = BZERO + BSCALE * stored; the first stored row is the bottom row (memory row 1).
    CHECK(obs.at(0, 1, 1) == 0.0f);                     // BLANK: alpha 0 ...
    CHECK(obs.at(0, 1, 0) == 0.0f);                     // ... and value 0
    CHECK(obs.at(1, 1, 0) == Approx(32768.0));
    CHECK(obs.at(2, 1, 0) == Approx(32818.0));
    CHECK(obs.at(0, 0, 0) == Approx(16384.5));          // top row = second stored row
    CHECK(obs.at(2, 0, 0) == Approx(32770.0));
    CHECK(obs.at(2, 0, 1) == 1.0f);

    // The same disc through EXR, TIFF (float), FITS and PNG (8-bit sRGB): the fits agree.
    FitOptions o;
    const MinnaertFit ref_fit = fit_minnaert(disc_pixels(img, kDisc, sun), sun, o);
    for (const char* ext : {".exr", ".tif", ".fits", ".png"}) {
        const std::string p = (dir / (std::string("d") + ext)).string();
        write_any_image(p, img);
        const MinnaertFit f = fit_minnaert(disc_pixels(read_any_image(p), kDisc, sun), sun, o);
        INFO(ext << ": k " << f.k << " B0 " << f.B0);
        CHECK(std::abs(f.k - 0.58) < (std::string(ext) == ".png" ? 0.005 : 0.002));
        if (std::string(ext) != ".png") CHECK(f.k == Approx(ref_fit.k).epsilon(1e-9));
    }
    fs::remove_all(dir);
}

TEST_CASE("moon plots: gnuplot draws the charts - without gnuplot one error line names gnuplot-nox, CSV kept",
          "[moon][plot]") {
    const fs::path dir = test::scratch_dir("moon");
    const std::string csv = (dir / "c.csv").string(), png = (dir / "c.png").string();
    const SunGeometry sun = sun_geometry(30.0, 0.0);
    const PhotometricModel m = make_photometric_model("minnaert", 0.7, 0, 1.0);
    CsvTable t({"profile", "s", "I_a"});
    for (const CurvePoint& p : equator_curve(m, sun, 50)) t.row().add("equator").add(p.s).add(p.value);
    for (const CurvePoint& p : across_curve(m, sun, 0.0, 50)) t.row().add("across").add(p.s).add(p.value);
    t.write(csv);

    const char* old = std::getenv("SHADELAB_GNUPLOT");
    const std::string saved = old ? old : "";
    ::setenv("SHADELAB_GNUPLOT", (dir / "no-gnuplot-here").string().c_str(), 1);
    try {
        plot_curves(csv, png, {"I_a"}, {"k 0.7"}, "test");
        FAIL("no error without gnuplot");
    } catch (const Error& e) {
        const std::string what = e.what();
        CHECK(what.find("gnuplot-nox") != std::string::npos);
        CHECK(what.find(csv) != std::string::npos);   // says the table was written
        CHECK(what.find('\n') == std::string::npos);  // one line
    }
    CHECK(fs::exists(csv));
    CHECK_FALSE(fs::exists(png));
    if (old) ::setenv("SHADELAB_GNUPLOT", saved.c_str(), 1); else ::unsetenv("SHADELAB_GNUPLOT");

    bool have_gnuplot = true;
    try {
        find_gnuplot();
    } catch (const Error&) {
        have_gnuplot = false;
    }
    if (!have_gnuplot) {
        WARN("gnuplot is not installed: the drawing half of this test is skipped (Debian package gnuplot-nox)");
    } else {
        plot_curves(csv, png, {"I_a"}, {"k 0.7"}, "test");
        CHECK(fs::file_size(png) > 1000);
        const std::string g = (dir / "g.png").string();
        plot_geometry(g, sun_geometry(60.0, 30.0), 0.2);
        CHECK(fs::file_size(g) > 1000);
        // gnuplot's own complaint becomes one line.
        CHECK_THROWS_WITH(run_gnuplot("set terminal pngcairo\nset output '" + (dir / "x.png").string() + "'\nplot nosuchfunction(x)\n",
                                      (dir / "x.png").string(), ""),
                          Catch::Contains("gnuplot could not draw"));
    }
    fs::remove_all(dir);
}
