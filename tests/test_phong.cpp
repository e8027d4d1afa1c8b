// Phong family (Phong, Blinn-Phong; reference = gated, seed 001's ungated forms, energy-normalised forms):
// kernels against the double references over the sphere and a parameter grid with a stated float error
// model, hand-computed values, pow(0, 0) / n = 0 / L = -V behaviour, the seed variants' measured
// deviation, directional albedo (energy normalisation) and reciprocity.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>

#include "cl/runtime.hpp"
#include "consts/phong.h"
#include "core/error.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"
#include "support.hpp"

using namespace shadelab;

namespace {

// The family's materials: the shared test colours, the specular one included.
Material make(const std::string& model, std::map<std::string, double> params = {}, glm::dvec3 albedo = test::kAlbedo,
              glm::dvec3 specular = test::kSpecular) {
    return test::material(model, std::move(params), albedo, specular);
}

// ---- the float error model -------------------------------------------------------------------------
// The kernel computes NoL, NoV, LoV (and NoH) in float from the same float vectors the reference reads in
// double. Bounds on those float errors (u = 2^-24):
//   a dot product of unit float vectors: gamma_3 <= 3u, taken as 4u;
//   RoV = 2 NoL NoV - LoV: (2|NoV| + 2|NoL| + 1) 4u + 2u (2|NoL NoV| + |LoV|), plus the kernel's clamp of
//         RoV to 1 (the reference does not clamp; float unit vectors give RoV up to 1 + 3e-7);
//   NoH = dot(N, L + V) rsqrt(|L + V|^2): 4u (dot and the rounded sum) + 7.5u (|L + V|^2, rsqrt <= 2 ulp,
//         product), taken as 12u, plus the clamp to 1.
// A model is written here as g(NoL, x) with x = RoV or NoH; g increases in both, so its change over the
// box NoL +- dNoL, x +- dx is attained at a corner. That change B is what float rounding of the inputs
// can legitimately do to the value; the kernel's own arithmetic adds a few ulps (kTightRel).
constexpr double kU = 0x1p-24;
constexpr double kDeltaDot = 4 * kU;
constexpr double kDeltaNoH = 12 * kU;
constexpr double kTightRel = 4e-6;   // pow (PoCL ~1 ulp, OpenCL allows 16) and ~6 roundings: "a few 1e-6"
constexpr double kValueFloor = 1e-3;
constexpr double kCondRel = 1e-6;    // conditioned: B <= 1e-6 |value|
// Float underflow: a lobe below FLT_MIN = 1.2e-38 keeps no relative precision (denormal or 0), and the
// model's constants (<= ks K_n ~ 1e4) scale that absolute error; 1e-33 bounds it.
constexpr double kUnderflow = 1e-33;

enum class Form { Gated, Ungated, Normalized };
enum class Lobe { Phong, Blinn };

struct ModelShape {
    Form form;
    Lobe lobe;
    double n;            // exponent
    double kd_scale;     // diffuse weight (1 or 1 - ks)
    double spec_scale;   // lobe weight (ks, specular_power, or ks K_n)
};

double exact_blinn_norm(double n) { return (n + 2.0) * (n + 4.0) / (8.0 * (std::exp2(-0.5 * n) + n)); }

ModelShape shape_of(const Material& m) {
    const auto& p = m.params;
    const std::string& name = m.model;
    const Lobe lobe = name.rfind("blinn", 0) == 0 ? Lobe::Blinn : Lobe::Phong;
    if (name == "phong" || name == "blinn_phong") return {Form::Gated, lobe, p.at("n"), 1.0, p.at("ks")};
    if (name == "phong_seed001") return {Form::Ungated, lobe, p.at("gloss") / 4.0, 1.0, p.at("specular_power")};
    if (name == "blinn_phong_seed001") return {Form::Ungated, lobe, p.at("gloss"), 1.0, p.at("specular_power")};
    const double n = p.at("n"), ks = p.at("ks");
    double K = 0.0;
    if (name == "phong_normalized") K = (n + 2.0) / 2.0;
    if (name == "blinn_phong_normalized") K = exact_blinn_norm(n);
    if (name == "blinn_phong_normalized_approx") K = (n + 8.0) / 8.0;
    return {Form::Normalized, lobe, n, 1.0 - ks, ks * K};
}

double lobe_pow(double x, double n) { return x > 0.0 ? std::pow(x, n) : 0.0; }

double g_of(const ModelShape& s, double kd, double ks, double NoL, double x) {
    const double cosine = std::max(NoL, 0.0);
    switch (s.form) {
        case Form::Gated: return kd * cosine + ks * (NoL > 0.0 ? lobe_pow(x, s.n) : 0.0);
        case Form::Ungated: return kd * cosine + ks * lobe_pow(x, s.n);
        case Form::Normalized: break;
    }
    return kd * cosine + ks * lobe_pow(x, s.n) * cosine;
}

struct Dots { double NoL, NoV, LoV, x, dx; };

Dots dots(const ModelShape& s, const glm::dvec3& N, const glm::dvec3& L, const glm::dvec3& V) {
    Dots d{glm::dot(N, L), glm::dot(N, V), glm::dot(L, V), 0.0, 0.0};
    if (s.lobe == Lobe::Phong) {
        d.x = 2.0 * d.NoL * d.NoV - d.LoV;
        d.dx = kDeltaDot * (2 * std::abs(d.NoV) + 2 * std::abs(d.NoL) + 1) +
               2 * kU * (2 * std::abs(d.NoL * d.NoV) + std::abs(d.LoV));
    } else {
        const glm::dvec3 h = L + V;
        const double len = glm::length(h);
        d.x = len > 1e-10 ? glm::dot(N, h) / len : 0.0;
        d.dx = len > 1e-10 ? kDeltaNoH : 0.0;   // L = -V exactly: both sides take NoH = 0
    }
    d.dx += std::max(0.0, d.x - 1.0);
    return d;
}

// Largest change of the value over the input box, per channel.
glm::dvec3 input_bound(const ModelShape& s, const Material& m, const Dots& d) {
    glm::dvec3 B(0.0);
    for (int c = 0; c < 3; ++c) {
        const double kd = s.kd_scale * m.albedo[c], ks = s.spec_scale * m.specular[c];
        const double g0 = g_of(s, kd, ks, d.NoL, d.x);
        for (double a : {-1.0, 1.0})
            for (double b : {-1.0, 1.0})
                B[c] = std::max(B[c], std::abs(g_of(s, kd, ks, d.NoL + a * kDeltaDot, d.x + b * d.dx) - g0));
    }
    return B;
}

// The kernel over the standard sweep against the reference, with the input bound of each value.
test::ConditionedResult check_sweep(const Material& m) {
    const ModelShape s = shape_of(m);
    return test::check_conditioned(m, {kTightRel, kValueFloor, kCondRel, kUnderflow}, [&](const test::Compared& v) {
        return input_bound(s, m, dots(s, v.N(), v.L(), v.V()));
    });
}

// Directional albedo (1/pi) integral of value dL of a lobe-only material (albedo 0), by the midpoint rule
// after the substitution u = s^(1/(n+1)) (u = RoV around R(V) for Phong; u = NoH around N for Blinn-Phong,
// with dL = 4 VoH dH), which makes the cosine power flat so n up to 10000 integrates accurately.
double lobe_albedo(const Material& m, Lobe lobe, double n, const glm::dvec3& V, int S = 192, int Bn = 384) {
    const glm::dvec3 N{0, 0, 1};
    const glm::dvec3 axis = lobe == Lobe::Phong ? 2.0 * V.z * N - V : N;
    const glm::dvec3 t = glm::normalize(glm::cross(axis, std::abs(axis.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    const glm::dvec3 b = glm::cross(axis, t);
    double sum = 0.0;
    for (int i = 0; i < S; ++i) {
        const double s = (i + 0.5) / S;
        const double u = std::pow(s, 1.0 / (n + 1.0));
        const double jac = 1.0 / ((n + 1.0) * std::pow(s, n / (n + 1.0)));   // du/ds = 1 / ((n+1) u^n)
        const double st = std::sqrt(std::max(0.0, 1.0 - u * u));
        for (int j = 0; j < Bn; ++j) {
            const double beta = 2.0 * M_PI * (j + 0.5) / Bn;
            const glm::dvec3 w = u * axis + st * (std::cos(beta) * t + std::sin(beta) * b);
            if (lobe == Lobe::Phong) {
                sum += ref::eval_material(N, w, V, {}, m).x * jac;
            } else {
                const double VoH = glm::dot(V, w);
                if (VoH <= 0.0) continue;   // each L has its H with VoH > 0
                sum += ref::eval_material(N, 2.0 * VoH * w - V, V, {}, m).x * 4.0 * VoH * jac;
            }
        }
    }
    return sum * (1.0 / S) * (2.0 * M_PI / Bn) / M_PI;
}

glm::dvec3 view_at(double deg) { return {std::sin(deg * M_PI / 180.0), 0.0, std::cos(deg * M_PI / 180.0)}; }

}  // namespace

TEST_CASE("phong kernels match the double references over the sphere and the parameter grid", "[phong][kernel]") {
    std::vector<Material> grid;
    for (double n : {0.0, 1.0, 32.0, 10000.0})
        for (double ks : {0.0, 1.0, 10.0}) {
            grid.push_back(make("phong", {{"n", n}, {"ks", ks}}));
            grid.push_back(make("blinn_phong", {{"n", n}, {"ks", ks}}));
        }
    for (double gloss : {0.0, 1.0, 128.0, 40000.0})
        for (double sp : {0.0, 1.0, 10.0}) {
            grid.push_back(make("phong_seed001", {{"gloss", gloss}, {"specular_power", sp}}));
            grid.push_back(make("blinn_phong_seed001", {{"gloss", gloss}, {"specular_power", sp}}));
        }
    for (double n : {0.0, 1.0, 32.0, 10000.0})
        for (double ks : {0.0, 0.5, 1.0})
            for (const char* name : {"phong_normalized", "blinn_phong_normalized", "blinn_phong_normalized_approx"})
                grid.push_back(make(name, {{"n", n}, {"ks", ks}}));
    std::cout << "phong kernels vs double reference, " << test::sweep().size()
              << " triples; conditioned: |ref| >= 1e-3 and the float input box moves it <= 1e-6 relative\n";
    for (const Material& m : grid) {
        const test::ConditionedResult r = check_sweep(m);
        const test::KernelVsReference& e = r.e;
        std::cout << "  " << std::left << std::setw(50) << test::describe(m, true) << std::right << " max abs "
                  << std::setw(11) << e.max_abs << " max rel " << std::setw(11) << e.max_rel << "  cond " << std::setw(6)
                  << r.cond << " max rel " << std::setw(11) << r.max_rel_cond << "  rest " << std::setw(6) << r.rest
                  << " max err/bound " << e.worst_ratio << "\n";
        test::expect_within(e, test::sweep().size());
    }
}

TEST_CASE("phong closed-form values, pow(0, 0), n = 0 and the L = -V guard", "[phong][kernel][stability]") {
    Shader shader(test::runtime());
    const double c60 = 0.5, s60 = std::sqrt(3.0) / 2.0;
    const glm::dvec3 Nz{0, 0, 1};
    const glm::dvec3 L60{s60, 0, c60}, R60{-s60, 0, c60};
    const glm::dvec3 below{0.995, 0.0, -std::sqrt(1.0 - 0.995 * 0.995)};   // NoL = -0.0999
    const glm::dvec3 mirror_of_below{-below.x, 0.0, -below.z};               // NoV = +0.0999, RoV ~ 0.98
    const glm::dvec3 white{1, 1, 1};
    struct Spot { const char* what; Material m; glm::dvec3 L, V; double expect; };
    const double k2 = 4.0 * 6.0 / (8.0 * 2.5);   // exact Blinn-Phong K at n = 2: 1.2
    const std::vector<Spot> spots = {
        {"phong, V = R", make("phong", {{"n", 32}, {"ks", 1}}, {0.5, 0.5, 0.5}, white), L60, R60, 0.25 + 1.0},
        {"phong n=2, V = N (RoV = 0.5)", make("phong", {{"n", 2}, {"ks", 2}}, {0, 0, 0}, white), L60, Nz, 2 * 0.25},
        {"phong_seed001 gloss=8 (n = 2)", make("phong_seed001", {{"gloss", 8}}, {0, 0, 0}, white), L60, Nz, 0.25},
        {"blinn_phong n=2, V = N (NoH = cos 30)", make("blinn_phong", {{"n", 2}}, {0, 0, 0}, white), L60, Nz, 0.75},
        {"phong_normalized n=2 ks=0.5, L = V = N", make("phong_normalized", {{"n", 2}, {"ks", 0.5}}, white, white), Nz, Nz,
         0.5 + 0.5 * 2.0},
        {"blinn_phong_normalized n=2 ks=1, L = V = N", make("blinn_phong_normalized", {{"n", 2}, {"ks", 1}}, white, white),
         Nz, Nz, k2},
        {"blinn_phong_normalized_approx n=2 ks=1, L = V = N",
         make("blinn_phong_normalized_approx", {{"n", 2}, {"ks", 1}}, white, white), Nz, Nz, 10.0 / 8.0},
        // pow(0, 0): n = 0 with RoV = 0 (L = N, V horizontal) and RoV < 0 gives 0, not ks.
        {"phong n=0, RoV = 0", make("phong", {{"n", 0}}, {0, 0, 0}, white), Nz, {1, 0, 0}, 0.0},
        {"phong_seed001 gloss=0, RoV = -0.8", make("phong_seed001", {{"gloss", 0}}, {0, 0, 0}, white), Nz, {0.6, 0, -0.8}, 0.0},
        {"phong n=0, RoV = 0.5 > 0", make("phong", {{"n", 0}}, {0, 0, 0}, white), L60, Nz, 1.0},
        {"blinn_phong n=0, NoH = 0 (L = -V horizontal)", make("blinn_phong", {{"n", 0}}, {0, 0, 0}, white), {1, 0, 0}, {-1, 0, 0}, 0.0},
        // L = -V: H undefined, highlight 0 even ungated and at n = 0.
        {"blinn_phong_seed001 gloss=0, L = -V", make("blinn_phong_seed001", {{"gloss", 0}}, {0, 0, 0}, white), L60, -L60, 0.0},
        {"blinn_phong, L = -V, lit", make("blinn_phong", {{"n", 1}}, white, white), L60, -L60, 0.5},
        // The seed's ungated highlight from a light below the horizon; the reference gates it to 0.
        {"phong_seed001 gloss=4, light behind", make("phong_seed001", {{"gloss", 4}}, {0, 0, 0}, white), below,
         mirror_of_below, 2 * below.z * mirror_of_below.z - glm::dot(below, mirror_of_below)},
        {"phong n=1, light behind", make("phong", {{"n", 1}}, {0, 0, 0}, white), below, mirror_of_below, 0.0},
        // n at the top of its range on the peak: exactly the peak (the clamp of x to 1), finite.
        {"phong n=10000, L = V = N", make("phong", {{"n", 10000}}, {0, 0, 0}, white), Nz, Nz, 1.0},
        {"blinn_phong n=10000, L = V = N", make("blinn_phong", {{"n", 10000}}, {0, 0, 0}, white), Nz, Nz, 1.0},
    };
    std::cout << "phong spot values (kernel, reference, by hand):\n";
    for (const Spot& sp : spots) {
        const std::vector<float> N = {0, 0, 1}, L = {float(sp.L.x), float(sp.L.y), float(sp.L.z)},
                                 V = {float(sp.V.x), float(sp.V.y), float(sp.V.z)}, P = {0, 0, 0};
        const auto out = shader.eval_directions(sp.m, N, L, V, P);
        const double r = ref::eval_material(Nz, sp.L, sp.V, {}, sp.m).x;
        std::cout << "  " << std::left << std::setw(52) << sp.what << std::right << " " << std::setw(12) << out[0] << " "
                  << std::setw(12) << r << " " << sp.expect << "\n";
        INFO(sp.what << ": kernel " << out[0] << ", reference " << r << ", by hand " << sp.expect);
        CHECK(std::isfinite(out[0]));
        CHECK(std::abs(out[0] - sp.expect) <= 2e-6 * std::max(1.0, sp.expect));
        CHECK(std::abs(r - sp.expect) <= 1e-12 * std::max(1.0, sp.expect));
    }
}

TEST_CASE("phong seed variants: the gloss/4 convention, and the measured effect of the missing NoL gate", "[phong][seed]") {
    const auto& sw = test::sweep();
    Shader shader(test::runtime());
    std::cout << "seed 001's ungated forms vs the gated references (same exponent; green channel, specular 0.8):\n";
    for (double n : {1.0, 32.0, 1000.0}) {
        for (bool blinn : {false, true}) {
            const Material ref_m = make(blinn ? "blinn_phong" : "phong", {{"n", n}, {"ks", 1.0}});
            const Material seed_m = make(blinn ? "blinn_phong_seed001" : "phong_seed001",
                                         {{"gloss", blinn ? n : 4.0 * n}, {"specular_power", 1.0}});
            const auto kr = shader.eval_directions(ref_m, sw.N, sw.L, sw.V, sw.P);
            const auto ks = shader.eval_directions(seed_m, sw.N, sw.L, sw.V, sw.P);
            double lit_dev = 0.0, max_dev = 0.0, front_dev = 0.0;
            std::size_t differ = 0;
            for (std::size_t i = 0; i < sw.size(); ++i) {
                const double NoL = glm::dot(sw.dN[i], sw.dL[i]), NoV = glm::dot(sw.dN[i], sw.dV[i]);
                const double d = std::abs(double(ks[3 * i + 1]) - double(kr[3 * i + 1]));
                if (NoL > kDeltaDot) lit_dev = std::max(lit_dev, d);
                if (NoV > 0.0) front_dev = std::max(front_dev, d);
                max_dev = std::max(max_dev, d);
                if (d > 0.0) ++differ;
            }
            std::cout << "  " << std::left << std::setw(20) << seed_m.model << std::right << " gloss " << std::setw(6)
                      << seed_m.params.at("gloss") << ": " << std::setw(6) << differ << " of " << sw.size()
                      << " triples differ, max deviation " << max_dev << " (viewer in front, NoV > 0: " << front_dev
                      << ")\n";
            INFO(test::describe(seed_m, true));
            CHECK(lit_dev == 0.0);   // gloss / 4 (Phong) and gloss (Blinn) give the reference's exponent exactly
            CHECK(max_dev > 0.0);    // light from behind produces highlights in the seed form
            CHECK(max_dev <= 0.8 + 1e-6);
        }
    }
    // Why gloss / 4: near the peak (V = N, light at angle theta) ln(cos theta^(g/4)) / ln(cos(theta/2)^g)
    // = 1 + theta^2 / 8 + ..., so the two seed lobes have the same width for the same _SpecularGloss.
    const Material p = make("phong_seed001", {{"gloss", 128}}, {0, 0, 0}, {1, 1, 1});
    const Material b = make("blinn_phong_seed001", {{"gloss", 128}}, {0, 0, 0}, {1, 1, 1});
    const glm::dvec3 Nz{0, 0, 1};
    for (double theta : {0.01, 0.05, 0.1}) {
        const glm::dvec3 L{std::sin(theta), 0, std::cos(theta)};
        const double ratio = std::log(ref::eval_material(Nz, L, Nz, {}, p).x) / std::log(ref::eval_material(Nz, L, Nz, {}, b).x);
        INFO("theta " << theta << ": ratio of log lobes " << ratio);
        CHECK(std::abs(ratio - 1.0) <= theta * theta / 4.0);
    }
}

TEST_CASE("energy-normalised lobes integrate to at most 1 - the (n+8)/8pi Blinn-Phong factor overshoots",
          "[phong][physics]") {
    const glm::dvec3 black{0, 0, 0}, white{1, 1, 1};
    const double views[] = {0.0, 45.0, 85.0};
    std::cout << "lobe directional albedo (albedo 0, ks 1, specular 1) at view 0/45/85 deg:\n";
    double approx_worst = 0.0;
    for (double n : {0.0, 1.0, 11.0, 100.0, 10000.0}) {
        for (const char* name : {"phong_normalized", "blinn_phong_normalized", "blinn_phong_normalized_approx"}) {
            const Material m = make(name, {{"n", n}, {"ks", 1.0}}, black, white);
            const Lobe lobe = name[0] == 'b' ? Lobe::Blinn : Lobe::Phong;
            std::cout << "  " << std::left << std::setw(30) << name << std::right << " n " << std::setw(6) << n << ":";
            for (double deg : views) {
                const double a = lobe_albedo(m, lobe, n, view_at(deg));
                std::cout << " " << std::setw(10) << a;
                INFO(name << " n " << n << " view " << deg << " deg: lobe albedo " << a);
                CHECK(std::isfinite(a));
                if (std::string(name) == "blinn_phong_normalized_approx") {
                    approx_worst = std::max(approx_worst, a);
                    // at V = N the overshoot is exactly the ratio of the two factors
                    if (deg == 0.0) CHECK(a == Approx((n + 8.0) / 8.0 / exact_blinn_norm(n)).epsilon(1e-3));
                } else {
                    CHECK(a <= 1.0 + 1e-3);   // 1e-3: midpoint-rule error (measured ~1e-5 at V = N)
                    if (deg == 0.0) CHECK(a == Approx(1.0).epsilon(1e-3));   // normalised: exactly 1 at V = N
                }
            }
            std::cout << "\n";
        }
    }
    std::cout << "  (n+8)/8pi Blinn-Phong: largest lobe albedo on this grid " << approx_worst << "\n";
    CHECK(approx_worst > 1.05);
    CHECK(find_model("phong_normalized").energy_conserving);
    CHECK(find_model("blinn_phong_normalized").energy_conserving);
    CHECK_FALSE(find_model("blinn_phong_normalized_approx").energy_conserving);
    // The un-normalised forms are not energy conserving: at n = 0 the lobe alone gathers more than the
    // diffuse term, on top of a full Lambert term.
    for (const char* name : {"phong", "blinn_phong"}) {
        const Material m = make(name, {{"n", 0.0}, {"ks", 1.0}}, black, white);
        const double a = 1.0 + lobe_albedo(m, name[0] == 'b' ? Lobe::Blinn : Lobe::Phong, 0.0, view_at(0.0));
        INFO(name << " n 0 ks 1 albedo 1: directional albedo " << a);
        CHECK(a > 1.5);
        CHECK_FALSE(find_model(name).energy_conserving);
    }
    for (const char* name : {"phong_seed001", "blinn_phong_seed001"}) CHECK_FALSE(find_model(name).energy_conserving);
}

TEST_CASE("reciprocity: R(L).V == R(V).L - only the f_r forms (normalised) are reciprocal, as flagged", "[phong][physics]") {
    std::mt19937_64 g(4242);
    const glm::dvec3 Nz{0, 0, 1};
    double rr = 0.0;
    for (int i = 0; i < 10000; ++i) {
        const glm::dvec3 N = test::random_unit(g), L = test::random_unit(g), V = test::random_unit(g);
        const glm::dvec3 RL = 2.0 * glm::dot(N, L) * N - L, RV = 2.0 * glm::dot(N, V) * N - V;
        rr = std::max(rr, std::abs(glm::dot(RL, V) - glm::dot(RV, L)));
    }
    CHECK(rr <= 1e-15);
    auto asymmetry = [&](const Material& m) {
        std::mt19937_64 h(7);
        double worst = 0.0;
        for (int i = 0; i < 3000; ++i) {
            const glm::dvec3 L = test::random_above(h), V = test::random_above(h);
            const double a = ref::eval_material(Nz, L, V, {}, m).x / L.z, b = ref::eval_material(Nz, V, L, {}, m).x / V.z;
            worst = std::max(worst, std::abs(a - b) / std::max({a, b, 1e-300}));
        }
        return worst;
    };
    for (const char* name : {"phong", "phong_seed001", "phong_normalized", "blinn_phong", "blinn_phong_seed001",
                             "blinn_phong_normalized", "blinn_phong_normalized_approx"}) {
        const ModelInfo& info = find_model(name);
        for (double n : {0.0, 1.0, 32.0, 10000.0}) {
            std::map<std::string, double> p;
            if (info.params[0].name == "gloss") p = {{"gloss", 4.0 * n}, {"specular_power", 1.0}};
            else p = {{"n", n}, {"ks", 0.5}};
            const double a = asymmetry(make(name, p, {1, 1, 1}, {1, 1, 1}));
            INFO(name << " n " << n << ": max relative asymmetry of value/NoL " << a);
            if (info.reciprocal) CHECK(a < 1e-9);
            else if (n < 1000) CHECK(a > 1e-3);   // at n = 10000 the lobe is too narrow for random pairs to see
        }
    }
    // With ks = 0 the reference forms are Lambert, hence reciprocal: the flag describes the model's range.
    CHECK(asymmetry(make("phong", {{"ks", 0.0}}, {1, 1, 1}, {1, 1, 1})) < 1e-12);
}

TEST_CASE("normalised pack rejects nothing in range and the constants are computed on the host", "[phong][catalogue]") {
    for (const char* name : {"phong_normalized", "blinn_phong_normalized", "blinn_phong_normalized_approx"}) {
        for (double n : {0.0, 10000.0}) {
            const auto k = consts_of<PhongNormalizedConsts>(pack_material(make(name, {{"n", n}, {"ks", 1.0}}))[0]);
            INFO(name << " n " << n << " constants " << k.n << " " << k.kd << " " << k.lobe_scale);
            CHECK(std::isfinite(k.lobe_scale));
            CHECK(k.kd == 0.0f);            // 1 - ks
            CHECK(k.lobe_scale >= 1.0f);    // K_n >= 1: 1 at n = 0
        }
    }
    CHECK(consts_of<PhongNormalizedConsts>(pack_material(make("blinn_phong_normalized", {{"n", 0.0}, {"ks", 1.0}}))[0])
              .lobe_scale == 1.0f);
    CHECK(consts_of<PhongConsts>(pack_material(make("phong_seed001", {{"gloss", 128.0}}))[0]).n == 32.0f);
    CHECK_THROWS_AS(resolve_material([] { Material m; m.model = "phong"; m.params["n"] = 10001; return m; }()), Error);
}
