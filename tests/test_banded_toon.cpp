// Banded lighting and toon shading: the kernels against the double references over the sphere and a
// parameter grid. Quantisers are discontinuous, so a float input within a few ulps of a band edge may
// land in the neighbouring band: such mismatches are counted and each must be (a) within a few ulps of an
// edge, measured from the double reference's own NoL / NoH, and (b) at most the jump at that edge. Also:
// the band rules by hand, the seed's formula vs the intended one, directional albedo, flags, edge cases.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "cl/runtime.hpp"
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

// Float error bounds of the quantisers' inputs (u = 2^-24): NoL = dot in float, <= 3u, plus the
// quantiser's own arithmetic before the floor (NoL steps + 1/2, or (256 NoL + t/2) / t: <= ~3u in NoL
// units): 8u. NoH (see test_phong.cpp): 12u, plus the power's rounding mapped back to NoH: 16u.
constexpr double kU = 0x1p-24;
constexpr double kDeltaNoL = 8 * kU;
constexpr double kDeltaNoH = 16 * kU;
// Away from edges a level is a sum of a few float constants times the colour: a few ulps.
constexpr double kTightRel = 2e-6;

glm::dvec3 light_at(double x) { return {std::sqrt(std::max(0.0, 1.0 - x * x)), 0.0, x}; }

// Distance of x from the nearest point of the lattice (k + offset) * step.
double lattice_distance(double x, double step, double offset) {
    const double q = x / step - offset;
    return std::abs(q - std::round(q)) * step;
}

// Triples placed on the band edges: NoL = e + k u (k = -4..4) for each NoL edge e, and NoH = e + k u for
// each NoH edge (H at that angle from N, L and V mirrored about H), in random orientations, so the float
// rounding of the vectors and of the kernel's dot products scatters them to both sides of the edge.
test::DirectionSweep edge_sweep(const std::vector<double>& nol_edges, const std::vector<double>& noh_edges,
                                std::size_t per_edge) {
    std::mt19937_64 g(2024);
    test::DirectionSweep s;
    auto push = [&](const glm::dvec3& n, const glm::dvec3& l, const glm::dvec3& v, const char* kind) {
        test::add_triple(s, n, l, v, glm::dvec3(0.0), kind);
    };
    for (double e : nol_edges)
        for (std::size_t k = 0; k < per_edge; ++k) {
            const double x = std::clamp(e + double(int(k % 9) - 4) * kU, -1.0, 1.0);
            const glm::dvec3 n = test::random_unit(g);
            push(n, test::at_angle(n, std::acos(x), g), test::random_unit(g), "NoL on an edge");
        }
    for (double e : noh_edges)
        for (std::size_t k = 0; k < per_edge; ++k) {
            const double x = std::clamp(e + double(int(k % 9) - 4) * kU, -1.0, 1.0);
            const glm::dvec3 n = test::random_unit(g);
            const glm::dvec3 h = test::at_angle(n, std::acos(x), g);
            const glm::dvec3 l = test::at_angle(h, 1.2 * test::unit_double(g), g);
            push(n, l, 2.0 * glm::dot(l, h) * h - l, "NoH on an edge");
        }
    return s;
}

}  // namespace

