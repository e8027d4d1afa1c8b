// Cook-Torrance (kernels/models/cook_torrance.cl): in layers.
//   1. closed-form spot values (the lobe's peak, the mirror configuration) through the kernels;
//   2. each kernel against its double reference over a 100,000-triple sweep, on a grid of m and f0 that includes
//      both ends of each range, with an error bound derived from the conditioning of each input (stated below);
//   3. the terms: D normalised (Beckmann and GGX, kernel and reference), Schlick against the exact Fresnel
//      against Snell's law computed here, the seed's literal angle form;
//   4. physics: reciprocity (kernel and reference), white furnace of the specular lobe against m;
//   5. stability where the model breaks: grazing, the mirror configuration at the horizon, L = -V.
#include <catch2/catch.hpp>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "cl/runtime.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"
#include "support.hpp"

using namespace shadelab;
using glm::dvec3;

namespace {
const char* const kModels[] = {"cook_torrance", "cook_torrance_ggx", "cook_torrance_exact_fresnel",
                               "cook_torrance_seed004"};

Material ct(const std::string& model, double m, double f0, double kd = 0.0, double ks = 1.0,
            dvec3 specular = {1.0, 0.9, 0.8}) {
    Material mat;
    mat.model = model;
    mat.params = {{"m", m}, {"f0", f0}, {"kd", kd}, {"ks", ks}};
    mat.albedo = {0.6, 0.4, 0.2};
    mat.specular = specular;
    return resolve_material(mat);
}

// Direction triples built by hand, float as the kernel reads them and the same values in double.
struct Triples {
    std::vector<float> N, L, V, P;
    void add(const dvec3& n, const dvec3& l, const dvec3& v) {
        for (int c = 0; c < 3; ++c) {
            N.push_back(float(n[c]));
            L.push_back(float(l[c]));
            V.push_back(float(v[c]));
            P.push_back(0.0f);
        }
    }
    dvec3 at(const std::vector<float>& a, std::size_t i) const { return {a[3 * i], a[3 * i + 1], a[3 * i + 2]}; }
    std::size_t size() const { return N.size() / 3; }
};

// The kernel-vs-reference bound for one value (derivation above the sweep test below): the arithmetic itself,
// 2e-6 relative plus 1e-7 absolute (relative above 1), and four roundings' worth of the slope, which is only
// computed when the first part does not already cover the error.
double allowed(const dvec3& N, const dvec3& L, const dvec3& V, const Material& m, int c, double r, double e) {
    const double base = 2e-6 * std::abs(r) + 1e-7 * std::max(std::abs(r), 1.0);
    return e <= base ? base : base + 4.0 * 6e-8 * test::slope(N, L, V, m, c, r);
}
}  // namespace

// ---- 1. closed-form spot values ---------------------------------------------------------------------------

TEST_CASE("cook-torrance closed-form values: the lobe peak and the mirror configuration", "[cook_torrance][kernel]") {
    // L = V = N: VoH = NoH = 1, F = f0, D = 1/(pi m^2) for both distributions, G = 1, NoV = 1:
    //   value = kd albedo + ks specular f0 / (pi m^2).
    // Mirror configuration, V at theta from N and L mirrored (H = N): D = 1/(pi m^2), G = 1 (Gb = Gc = 2),
    //   value = ks specular F(cos theta) / (pi m^2 cos theta); with f0 = 1, F = 1.
    Shader shader(test::runtime());
    Triples t;
    const dvec3 N{0, 0, 1};
    t.add(N, N, N);
    for (double deg : {30.0, 60.0, 89.0}) {
        const double th = glm::radians(deg);
        t.add(N, {-std::sin(th), 0, std::cos(th)}, {std::sin(th), 0, std::cos(th)});
    }
    for (const char* model : {"cook_torrance", "cook_torrance_ggx", "cook_torrance_exact_fresnel"})
        for (double m : {0.02, 0.3, 1.0}) {
            const Material peak = ct(model, m, 0.04, 0.5, 0.7, {1, 1, 1});
            const auto o = shader.eval_directions(peak, t.N, t.L, t.V, t.P);
            INFO(model << " m " << m);
            CHECK(o[0] == Approx(0.5 * 0.6 + 0.7 * 0.04 / (M_PI * m * m)).epsilon(2e-6));
            const Material mirror = ct(model, m, 1.0, 0.0, 1.0, {1, 1, 1});
            const auto om = shader.eval_directions(mirror, t.N, t.L, t.V, t.P);
            for (std::size_t i = 1; i < t.size(); ++i) {
                const double cos_t = double(t.V[3 * i + 2]);
                INFO("mirror configuration, NoV " << cos_t);
                CHECK(om[3 * i] == Approx(1.0 / (M_PI * m * m * cos_t)).epsilon(2e-6));
            }
        }
}

