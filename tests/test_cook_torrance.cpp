// Cook-Torrance: kernel vs reference over parameter grids, the distributions' normalisation, Fresnel forms,
// the grazing singularity, white furnace.
#include <catch2/catch.hpp>

#include <cmath>
#include <iomanip>
#include <iostream>

#include "cl/runtime.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"
#include "sweep.hpp"

using namespace shadelab;

namespace {
Runtime& runtime() {
    static Runtime rt;
    return rt;
}

Material ct(const std::string& model, double m, double f0, double kd = 1.0, double ks = 1.0) {
    Material mat;
    mat.model = model;
    mat.params = {{"m", m}, {"f0", f0}, {"kd", kd}, {"ks", ks}};
    mat.albedo = {0.6, 0.4, 0.2};
    mat.specular = {1.0, 0.9, 0.8};
    return resolve_material(mat);
}
}  // namespace

TEST_CASE("cook-torrance kernels match the double references over roughness and f0 grids", "[cook_torrance][kernel]") {
    const auto sweep = test::make_sweep(100000, 31);
    Shader shader(runtime());
    std::cout << "cook-torrance kernel vs reference, 100k triples\n";
    for (const char* model : {"cook_torrance", "cook_torrance_ggx", "cook_torrance_exact_fresnel", "cook_torrance_seed004"})
        for (double m : {0.02, 0.3, 1.0})
            for (double f0 : {0.0, 0.04, 0.99}) {
                const Material mat = ct(model, m, f0);
                const auto out = shader.eval_directions(mat, sweep.N, sweep.L, sweep.V, sweep.P);
                std::vector<glm::dvec3> ref(sweep.size());
                double peak = 0.0;
                for (std::size_t i = 0; i < sweep.size(); ++i) {
                    ref[i] = ref::eval_material(sweep.dN[i], sweep.dL[i], sweep.dV[i], sweep.dP[i], mat);
                    peak = std::max({peak, ref[i].x, ref[i].y, ref[i].z});
                }
                // Error in units of what float rounding of the inputs (~6e-8 on each dot product) can do to this
                // model: 1/min(NoL, NoV, VoH) from the 1/NoV and 1/VoH factors, 2/(m^2 NoH^3) from the slope of
                // Beckmann's (and GGX's) exponent at roughness m, and 1e-6 relative plus 1e-7 absolute for the
                // arithmetic itself. `rel` is the plain relative error where NoL, NoV >= 0.05.
                double rel = 0.0, units = 0.0;
                std::size_t nonfinite = 0, worst = 0, negative = 0;
                for (std::size_t i = 0; i < sweep.size(); ++i) {
                    const double NoL = glm::dot(sweep.dN[i], sweep.dL[i]), NoV = glm::dot(sweep.dN[i], sweep.dV[i]);
                    const glm::dvec3 sum = sweep.dL[i] + sweep.dV[i];
                    const glm::dvec3 H = glm::length(sum) > 1e-9 ? glm::normalize(sum) : sweep.dN[i];
                    const double NoH = std::max(glm::dot(sweep.dN[i], H), 1e-3), VoH = std::abs(glm::dot(sweep.dV[i], H));
                    const double amplify = 1.0 / std::max(std::min({std::abs(NoL), std::abs(NoV), VoH}), 1e-7) +
                                           2.0 / (m * m * NoH * NoH * NoH);
                    // Within float rounding of the horizon (|NoL| or |NoV| < 1e-6) the float and double dot
                    // products may fall on opposite sides of 0, where the model jumps from its specular value
                    // to 0: either side is right there, so only finiteness and sign are required.
                    const bool horizon = std::abs(NoL) < 1e-6 || std::abs(NoV) < 1e-6;
                    for (int c = 0; c < 3; ++c) {
                        const double k = out[3 * i + std::size_t(c)], r = ref[i][c];
                        if (!std::isfinite(k)) { ++nonfinite; continue; }
                        // (the seed's literal Fresnel goes negative by itself: no sign check for it)
                        if (horizon) { negative += (k < 0.0 && std::string(model) != "cook_torrance_seed004") ? 1 : 0; continue; }
                        const double e = std::abs(k - r);
                        if (NoL >= 0.05 && NoV >= 0.05 && r > 1e-6) rel = std::max(rel, e / r);
                        const double u = e / (std::abs(r) * (6e-8 * amplify + 1e-6) + 1e-7);
                        if (u > units) { units = u; worst = i; }
                    }
                }
                std::cout << "  " << std::left << std::setw(28) << model << " m " << std::setw(5) << m << " f0 "
                          << std::setw(5) << f0 << std::right << " rel (NoL, NoV >= 0.05) " << std::setw(11) << rel
                          << "  worst in rounding units " << units << "\n";
                INFO(model << " m " << m << " f0 " << f0 << ": worst triple " << worst << " (" << sweep.kind[worst] << ")");
                CHECK(nonfinite == 0);
                CHECK(negative == 0);
                CHECK(units < 8.0);
            }
}