TEST_CASE("banded kernels match the reference - mismatches only within a few ulps of a band edge",
          "[banded_toon][kernel]") {
    std::cout << "banded kernels vs double reference, " << test::sweep().size() << " sweep triples + 9000 placed on band "
              << "edges (edge = within " << kDeltaNoL << " of a band edge in NoL):\n";
    std::vector<Material> grid;
    for (double s : {1.0, 2.0, 3.0, 4.0, 7.0, 100.0, 255.0, 256.0}) grid.push_back(make("banded", {{"steps", s}}));
    for (double t : {1.0, 2.0, 3.0, 64.0, 100.0, 170.0, 255.0, 256.0})
        grid.push_back(make("banded_seed001", {{"light_steps", t}}));
    for (const Material& m : grid) {
        const bool seed = m.model == "banded_seed001";
        const double p = seed ? m.params.at("light_steps") : m.params.at("steps");
        const double step = seed ? p / 256.0 : 1.0 / p;   // level spacing = edge spacing in NoL
        std::vector<double> edges;   // up to 10 edges spread over [0, 1]
        const int count = int(std::floor((1.0 - 0.5 * step) / step)) + 1;
        for (int j = 0; j < count; j += std::max(1, count / 10)) edges.push_back((j + 0.5) * step);
        const test::DirectionSweep on_edges = edge_sweep(edges, {}, 9000 / edges.size());
        std::size_t mismatches = 0;
        double max_dist = 0.0, max_err_off_edge = 0.0;
        // Within a few ulps of the reference's level; or, next to an edge only, one band up or down: off the
        // reference by the jump (albedo step) to within the same few ulps.
        const auto e = test::check_kernel_against_reference(m, [&](const test::Compared& v) {
            // edges: NoL = (j + 1/2) / steps, or (m - 1/2) t / 256 for the seed: the same lattice
            const double dist = lattice_distance(std::max(0.0, v.NoL()), step, 0.5);
            const double jump = m.albedo[v.c] * step, tol = kTightRel * std::max(std::abs(v.r), jump);
            if (v.err() <= tol) {
                if (dist > kDeltaNoL) max_err_off_edge = std::max(max_err_off_edge, v.err());
                return tol;
            }
            ++mismatches;
            max_dist = std::max(max_dist, dist);
            return dist <= kDeltaNoL && std::abs(v.err() - jump) <= tol ? jump + tol : tol;
        }, {&test::sweep(), &on_edges});
        std::cout << "  " << std::left << std::setw(30) << test::describe(m, true) << std::right << " mismatching values "
                  << std::setw(3) << mismatches << " (farthest from an edge: " << max_dist / kU
                  << " u), max error elsewhere " << max_err_off_edge << "\n";
        test::expect_within(e, test::sweep().size());
    }
}