// ---- 2. kernel against reference ---------------------------------------------------------------------------

// The bound. For each value, with r the reference and k the kernel:
//   |k - r| <= 2e-6 |r| + 1e-7 max(|r|, 1) ... the arithmetic itself (a few float roundings), plus
//              4 * 6e-8 * slope                 ... the rounding of the directions the kernel forms (test::slope:
//                                                   it carries the 1/NoV and 1/VoH factors, Beckmann's exponent
//                                                   with its 2 tan / (m^2 cos^2) slope near a narrow peak,
//                                                   Schlick's (1 - VoH)^5 at f0 = 0, ...).
// Within 2e-6 of the horizon (|NoL| or |NoV| < 2e-6, where a turn of 1e-6 rad would cross it) the value jumps
// from the lobe to 0 across NoV = 0 and either side is right: there only finiteness and sign are required.
// The sweep's relative error where the problem is plainly well conditioned (NoL, NoV >= 0.05, LoV > -0.95 and the
// value >= 1e-3 of the peak: the criterion of tests/test_precision.cpp) is printed beside it.
TEST_CASE("cook-torrance kernels match the double references over m and f0 grids including the range ends",
          "[cook_torrance][kernel]") {
    const auto sweep = test::make_sweep(100000, 31);
    std::cout << "cook-torrance kernel vs reference, " << sweep.size() << " triples: max rel over plainly conditioned "
              << "values; max abs; worst |k - r| / arithmetic part of the bound; number of values beyond it and the "
              << "worst of those in units of the full bound (<= 1 asserted)\n";
    struct Case {
        double m, f0, kd;
    };
    std::vector<Case> cases;
    for (double m : {0.02, 0.1, 0.3, 1.0})
        for (double f0 : {0.0, 0.04, 1.0}) cases.push_back({m, f0, 0.0});   // the lobe alone
    cases.push_back({0.3, 0.04, 1.0});                                       // defaults: diffuse + lobe
    for (const char* model : kModels)
        for (const Case& cs : cases) {
            const Material mat = ct(model, cs.m, cs.f0, cs.kd);
            const bool seed = std::string(model) == "cook_torrance_seed004";
            double peak = -1.0, rel = 0.0, over_base = 0.0;
            std::size_t beyond = 0;
            const auto e = test::check_kernel_against_reference(mat, [&](const test::Compared& v) {
                auto plain = [](const dvec3& N, const dvec3& L, const dvec3& V) {
                    return glm::dot(N, L) >= 0.05 && glm::dot(N, V) >= 0.05 && glm::dot(L, V) > -0.95;
                };
                if (peak < 0.0) {   // the largest plainly conditioned value, the scale of the printed max rel
                    peak = 0.0;
                    for (std::size_t i = 0; i < v.reference.size(); ++i)
                        if (plain(v.sweep.dN[i], v.sweep.dL[i], v.sweep.dV[i]))
                            peak = std::max({peak, std::abs(v.reference[i].x), std::abs(v.reference[i].y),
                                             std::abs(v.reference[i].z)});
                }
                if (std::abs(v.NoL()) < 2e-6 || std::abs(v.NoV()) < 2e-6) return test::kExempt;   // near the horizon
                if (plain(v.N(), v.L(), v.V()) && std::abs(v.r) >= 1e-3 * peak) rel = std::max(rel, v.err() / std::abs(v.r));
                const double base = allowed(v.N(), v.L(), v.V(), mat, v.c, v.r, 0.0);
                over_base = std::max(over_base, v.err() / base);
                if (v.err() > base) ++beyond;
                return allowed(v.N(), v.L(), v.V(), mat, v.c, v.r, v.err());
            }, {&sweep});
            std::cout << "  " << std::left << std::setw(28) << model << " m " << std::setw(5) << cs.m << " f0 "
                      << std::setw(5) << cs.f0 << " kd " << cs.kd << std::right << "  max rel " << std::setw(11)
                      << rel << "  max abs " << std::setw(11) << e.max_abs << "  arithmetic " << std::setw(9)
                      << over_base << "  beyond it " << std::setw(5) << beyond << ", worst " << e.worst_ratio << "\n";
            test::expect_within(e, sweep.size());
            // (the seed's literal Fresnel goes negative by itself past theta = 1 rad)
            if (!seed) CHECK(e.negative == 0);
            CHECK(e.exempt < 3 * sweep.size() / 10);   // the horizon exemption stays a thin band (< 10% of triples)
        }
}