TEST_CASE("Beckmann and GGX distributions are normalised: integral of D(h) NoH over the hemisphere is 1", "[cook_torrance][physics]") {
    // D depends on theta_h only: integral = 2 pi * int_0^{pi/2} D(theta) cos(theta) sin(theta) d theta, evaluated
    // with the reference through the model (kd = 0, and F = 1 needs f0 = 1, out of range): instead integrate D
    // directly from its closed form, as written in the paper.
    auto beckmann = [](double c, double m) { const double t2 = (1 - c * c) / (c * c); return std::exp(-t2 / (m * m)) / (M_PI * m * m * c * c * c * c); };
    auto ggx = [](double c, double m) { const double d = c * c * (m * m - 1) + 1; return m * m / (M_PI * d * d); };
    for (double m : {0.05, 0.1, 0.3, 0.6, 1.0}) {
        double ib = 0.0, ig = 0.0;
        const int n = 200000;
        for (int i = 0; i < n; ++i) {
            const double th = (i + 0.5) / n * (M_PI / 2);
            const double w = std::cos(th) * std::sin(th) * (M_PI / 2) / n * 2 * M_PI;
            ib += beckmann(std::cos(th), m) * w;
            ig += ggx(std::cos(th), m) * w;
        }
        std::cout << "normalisation m " << m << ": Beckmann " << ib << ", GGX " << ig << "\n";
        INFO("m " << m);
        CHECK(ib == Approx(1.0).epsilon(1e-4));
        CHECK(ig == Approx(1.0).epsilon(1e-4));
    }
}

TEST_CASE("Schlick against the exact dielectric Fresnel - the seed's literal angle form departs", "[cook_torrance]") {
    // Through the kernels: V = N, L at angle 2a from N gives VoH = cos a; kd = 0, m = 1 (broad lobe).
    Shader shader(runtime());
    std::vector<float> N, L, V, P;
    std::vector<double> angles;
    for (int d = 0; d <= 88; d += 4) {
        const double a = glm::radians(double(d)) / 2.0;   // half angle: VoH = cos(a)
        N.insert(N.end(), {0, 0, 1});
        V.insert(V.end(), {0, 0, 1});
        L.insert(L.end(), {float(std::sin(2 * a)), 0, float(std::cos(2 * a))});
        P.insert(P.end(), {0, 0, 0});
        angles.push_back(a);
    }
    const auto schlick = shader.eval_directions(ct("cook_torrance", 1.0, 0.04, 0.0), N, L, V, P);
    const auto exact = shader.eval_directions(ct("cook_torrance_exact_fresnel", 1.0, 0.04, 0.0), N, L, V, P);
    const auto seed = shader.eval_directions(ct("cook_torrance_seed004", 1.0, 0.04, 0.0), N, L, V, P);
    double max_rel = 0.0;
    for (std::size_t i = 0; i < angles.size(); ++i) {
        const double r = std::abs(schlick[3 * i] - exact[3 * i]) / exact[3 * i];
        max_rel = std::max(max_rel, r);
        CHECK(std::isfinite(seed[3 * i]));
    }
    std::cout << "Schlick vs exact dielectric Fresnel (f0 = 0.04), VoH from cos 0 to cos 44 deg: max relative difference "
              << max_rel << "\n";
    // Schlick under-estimates a glass-like dielectric by up to 15% at VoH = cos 44 deg (exact 0.049, Schlick
    // 0.042 by hand); the bound is set just above that.
    CHECK(max_rel < 0.2);
    CHECK(schlick[0] == Approx(exact[0]).epsilon(1e-5));   // equal at normal incidence, both f0
    // The seed's literal (1 - theta)^5 with theta the angle gives F = 1 at normal incidence (theta = 0), not f0:
    // the reading turns Fresnel upside down. So the seed variant is schlick / f0 there.
    CHECK(seed[0] == Approx(schlick[0] / 0.04).epsilon(1e-4));
}