TEST_CASE("banded rule by hand: levels, edge values, and the seed's formula as a step size", "[banded_toon][kernel]") {
    Shader shader(test::runtime());
    const glm::dvec3 white{1, 1, 1};
    // NoL values exactly representable, with the band rule worked by hand for steps = 4:
    // floor(4 NoL + 1/2) / 4.
    struct Spot { double NoL, expect; };
    const std::vector<Spot> spots4 = {{-0.5, 0.0}, {0.0, 0.0},  {0.1, 0.0},   {0.125, 0.25}, {0.13, 0.25},
                                      {0.5, 0.5},  {0.6, 0.5},  {0.875, 1.0}, {0.87, 0.75},  {1.0, 1.0}};
    std::vector<float> N, L, V, P;
    for (const Spot& s : spots4) {
        const glm::dvec3 l = light_at(s.NoL);
        N.insert(N.end(), {0, 0, 1});
        L.insert(L.end(), {float(l.x), 0.0f, float(s.NoL)});   // N = z: NoL is L.z exactly
        V.insert(V.end(), {0, 0, 1});
        P.insert(P.end(), {0, 0, 0});
    }
    const auto b4 = shader.eval_directions(make("banded", {{"steps", 4}}, white), N, L, V, P);
    const auto s64 = shader.eval_directions(make("banded_seed001", {{"light_steps", 64}}, white), N, L, V, P);
    for (std::size_t i = 0; i < spots4.size(); ++i) {
        INFO("steps 4 at NoL " << spots4[i].NoL << ": banded " << b4[3 * i] << ", seed t=64 " << s64[3 * i]
                               << ", by hand " << spots4[i].expect);
        CHECK(b4[3 * i] == float(spots4[i].expect));   // exact: every operation is exact for steps = 4
        CHECK(s64[3 * i] == float(spots4[i].expect));  // the seed with t = 256 / 4 is the same rule
    }

    // Levels over a dense NoL sweep: banded gives exactly steps + 1 levels k / steps; the seed with step
    // size t / 256 gives levels k t / 256, which for t = 100 run 0, 0.39, 0.78, 1.17 (above 1).
    auto levels = [&](const Material& m) {
        std::vector<float> n, l, v, p;
        for (int i = 0; i <= 40000; ++i) {
            const double x = -0.1 + 1.1 * i / 40000.0;
            const glm::dvec3 d = light_at(std::min(x, 1.0));
            n.insert(n.end(), {0, 0, 1});
            l.insert(l.end(), {float(d.x), 0.0f, float(d.z)});
            v.insert(v.end(), {0, 0, 1});
            p.insert(p.end(), {0, 0, 0});
        }
        const auto out = shader.eval_directions(m, n, l, v, p);
        std::set<float> s;
        for (std::size_t i = 0; i < out.size(); i += 3) s.insert(out[i]);
        return s;
    };
    for (double steps : {1.0, 2.0, 3.0, 7.0, 256.0}) {
        const auto s = levels(make("banded", {{"steps", steps}}, white));
        INFO("banded steps " << steps << ": " << s.size() << " levels, top " << *s.rbegin());
        CHECK(s.size() == std::size_t(steps) + 1);
        CHECK(*s.begin() == 0.0f);
        CHECK(*s.rbegin() == 1.0f);
        for (float v : s) CHECK(std::abs(v * steps - std::round(v * steps)) <= 4 * kU * steps);
    }
    const auto s100 = levels(make("banded_seed001", {{"light_steps", 100}}, white));
    std::cout << "banded_seed001 light_steps=100 levels:";
    for (float v : s100) std::cout << " " << v;
    std::cout << "  (floor((256 + 50) / 100) = 3 steps of 100/256 at NoL = 1)\n";
    CHECK(s100.size() == 4);
    CHECK(*s100.rbegin() == Approx(300.0 / 256.0).epsilon(1e-7));
    CHECK(levels(make("banded_seed001", {{"light_steps", 1}}, white)).size() == 257);

    // The seed's formula with t = 256 / s is banded with steps = s, bit for bit, over the whole sweep.
    const auto& sw = test::sweep();
    for (int s = 1; s <= 256; s *= 2) {
        const auto a = shader.eval_directions(make("banded", {{"steps", double(s)}}), sw.N, sw.L, sw.V, sw.P);
        const auto b = shader.eval_directions(make("banded_seed001", {{"light_steps", 256.0 / s}}), sw.N, sw.L, sw.V, sw.P);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < a.size(); ++i) differ += a[i] != b[i] ? 1 : 0;
        INFO("steps " << s << " vs light_steps " << 256 / s << ": " << differ << " values differ");
        CHECK(differ == 0);
    }
}

TEST_CASE("banded directional albedo: exactly Lambert's for every steps - the seed's never above 1",
          "[banded_toon][physics]") {
    // value depends on NoL only: albedo = 2 * integral over NoL in [0, 1]. The integrand is piecewise
    // constant between the edges, so the integral is exact from one reference value per piece; the
    // pieces are checked flat by evaluating the reference next to both ends.
    const glm::dvec3 Nz{0, 0, 1}, white{1, 1, 1};
    auto piecewise = [&](const Material& m, double step, bool& flat) {
        std::vector<double> cuts = {0.0};
        for (double e = 0.5 * step; e < 1.0; e += step) cuts.push_back(e);
        cuts.push_back(1.0);
        double sum = 0.0;
        for (std::size_t j = 0; j + 1 < cuts.size(); ++j) {
            const double a = cuts[j], b = cuts[j + 1];
            auto v = [&](double x) { return ref::eval_material(Nz, light_at(x), Nz, {}, m).x; };
            const double mid = v(0.5 * (a + b));
            if (b - a > 1e-9 && (v(a + 1e-10) != mid || v(b - 1e-10) != mid)) flat = false;
            sum += (b - a) * mid;
        }
        return 2.0 * sum;
    };
    bool flat = true;
    double b_lo = 9.0, b_hi = 0.0;
    for (int s = 1; s <= 256; ++s) {
        const double a = piecewise(make("banded", {{"steps", double(s)}}, white), 1.0 / s, flat);
        b_lo = std::min(b_lo, a);
        b_hi = std::max(b_hi, a);
    }
    double t_lo = 9.0, t_hi = 0.0;
    int t_at = 0;
    for (int t = 1; t <= 256; ++t) {
        const double a = piecewise(make("banded_seed001", {{"light_steps", double(t)}}, white), t / 256.0, flat);
        if (a < t_lo) { t_lo = a; t_at = t; }
        t_hi = std::max(t_hi, a);
    }
    std::cout << "directional albedo (albedo 1): banded steps 1..256 in [" << b_lo << ", " << b_hi
              << "]; banded_seed001 light_steps 1..256 in [" << t_lo << " (t = " << t_at << "), " << t_hi << "]\n";
    CHECK(flat);
    CHECK(std::abs(b_lo - 1.0) <= 1e-12);
    CHECK(std::abs(b_hi - 1.0) <= 1e-12);
    CHECK(t_hi <= 1.0 + 1e-12);
    CHECK(t_lo < 0.95);   // far from Lambert for step sizes that do not divide 256
    CHECK(find_model("banded").energy_conserving);
    CHECK(find_model("banded_seed001").energy_conserving);
    // A cross-check of the piecewise integration by the plain midpoint rule (one edge costs <= step * h).
    const Material m7 = make("banded", {{"steps", 7.0}}, white);
    double mid = 0.0;
    const int cells = 100000;
    for (int i = 0; i < cells; ++i) mid += ref::eval_material(Nz, light_at((i + 0.5) / cells), Nz, {}, m7).x;
    CHECK(std::abs(2.0 * mid / cells - 1.0) <= 2.0 * 7.0 * (1.0 / 7.0) / cells);
}