// ---- 3. the terms ------------------------------------------------------------------------------------------

// D through the whole model: with L = V at angle theta from N, H = L = V, so VoH = 1 and F = f0 = 1 exactly
// (Schlick and the exact form alike), NoH = NoL = NoV = cos theta, and G / NoV = min(1, 2 cos^2 theta) / cos theta.
// So D(theta) = value * cos theta / min(1, 2 cos^2 theta), and 2 pi * integral of D cos sin d theta must be 1.
TEST_CASE("Beckmann and GGX are normalised: integral of D NoH over the hemisphere is 1 (kernel and reference)",
          "[cook_torrance][physics]") {
    Shader shader(test::runtime());
    const int n = 100000;   // midpoint rule in theta: spacing 1.6e-5 rad, 1/1300 of the narrowest lobe (m = 0.02)
    Triples t;
    const dvec3 N{0, 0, 1};
    for (int i = 0; i < n; ++i) {
        const double th = (i + 0.5) / n * (M_PI / 2);
        const dvec3 W{std::sin(th), 0, std::cos(th)};
        t.add(N, W, W);
    }
    std::cout << "normalisation of D, 2 pi int D cos sin d theta (kernel / reference):\n";
    for (const char* model : {"cook_torrance", "cook_torrance_ggx"})
        for (double m : {0.02, 0.05, 0.1, 0.3, 0.6, 1.0}) {
            const Material mat = ct(model, m, 1.0, 0.0, 1.0, {1, 1, 1});
            const auto o = shader.eval_directions(mat, t.N, t.L, t.V, t.P);
            double ik = 0.0, ir = 0.0;
            for (int i = 0; i < n; ++i) {
                const dvec3 W = t.at(t.L, std::size_t(i));
                const double c = W.z, s = W.x;   // the float direction's own cosine and sine
                const double g_over = std::min(1.0, 2.0 * c * c) / c;
                const double w = 2.0 * M_PI * c * s * (M_PI / 2) / n;
                ik += double(o[3 * std::size_t(i)]) / g_over * w;
                ir += ref::eval_material(N, W, W, {}, mat).x / g_over * w;
            }
            std::cout << "  " << std::setw(18) << model << " m " << std::setw(4) << m << ": " << std::setprecision(8)
                      << ik << " / " << ir << std::setprecision(6) << "\n";
            INFO(model << " m " << m);
            CHECK(ik == Approx(1.0).epsilon(1e-5));
            CHECK(ir == Approx(1.0).epsilon(1e-5));
        }
}