// Where the singularity is: f_s = F D G / (pi NoL NoV). Where G < 1 (masking), G / NoV <= 2 NoH / VoH
// cancels the 1/NoV; but for light and view both grazing on opposite sides (L -> -V at the horizon) H -> N,
// VoH -> NoV, G = 1 and the value grows as 1/NoV: the 1982 model's own singularity. The kernel evaluates the
// formula as written in that regime (finite for NoV > 0, 0 for NoV <= 0), and never divides by a vanishing NoV
// elsewhere; both are checked against the double reference and the bound value <= F D 2 NoH / VoH.
TEST_CASE("cook-torrance at grazing angles: finite, equal to the reference, within the masking bound", "[cook_torrance][stability]") {
    Shader shader(runtime());
    std::vector<float> N, L, V, P;
    for (double eps : {1e-2, 1e-4, 1e-6, 1e-8, 0.0})
        for (double lth : {0.0, 1.2, M_PI / 2 - eps}) {
            N.insert(N.end(), {0, 0, 1});
            V.insert(V.end(), {float(std::cos(eps)), 0, float(std::sin(eps))});
            L.insert(L.end(), {float(-std::sin(lth)), 0, float(std::cos(lth))});
            P.insert(P.end(), {0, 0, 0});
        }
    for (const char* model : {"cook_torrance", "cook_torrance_ggx", "cook_torrance_exact_fresnel"}) {
        const Material mat = ct(model, 0.3, 0.04, 0.0);
        const auto out = shader.eval_directions(mat, N, L, V, P);
        for (std::size_t i = 0; i < out.size() / 3; ++i) {
            const glm::dvec3 n{N[3 * i], N[3 * i + 1], N[3 * i + 2]}, l{L[3 * i], L[3 * i + 1], L[3 * i + 2]},
                v{V[3 * i], V[3 * i + 1], V[3 * i + 2]};
            const double r = ref::eval_material(n, l, v, {}, mat).x;
            INFO(model << " case " << i << ": kernel " << out[3 * i] << ", reference " << r);
            CHECK(std::isfinite(out[3 * i]));
            CHECK(std::abs(out[3 * i] - r) <= 1e-4 * std::max(1.0, r));
            const glm::dvec3 s = l + v;
            if (glm::dot(n, l) > 0 && glm::dot(n, v) > 0 && glm::length(s) > 1e-6) {
                const glm::dvec3 h = glm::normalize(s);
                const double bound = 1.0 / (M_PI * 0.09) * 2.0 * glm::dot(n, h) / glm::dot(v, h);   // F <= 1, D <= 1/(pi m^2)
                CHECK(out[3 * i] <= bound * (1 + 1e-5));
            } else {
                CHECK(out[3 * i] == 0.0f);
            }
        }
    }
}

TEST_CASE("cook-torrance white furnace: directional albedo of the specular lobe against roughness", "[cook_torrance][physics]") {
    std::cout << "directional albedo of the specular lobe (kd = 0, f0 = 0.99 ~ F = 1), reference, by view angle\n";
    for (const char* model : {"cook_torrance", "cook_torrance_ggx"}) {
        for (double m : {0.1, 0.3, 0.6, 1.0}) {
            const Material mat = ct(model, m, 0.99, 0.0, 1.0);
            std::cout << "  " << std::left << std::setw(20) << model << " m " << std::setw(4) << m << std::right;
            for (double deg : {0.0, 45.0, 80.0}) {
                const double t = glm::radians(deg);
                const glm::dvec3 V{std::sin(t), 0, std::cos(t)}, Nn{0, 0, 1};
                const int n = 400;
                double sum = 0.0;
                for (int i = 0; i < n; ++i)
                    for (int j = 0; j < 2 * n; ++j) {
                        const double ct_ = (i + 0.5) / n, st = std::sqrt(1 - ct_ * ct_), ph = M_PI * (j + 0.5) / n;
                        sum += ref::eval_material(Nn, {st * std::cos(ph), st * std::sin(ph), ct_}, V, {}, mat).x;
                    }
                const double albedo = sum * (1.0 / n) * (M_PI / n) / M_PI / 1.0;   // specular colour r = 1
                std::cout << std::setw(10) << std::setprecision(4) << albedo;
                CHECK(std::isfinite(albedo));
                CHECK(albedo > 0.0);
                CHECK(albedo < 1.3);
                // The 1982 form's pi NoL NoV (not today's 4 NoL NoV) makes a narrow lobe at normal incidence
                // reflect 4/pi = 1.27 times the energy, times F (~0.99 at f0 = 0.99): the white furnace shows it.
                // (GGX keeps 0.97 of it: its long tails lose more to masking; Beckmann 0.99.)
                if (m == 0.1 && deg == 0.0) CHECK(albedo / (4.0 / M_PI) == Approx(0.98).margin(0.02));
            }
            std::cout << "\n";
        }
    }
}