TEST_CASE("toon kernel matches the reference - hard-band mismatches only within a few ulps of an edge",
          "[banded_toon][kernel]") {
    std::vector<Material> grid = {make("toon"), make("toon", {{"width", 0.0}}), make("toon", {{"width", 0.5}})};
    for (double n : {0.0, 1.0, 10000.0})
        for (double w : {0.0, 0.02}) grid.push_back(make("toon", {{"n", n}, {"width", w}}));
    const std::map<std::string, double> ends_low = {{"diffuse_t1", -1}, {"diffuse_t2", -1}, {"diffuse_t3", -1},
                                                    {"spec_t1", 0},     {"spec_t2", 0},     {"width", 0}};
    const std::map<std::string, double> ends_high = {{"diffuse_t1", 1}, {"diffuse_t2", 1}, {"diffuse_t3", 1},
                                                     {"spec_t1", 1},    {"spec_t2", 1},    {"diffuse_l0", 1},
                                                     {"spec_l0", 1},    {"width", 0}};
    grid.push_back(make("toon", ends_low));
    grid.push_back(make("toon", ends_high));
    std::cout << "toon kernel vs double reference, " << test::sweep().size() << " sweep triples + 9000 placed on the edges;"
              << " edges: NoL within " << kDeltaNoL
              << " of a diffuse threshold or 0, NoH within " << kDeltaNoH << " of a highlight threshold\n";
    for (const Material& m : grid) {
        const auto& p = m.params;
        const double n = p.at("n"), width = p.at("width");
        const double dt[3] = {p.at("diffuse_t1"), p.at("diffuse_t2"), p.at("diffuse_t3")};
        const double dl[4] = {p.at("diffuse_l0"), p.at("diffuse_l1"), p.at("diffuse_l2"), p.at("diffuse_l3")};
        const double st[2] = {p.at("spec_t1"), p.at("spec_t2")};
        const double sl[3] = {p.at("spec_l0"), p.at("spec_l1"), p.at("spec_l2")};
        const double d_jumps = std::abs(dl[1] - dl[0]) + std::abs(dl[2] - dl[1]) + std::abs(dl[3] - dl[2]);
        const double s_jumps = std::abs(sl[1] - sl[0]) + std::abs(sl[2] - sl[1]);
        const double s_max = std::max({sl[0], sl[1], sl[2]});
        // highlight edges in NoH: x = NoH^n >= u  <=>  NoH >= u^(1/n) (n > 0; u = 0 is always passed);
        // at n = 0, x jumps from 0 to 1 at NoH = 0
        std::vector<double> noh_edges;
        for (double u : st)
            if (u > 0.0) noh_edges.push_back(n > 0.0 ? std::pow(u, 1.0 / n) : 0.0);
        std::vector<double> nol_edges(dt, dt + 3);
        nol_edges.push_back(0.0);
        const test::DirectionSweep on_edges = edge_sweep(nol_edges, noh_edges, 9000 / (nol_edges.size() + noh_edges.size()));
        std::size_t flat = 0, transition = 0, mismatches = 0;
        double max_rel_flat = 0.0, max_dist_ulps = 0.0;
        const auto e = test::check_kernel_against_reference(m, [&](const test::Compared& v) {
            const double NoL = v.NoL();
            const glm::dvec3 h = v.L() + v.V();
            const double hl = glm::length(h);
            const bool h_defined = hl > 1e-10;
            const double NoH = h_defined ? glm::dot(v.N(), h) / hl : 0.0;
            // distance to the nearest edge, in NoL and in NoH units
            double dNoL = std::abs(NoL);   // the highlight gate
            for (double t : dt) dNoL = std::min(dNoL, std::abs(NoL - t));
            double dNoH = 1e9;
            if (h_defined)
                for (double edge : noh_edges) dNoH = std::min(dNoH, std::abs(NoH - edge));
            const double half = 0.5 * width;
            const bool near = dNoL <= half + kDeltaNoL || dNoH <= kDeltaNoH + (half > 0.0 ? 1.0 : 0.0);
            const int c = v.c;
            const double err = v.err(), tol = kTightRel * (std::abs(v.r) + m.albedo[c] + m.specular[c]);
            if (!near) {   // away from every edge: a few ulps
                ++flat;
                if (std::abs(v.r) > 0.0) max_rel_flat = std::max(max_rel_flat, err / std::abs(v.r));
                return tol;
            }
            ++transition;
            // width > 0: Lipschitz bound of the smoothsteps (slope <= 1.5 / width per unit jump) times the
            // input error; the highlight's x moves by at most (NoH + dNoH)^n - NoH^n, and at n = 0 it jumps.
            double dx = 0.0;
            if (h_defined && NoH > -kDeltaNoH) {
                const double up = std::pow(std::max(NoH, 0.0) + kDeltaNoH, n);
                dx = n > 0.0 ? up - (NoH > 0.0 ? std::pow(NoH, n) : 0.0) : (NoH <= kDeltaNoH ? 1.0 : 0.0);
            }
            if (width > 0.0) {
                const double slope = 1.5 / width;
                return tol + m.albedo[c] * d_jumps * slope * kDeltaNoL + m.specular[c] * s_max * slope * kDeltaNoL +
                       m.specular[c] * (n > 0.0 ? s_jumps * slope * dx : s_jumps * dx);
            }
            // hard bands: at most every jump at once (in practice one band)
            if (err > tol) {
                ++mismatches;
                max_dist_ulps = std::max(max_dist_ulps, std::min(dNoL, dNoH) / kU);
            }
            return tol + m.albedo[c] * d_jumps + m.specular[c] * (s_max + s_jumps);
        }, {&test::sweep(), &on_edges});
        std::cout << "  " << std::left << std::setw(40) << test::describe(m) << std::right << " away from edges " << std::setw(6)
                  << flat << " values, max rel " << std::setw(11) << max_rel_flat << "; near edges " << std::setw(5)
                  << transition;
        if (width > 0.0) std::cout << " values, max err/bound " << e.worst_ratio << "\n";
        else std::cout << " values, " << mismatches << " in the other band (<= " << max_dist_ulps << " u from the edge)\n";
        test::expect_within(e, test::sweep().size());
    }
}