// Schlick against the exact Fresnel term. In the mirror configuration (V at theta, L mirrored, H = N) D, G and
// NoV are the same for every model and known, so F = value * pi m^2 cos theta (kd = 0, specular 1). The exact
// kernel (CT's g-form with 1/eta) is checked against Snell's law and the s/p reflectances written here.
TEST_CASE("Fresnel: Schlick against the exact dielectric term against Snell's law and the seed's angle form",
          "[cook_torrance]") {
    Shader shader(test::runtime());
    Triples t;
    const dvec3 N{0, 0, 1};
    const double degs[] = {0, 15, 30, 45, 60, 70, 75, 80, 84, 87, 89, 89.9};
    for (double d : degs) {
        const double th = glm::radians(d);
        t.add(N, {-std::sin(th), 0, std::cos(th)}, {std::sin(th), 0, std::cos(th)});
    }
    const double m = 0.3;
    auto fresnel_of = [&](const char* model, double f0) {
        const auto o = shader.eval_directions(ct(model, m, f0, 0.0, 1.0, {1, 1, 1}), t.N, t.L, t.V, t.P);
        std::vector<double> F;
        for (std::size_t i = 0; i < t.size(); ++i) F.push_back(double(o[3 * i]) * M_PI * m * m * double(t.V[3 * i + 2]));
        return F;
    };
    // Snell: sin t = sin i / eta; r_s = (cos i - eta cos t)^2 / (cos i + eta cos t)^2, r_p likewise, F = mean.
    auto snell = [](double c, double f0) {
        const double eta = (1 + std::sqrt(f0)) / (1 - std::sqrt(f0));
        const double st = std::sqrt(1 - c * c) / eta, cti = std::sqrt(1 - st * st);
        const double rs = (c - eta * cti) / (c + eta * cti), rp = (cti - eta * c) / (cti + eta * c);
        return 0.5 * (rs * rs + rp * rp);
    };
    auto schlick = [](double c, double f0) { return f0 + (1 - f0) * std::pow(1 - c, 5.0); };
    std::cout << "Fresnel at VoH = cos theta (kernels, mirror configuration): Schlick / exact / seed's (1 - theta)^5\n";
    std::cout << "  f0     " << std::fixed << std::setprecision(1);
    for (double d : degs) std::cout << std::setw(21) << d;
    std::cout << " deg\n" << std::defaultfloat << std::setprecision(6);
    for (double f0 : {0.0, 0.02, 0.04, 0.1, 0.5, 0.9}) {
        const auto fs = fresnel_of("cook_torrance", f0), fe = fresnel_of("cook_torrance_exact_fresnel", f0),
                   fseed = fresnel_of("cook_torrance_seed004", f0);
        std::cout << "  " << std::setw(5) << f0 << std::setprecision(4);
        double max_abs_diff = 0.0;
        for (std::size_t i = 0; i < t.size(); ++i) {
            std::cout << "  " << std::setw(5) << fs[i] << "/" << std::setw(6) << fe[i] << "/" << std::setw(7) << fseed[i];
            const double c = double(t.V[3 * i + 2]);
            INFO("f0 " << f0 << " theta " << degs[i] << " deg, VoH " << c);
            CHECK(fs[i] == Approx(schlick(c, f0)).epsilon(2e-6).margin(1e-7));
            if (f0 > 0.0) CHECK(fe[i] == Approx(snell(c, f0)).epsilon(2e-6).margin(1e-7));
            else CHECK(std::abs(fe[i]) < 1e-12);   // no interface: eta = 1 reflects nothing (Schlick: (1 - c)^5)
            // The seed's reading: F = 1 at theta = 0 (not f0), then (1 - theta)^5 with theta in radians.
            const double theta = glm::radians(degs[i]);
            CHECK(fseed[i] == Approx(f0 + (1 - f0) * std::pow(1 - theta, 5.0)).epsilon(1e-5).margin(1e-6));
            max_abs_diff = std::max(max_abs_diff, std::abs(fs[i] - fe[i]));
        }
        std::cout << std::setprecision(6) << "   max |Schlick - exact| " << max_abs_diff << "\n";
        CHECK(fs[0] == Approx(f0).margin(1e-7));   // both equal f0 at normal incidence
        CHECK(fe[0] == Approx(f0).margin(1e-7));
        CHECK(fseed[0] == Approx(1.0).epsilon(1e-6));
        // Over 0..89.9 deg, worked out by hand from the two formulas (at 0.1 deg steps): Schlick is within 0.036
        // of the exact term for glass-like f0 = 0.04 and within 0.06 for f0 = 0.02 (water); for f0 >= 0.5 the
        // dielectric with that eta has a deep Brewster dip near grazing that Schlick does not follow.
        if (f0 == 0.04) CHECK(max_abs_diff < 0.036);
        if (f0 == 0.02) CHECK(max_abs_diff < 0.061);
        if (f0 == 0.9) CHECK(max_abs_diff > 0.3);
    }
    // f0 = 1 is a perfect mirror in both forms: F = 1 at every angle.
    const auto one_s = fresnel_of("cook_torrance", 1.0), one_e = fresnel_of("cook_torrance_exact_fresnel", 1.0);
    for (std::size_t i = 0; i < t.size(); ++i) {
        CHECK(one_s[i] == Approx(1.0).epsilon(2e-6));
        CHECK(one_e[i] == Approx(1.0).epsilon(2e-6));
    }
}

// ---- 4. physics --------------------------------------------------------------------------------------------

// f_r(L, V) = f_r(V, L): value(L, V) / NoL = value(V, L) / NoV. The reference to 1e-12 everywhere the lobe is
// defined; the kernel (two launches with L and V swapped) within the sweep's bound applied to both sides.
TEST_CASE("cook-torrance is reciprocal: kernel and reference", "[cook_torrance][physics]") {
    const auto sweep = test::make_sweep(100000, 77);
    Shader shader(test::runtime());
    for (const char* model : kModels)
        for (double m : {0.02, 0.3, 1.0}) {
            const Material mat = ct(model, m, 0.04, 1.0);
            const auto a = shader.eval_directions(mat, sweep.N, sweep.L, sweep.V, sweep.P);
            const auto b = shader.eval_directions(mat, sweep.N, sweep.V, sweep.L, sweep.P);
            double worst_ref = 0.0, worst_kernel = 0.0;
            std::size_t compared = 0, worst = 0;
            for (std::size_t i = 0; i < sweep.size(); ++i) {
                const dvec3 &N = sweep.dN[i], &L = sweep.dL[i], &V = sweep.dV[i];
                // The cosines of the unit directions (the inputs are float-rounded, |L| = 1 +- 6e-8).
                const double NoL = glm::dot(N, L) / (glm::length(N) * glm::length(L)),
                             NoV = glm::dot(N, V) / (glm::length(N) * glm::length(V));
                if (NoL < 1e-3 || NoV < 1e-3) continue;   // the reciprocity quotient divides by NoL, NoV
                const double ra = ref::eval_material(N, L, V, {}, mat).x, rb = ref::eval_material(N, V, L, {}, mat).x;
                const double fa = ra / NoL, fb = rb / NoV;
                worst_ref = std::max(worst_ref, std::abs(fa - fb) / std::max(fa, fb));
                const double ka = a[3 * i] / NoL, kb = b[3 * i] / NoV;
                // Each side may be off its reference by the kernel-vs-reference bound.
                const double ea = std::abs(a[3 * i] - ra), eb = std::abs(b[3 * i] - rb);
                const double tol = allowed(N, L, V, mat, 0, ra, ea) / NoL + allowed(N, V, L, mat, 0, rb, eb) / NoV;
                const double q = std::abs(ka - kb) / tol;
                if (q > worst_kernel) { worst_kernel = q; worst = i; }
                ++compared;
            }
            std::cout << "reciprocity " << std::setw(28) << model << " m " << std::setw(4) << m
                      << ": reference max rel asymmetry " << worst_ref << ", kernel worst in units of the bound "
                      << worst_kernel << " (" << compared << " triples)\n";
            INFO(model << " m " << m << " worst triple " << worst << " (" << sweep.kind[worst] << ")");
            CHECK(compared > 20000);
            CHECK(worst_ref < 1e-12);
            CHECK(worst_kernel <= 1.0);
        }
}