TEST_CASE("toon rule by hand: 4 diffuse and 3 highlight levels, edges, smoothing, ordering, L = -V",
          "[banded_toon][kernel][stability]") {
    Shader shader(test::runtime());
    const glm::dvec3 white{1, 1, 1}, black{0, 0, 0};
    // Diffuse only (highlight levels 0), representable thresholds 0, 0.25, 0.75 and levels 0.1 .. 1.
    std::map<std::string, double> p = {{"diffuse_t1", 0.0}, {"diffuse_t2", 0.25}, {"diffuse_t3", 0.75},
                                       {"diffuse_l0", 0.1}, {"diffuse_l1", 0.4},  {"diffuse_l2", 0.7},
                                       {"diffuse_l3", 1.0}, {"spec_l1", 0.0},     {"spec_l2", 0.0},
                                       {"width", 0.0}};
    const Material hard = make("toon", p, white);
    p["width"] = 0.02;
    const Material soft = make("toon", p, white);
    struct Spot { double NoL, hard, soft; };
    // soft: smoothstep over [t - 0.01, t + 0.01]; exactly at an edge it is half-way
    const std::vector<Spot> spots = {{-0.5, 0.1, 0.1},   {-0.01, 0.1, 0.1}, {0.0, 0.4, 0.25},  {0.1, 0.4, 0.4},
                                     {0.25, 0.7, 0.55},  {0.2499, 0.4, 0.4 + 0.3 * (0.495 * 0.495 * (3.0 - 2.0 * 0.495))},
                                     {0.5, 0.7, 0.7},    {0.75, 1.0, 0.85}, {1.0, 1.0, 1.0}};
    std::vector<float> N, L, V, P;
    for (const Spot& s : spots) {
        const glm::dvec3 l = light_at(s.NoL);
        N.insert(N.end(), {0, 0, 1});
        L.insert(L.end(), {float(l.x), 0.0f, float(s.NoL)});
        V.insert(V.end(), {0, 0, 1});
        P.insert(P.end(), {0, 0, 0});
    }
    const auto kh = shader.eval_directions(hard, N, L, V, P), ksoft = shader.eval_directions(soft, N, L, V, P);
    for (std::size_t i = 0; i < spots.size(); ++i) {
        INFO("NoL " << spots[i].NoL << ": hard " << kh[3 * i] << " (by hand " << spots[i].hard << "), soft "
                    << ksoft[3 * i] << " (by hand " << spots[i].soft << ")");
        CHECK(kh[3 * i] == Approx(spots[i].hard).margin(1e-6));
        CHECK(ksoft[3 * i] == Approx(spots[i].soft).margin(2e-6));
    }
    // Level counts over dense sweeps: 4 diffuse values (hard), monotone and continuous when smoothed.
    {
        std::vector<float> n, l, v, q;
        for (int i = 0; i <= 20000; ++i) {
            const glm::dvec3 d = light_at(-1.0 + 2.0 * i / 20000.0);
            n.insert(n.end(), {0, 0, 1});
            l.insert(l.end(), {float(d.x), 0.0f, float(d.z)});
            v.insert(v.end(), {0, 0, 1});
            q.insert(q.end(), {0, 0, 0});
        }
        const auto a = shader.eval_directions(hard, n, l, v, q), b = shader.eval_directions(soft, n, l, v, q);
        std::set<float> levels;
        double max_step = 0.0;
        bool monotone = true;
        for (std::size_t i = 0; i < a.size(); i += 3) {
            levels.insert(a[i]);
            if (i >= 3) {
                monotone = monotone && b[i] >= b[i - 3];
                max_step = std::max(max_step, double(b[i] - b[i - 3]));
            }
        }
        CHECK(levels.size() == 4);
        CHECK(monotone);
        CHECK(max_step <= 0.3 * 1.5 / 0.02 * (2.0 / 20000.0) * 1.01);   // largest jump * max slope * sample step
    }
    // Highlight: 3 levels of NoH^n, with V = N and the light swept through the mirror direction.
    {
        const Material spec_only = make("toon", {{"n", 64}, {"width", 0.0}, {"diffuse_l1", 0}, {"diffuse_l2", 0},
                                                 {"diffuse_l3", 0}}, black, white);
        std::vector<float> n, l, v, q;
        for (int i = 0; i <= 4000; ++i) {
            const double th = 0.5 * i / 4000.0;   // light angle; NoH = cos(th / 2)
            n.insert(n.end(), {0, 0, 1});
            l.insert(l.end(), {float(std::sin(th)), 0.0f, float(std::cos(th))});
            v.insert(v.end(), {0, 0, 1});
            q.insert(q.end(), {0, 0, 0});
        }
        const auto a = shader.eval_directions(spec_only, n, l, v, q);
        std::set<float> levels(a.begin(), a.end());
        CHECK(levels == std::set<float>{0.0f, 0.5f, 1.0f});
        // by hand: NoH^64 >= 0.9 <=> th <= 2 acos(0.9^(1/64)) = 0.1149; >= 0.5 <=> th <= 0.2944
        const auto at = [&](double th) {
            const std::vector<float> ll = {float(std::sin(th)), 0.0f, float(std::cos(th))};
            return shader.eval_directions(spec_only, {0, 0, 1}, ll, {0, 0, 1}, {0, 0, 0})[0];
        };
        CHECK(at(0.110) == 1.0f);
        CHECK(at(0.120) == 0.5f);
        CHECK(at(0.290) == 0.5f);
        CHECK(at(0.300) == 0.0f);
        // light behind the surface, viewer at its mirror: NoH = 1 but the gate is off
        const double z = -0.1, x = std::sqrt(1 - z * z);
        CHECK(shader.eval_directions(spec_only, {0, 0, 1}, {float(x), 0, float(z)}, {float(-x), 0, float(-z)}, {0, 0, 0})[0] ==
              0.0f);
        // L = -V: H undefined, highlight 0 (finite), diffuse unaffected
        const auto opp = shader.eval_directions(make("toon", {{"n", 0.0}}, white, white), {0, 0, 1, 0, 0, 1},
                                                {0.6f, 0, 0.8f, 0, 0, 1}, {-0.6f, 0, -0.8f, 0, 0, -1}, {0, 0, 0, 0, 0, 0});
        CHECK(opp[0] == Approx(1.0).margin(1e-6));   // NoL 0.8 >= 0.7: diffuse level 3, no highlight
        CHECK(opp[3] == Approx(1.0).margin(1e-6));   // L = N, V = -N
    }
    // Thresholds must ascend: the host refuses, naming the parameters.
    CHECK_THROWS_AS(pack_material(make("toon", {{"diffuse_t1", 0.5}, {"diffuse_t2", 0.4}})), Error);
    CHECK_THROWS_AS(pack_material(make("toon", {{"spec_t1", 0.95}, {"spec_t2", 0.9}})), Error);
    CHECK_NOTHROW(pack_material(make("toon", {{"diffuse_t1", 0.35}, {"diffuse_t2", 0.35}})));   // equal: 3 levels
}