// White furnace of the specular lobe alone, F = 1 (f0 = 1), specular colour 1, kd = 0:
//   albedo(V) = (1/pi) integral of value dL = (1/pi) integral of value(L(H)) 4 VoH dH,
// integrated over the half vector (midpoint rule in theta_h, phi_h) so narrow lobes are resolved.
// V-groove G = min(G1(V), G1(L)) with G1(V) = min(1, 2 NoH NoV / VoH), and the V-cavity G1 meets the projected-area
// condition integral of D G1(V) VoH dH = NoV (Heitz 2014, "Understanding the masking-shadowing function"), so with
// today's 4 NoL NoV denominator the albedo is <= 1; the 1982 pi NoL NoV makes it up to 4/pi = 1.27 times that.
TEST_CASE("cook-torrance white furnace: directional albedo of the specular lobe against roughness and view",
          "[cook_torrance][physics]") {
    // The furnace of tests/support.hpp on its half-vector grid, 1500 x 256, red channel (specular colour 1).
    test::Furnace f;
    f.grid = test::Furnace::Grid::half_vector;
    f.n_theta = 1500;
    f.n_phi = 256;
    auto albedo = [&](const Material& mat, double view_deg) { return test::furnace_reference(mat, test::at_angle(view_deg), f, 0); };
    const double views[] = {0.0, 45.0, 70.0, 80.0, 89.0};
    std::cout << "white furnace, specular lobe (F = 1, kd = 0): directional albedo with the 1982 pi NoL NoV at view "
                 "0/45/70/80/89 deg; [x pi/4 = today's 4 NoL NoV]\n";
    double max_1982 = 0.0;
    for (const char* model : {"cook_torrance", "cook_torrance_ggx"})
        for (double m : {0.02, 0.1, 0.3, 0.6, 1.0}) {
            const Material mat = ct(model, m, 1.0, 0.0, 1.0, {1, 1, 1});
            std::cout << "  " << std::left << std::setw(18) << model << " m " << std::setw(5) << m << std::right
                      << std::setprecision(4);
            std::vector<double> a;
            for (double deg : views) {
                a.push_back(albedo(mat, deg));
                std::cout << std::setw(8) << a.back();
            }
            std::cout << "   [";
            for (double x : a) std::cout << std::setw(8) << x * M_PI / 4;
            std::cout << " ]\n" << std::setprecision(6);
            for (std::size_t k = 0; k < a.size(); ++k) {
                INFO(model << " m " << m << " view " << views[k] << " deg: albedo " << a[k]);
                CHECK(std::isfinite(a[k]));
                CHECK(a[k] > 0.0);
                CHECK(a[k] * M_PI / 4 <= 1.0 + 2e-3);   // 2e-3: quadrature error at 1500 x 256
                max_1982 = std::max(max_1982, a[k]);
            }
        }
    // The published pi form is not energy-conserving (the flag says so): it exceeds 1, by up to 4/pi.
    CHECK(max_1982 > 1.2);
    // The same integral over the kernel's values, for one lobe: the furnace is a property of the kernel too.
    {
        const Material mat = ct("cook_torrance", 0.3, 1.0, 0.0, 1.0, {1, 1, 1});
        const double ak = test::furnace_kernel(mat, {test::at_angle(45.0)}, f, 0)[0], ar = albedo(mat, 45.0);
        std::cout << "  furnace m 0.3, view 45 deg: kernel " << ak << ", reference " << ar << "\n";
        CHECK(ak == Approx(ar).epsilon(1e-5));
    }
}