TEST_CASE("banded and toon are neither reciprocal nor (toon) energy conserving, as flagged", "[banded_toon][physics]") {
    const glm::dvec3 Nz{0, 0, 1}, white{1, 1, 1};
    const glm::dvec3 L = light_at(0.3), V = glm::dvec3(-std::sqrt(1 - 0.81), 0.0, 0.9);
    for (const Material& m : {make("banded", {}, white), make("banded_seed001", {}, white), make("toon", {}, white)}) {
        const double a = ref::eval_material(Nz, L, V, {}, m).x / L.z, b = ref::eval_material(Nz, V, L, {}, m).x / V.z;
        INFO(m.model << ": value/NoL " << a << " vs swapped " << b);
        CHECK(std::abs(a - b) > 0.1 * std::max(a, b));
        CHECK_FALSE(find_model(m.model).reciprocal);
    }
    // toon's hard diffuse ladder alone gathers 2 (0.3 * 0.35 + 0.6 * 0.35 + 1 * 0.3) = 1.23 at the default
    // levels (the default width 0.02 takes 2 * 0.3 * 0.02 * 3/32 = 0.001125 off: the edge at NoL = 0 is
    // only half inside the hemisphere; the others are symmetric)
    const Material t = make("toon", {{"spec_l1", 0.0}, {"spec_l2", 0.0}, {"width", 0.0}}, white);
    double sum = 0.0;
    const int cells = 100000;
    for (int i = 0; i < cells; ++i) sum += ref::eval_material(Nz, light_at((i + 0.5) / cells), Nz, {}, t).x;
    const double a = 2.0 * sum / cells;
    std::cout << "toon (default levels, no highlight) directional albedo " << a << " (by hand 1.23)\n";
    CHECK(a == Approx(1.23).epsilon(1e-4));
    CHECK_FALSE(find_model("toon").energy_conserving);
}