// ---- 5. stability ------------------------------------------------------------------------------------------

// Where the model breaks: f_s = F D G / (pi NoL NoV). The kernel forms G / NoV = min(min(1, k NoL) / NoV, k),
// k = 2 NoH / VoH, so masking bounds it by k. In the mirror configuration at the horizon (L -> -V along the
// surface) H = N, VoH = NoV and G = 1: the value is F D / NoV and grows without bound - the published model's
// own singularity. The cases, all with N = +z so every dot product below is exact in float:
TEST_CASE("cook-torrance at its failure points: finite, equal to the reference, zero where undefined",
          "[cook_torrance][stability]") {
    Shader shader(test::runtime());
    Triples t;
    std::vector<std::string> what;
    const dvec3 N{0, 0, 1};
    auto add = [&](const dvec3& l, const dvec3& v, const std::string& w) { t.add(N, l, v); what.push_back(w); };
    for (double eps : {1e-2, 1e-4, 1e-6, 1e-7}) {
        std::ostringstream s;
        s << "mirror at the horizon, NoV = sin " << eps;
        add({-std::cos(eps), 0, std::sin(eps)}, {std::cos(eps), 0, std::sin(eps)}, s.str());
        std::ostringstream g;
        g << "grazing view " << eps << ", light at 30 deg";
        add({-0.5, 0, std::sqrt(0.75)}, {std::cos(eps), 0, std::sin(eps)}, g.str());
        std::ostringstream h;
        h << "grazing light " << eps << ", view at 30 deg";
        add({std::cos(eps), 0, std::sin(eps)}, {-0.5, 0, std::sqrt(0.75)}, h.str());
    }
    add({-1, 0, 0}, {1, 0, 0}, "L = -V on the horizon (H undefined)");
    add({0.6, 0, 0.8}, {-0.6, 0, -0.8}, "L = -V, view below");
    add({0, 0, 1}, {1, 0, 0}, "NoV = 0 exactly");
    add({1, 0, 0}, {0, 0, 1}, "NoL = 0 exactly");
    add({0.6, 0, 0.8}, {0.6, 0, -0.8}, "view below the surface");
    add({0.6, 0, -0.8}, {0.6, 0, 0.8}, "light below the surface");
    add({std::cos(0.005), 0, std::sin(0.005)}, {0, std::cos(0.005), std::sin(0.005)},
        "H near the horizon (NoH = 0.005)");
    add({0, 0, 1}, {0, 0, 1}, "L = V = N");
    for (const char* model : kModels)
        for (double m : {0.02, 0.3}) {
            const Material mat = ct(model, m, 0.04, 0.0, 1.0, {1, 1, 1});
            const auto out = shader.eval_directions(mat, t.N, t.L, t.V, t.P);
            std::cout << model << " m " << m << ":";
            for (std::size_t i = 0; i < t.size(); ++i) {
                const dvec3 l = t.at(t.L, i), v = t.at(t.V, i);
                const double k = out[3 * i], r = ref::eval_material(N, l, v, {}, mat).x;
                if (i < 12 && i % 3 == 0) std::cout << "  mirror, NoV " << v.z << ": " << k;
                INFO(model << " m " << m << ", " << what[i] << ": kernel " << k << ", reference " << r);
                CHECK(std::isfinite(k));
                CHECK(std::abs(k - r) <= 1e-5 * std::abs(r) + 1e-7);
                const dvec3 s = l + v;
                if (l.z > 0 && v.z > 0 && glm::dot(s, s) > 1e-12) {
                    // F <= 1, D <= 1/(pi m^2), G / NoV <= 2 NoH / VoH.
                    const dvec3 h = glm::normalize(s);
                    CHECK(k <= (1.0 / (M_PI * m * m)) * 2.0 * h.z / glm::dot(v, h) * (1 + 1e-5));
                } else {
                    CHECK(k == 0.0);
                }
            }
            std::cout << "\n";
        }
}


