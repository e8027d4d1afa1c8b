// What the test files share: the one OpenCL runtime of the test process, the standard direction sweep,
// the bundled data folders, resolved materials, scratch folders, the slope of a model under small turns
// of its directions (the rounding part of the kernel-vs-reference bounds), the kernel-vs-reference harness and the
// white furnace (directional albedo) every family's tests use.
#pragma once
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <map>
#include <string>
#include <system_error>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include "cl/runtime.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"
#include "sweep.hpp"

namespace shadelab::test {

// Sets (or, with nullptr, unsets) an environment variable for the scope of one test.
struct ScopedEnv {
    std::string name, old;
    bool had = false;
    ScopedEnv(const char* n, const char* v) : name(n) {
        if (const char* o = std::getenv(n)) { had = true; old = o; }
        v ? (void)::setenv(n, v, 1) : (void)::unsetenv(n);
    }
    ~ScopedEnv() { had ? (void)::setenv(name.c_str(), old.c_str(), 1) : (void)::unsetenv(name.c_str()); }
};

// The folders the build names: the source tree, example scenes, bundled meshes, test data. The paths come from
// tests/paths.cpp, the one test file compiled with the build's paths, so that the other test files do not
// depend on where the tree is (a compiler cache then shares them between checkouts). Functions, not variables
// of that file: a test file's own statics built from these (kHostile = kData + ...) are then initialised after
// them, as C++ orders the inline variables of a header before what follows them in the same file.
std::string source_dir();
std::string mesh_dir();
std::string data_dir();
inline const std::string kSourceDir = source_dir();
inline const std::string kScenes = source_dir() + "/scenes";
inline const std::string kMeshes = mesh_dir();
inline const std::string kData = data_dir();

// The OpenCL runtime every test shares (one context and one program cache per test process).
inline Runtime& runtime() {
    static Runtime rt;
    return rt;
}

// The standard sweep of the family tests: 120,000 (N, L, V) triples over the sphere with the breaking cases
// (make_sweep in sweep.hpp, its default seed).
inline const DirectionSweep& sweep() {
    static const DirectionSweep s = make_sweep(120000);
    return s;
}

// The colours the family tests give their materials: distinct per channel, so a swapped channel shows.
inline const glm::dvec3 kAlbedo{0.9, 0.5, 0.25};
inline const glm::dvec3 kSpecular{1.0, 0.8, 0.6};

// A resolved material: `model` with `params` (the rest at their defaults), diffuse `albedo`, `specular`.
inline Material material(const std::string& model, std::map<std::string, double> params = {},
                         glm::dvec3 albedo = kAlbedo, glm::dvec3 specular = Material{}.specular) {
    Material m;
    m.model = model;
    m.params = std::move(params);
    m.albedo = albedo;
    m.specular = specular;
    return resolve_material(m);
}

// The per-process folder under the system temporary folder; removed, with all in it, when the process ends.
struct ScratchRoot {
    std::filesystem::path path = std::filesystem::temp_directory_path() /
                                 ("shadelab-test-" + std::to_string(::getpid()));
    ScratchRoot() { std::filesystem::remove_all(path); }
    ~ScratchRoot() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

// An empty folder `name` for one test's files, under the per-process folder (emptied if it existed).
inline std::filesystem::path scratch_dir(const std::string& name) {
    static const ScratchRoot root;
    const std::filesystem::path d = root.path / name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

// Rodrigues' rotation of unit v about unit axis a by angle t.
inline glm::dvec3 rotate(const glm::dvec3& v, const glm::dvec3& a, double t) {
    return v * std::cos(t) + glm::cross(a, v) * std::sin(t) + a * glm::dot(a, v) * (1.0 - std::cos(t));
}

// How much the exact value r = reference(N, L, V)[c] moves per radian when L or V is turned by a small angle,
// or per unit of relative length when N is scaled: the largest one-sided difference quotient over turns of
// +-1e-6 rad about two axes perpendicular to each and scalings by 1 +- 1e-6 (the reference in double). Float
// rounding turns every direction the kernel forms (the inputs' components, L + V, H, the dot products) by
// about 2^-24 = 6e-8 rad and leaves unit vectors unit to about as much (a model such as Blinn-Phong's NoH^n
// multiplies that by n); this slope times that is what the rounding can do to an exact evaluation.
inline double slope(const glm::dvec3& N, const glm::dvec3& L, const glm::dvec3& V, const Material& m, int c, double r) {
    constexpr double kTurn = 1e-6;
    double s = 0.0;
    for (int which = 0; which < 2; ++which) {
        const glm::dvec3 W = which ? V : L;
        const glm::dvec3 a1 = any_perpendicular(W), a2 = glm::cross(W, a1);
        for (const glm::dvec3& axis : {a1, a2})
            for (double t : {kTurn, -kTurn}) {
                const glm::dvec3 Wt = rotate(W, axis, t);
                const double rt = which ? ref::eval_material(N, L, Wt, {}, m)[c] : ref::eval_material(N, Wt, V, {}, m)[c];
                s = std::max(s, std::abs(rt - r) / kTurn);
            }
    }
    // A length 1 +- kTurn instead of a turn: scaling N scales every cosine alike.
    for (double f : {1.0 + kTurn, 1.0 - kTurn})
        s = std::max(s, std::abs(ref::eval_material(N * f, L, V, {}, m)[c] - r) / kTurn);
    return s;
}

// ---- the kernel against its reference ----------------------------------------------------------------------
// One harness for every family's kernel-vs-reference test: check_kernel_against_reference(m, allowed, sweeps)
// runs the kernel of the resolved material m through the shared runtime on the standard sweep (and any extra
// sweeps, e.g. triples placed on a model's band edges), evaluates the double reference on the same float inputs,
// and tallies each value (triple, channel) against the test's own bound, allowed(value): the largest |k - r| it
// allows there, or kExempt for a value the bound does not cover (a documented band such as the horizon, where
// either side is right) - exempt values still count as NaN/Inf when they are. expect_within(e) then asserts
// (Catch) no NaN/Inf and no value past its bound, and prints one line: max / p99 relative and absolute error,
// the worst geometry (largest error over its bound), the counts. A test states its bound in its allowance:
//     const auto e = test::check_kernel_against_reference(m, [&](const test::Compared& v) {
//         return v.NoL() >= 0.05 ? 2e-6 * std::abs(v.r) : 2e-7; });
//     test::expect_within(e);

// One value compared: channel c of triple i of `sweep`, the kernel's value k and the reference's r, and the whole
// run (kernel values and references of that sweep) for bounds that need a statistic of it (a peak, a quantile).
struct Compared {
    const DirectionSweep& sweep;
    const std::vector<float>& kernel;           // 3 per triple
    const std::vector<glm::dvec3>& reference;   // 1 per triple
    std::size_t i;
    int c;
    double k, r;
    double err() const { return std::abs(k - r); }
    const glm::dvec3& N() const { return sweep.dN[i]; }
    const glm::dvec3& L() const { return sweep.dL[i]; }
    const glm::dvec3& V() const { return sweep.dV[i]; }
    const glm::dvec3& P() const { return sweep.dP[i]; }
    double NoL() const { return glm::dot(N(), L()); }
    double NoV() const { return glm::dot(N(), V()); }
    double LoV() const { return glm::dot(L(), V()); }
};

// What an allowance returns for a value its bound does not cover.
constexpr double kExempt = -1.0;

// The tally of one material over its sweeps.
struct KernelVsReference {
    std::string what;   // the material, "model p=v ..."
    double rel_floor = 1e-3;   // relative errors are taken where |r| >= rel_floor
    std::size_t values = 0, compared = 0, exempt = 0, non_finite = 0, negative = 0, failures = 0;
    double max_abs = 0.0, p99_abs = 0.0, max_rel = 0.0, p99_rel = 0.0;   // over the compared values
    double worst_ratio = 0.0;   // the largest |k - r| / allowed (> 1: past the bound)
    std::string worst;          // that value's geometry, kernel and reference
    std::string first_non_finite;

    std::string summary() const {
        std::ostringstream o;
        o << what << ": " << compared << " values compared (" << exempt << " exempt), max rel " << max_rel << " p99 rel "
          << p99_rel << " (|r| >= " << rel_floor << "), max abs " << max_abs << " p99 abs " << p99_abs
          << ", max err/bound " << worst_ratio << ", past bound " << failures << ", NaN/Inf " << non_finite;
        return o.str();
    }
};

// "model p=v ..." for a resolved material: the parameters that differ from the model's defaults, or all.
inline std::string describe(const Material& m, bool all = false) {
    std::ostringstream o;
    o << m.model;
    for (const auto& p : find_model(m.model).params)
        if (all || m.params.at(p.name) != p.def) o << " " << p.name << "=" << m.params.at(p.name);
    return o.str();
}

// Where a compared value sits: triple, kind, the cosines, the vectors, kernel and reference.
inline std::string describe(const Compared& v) {
    std::ostringstream o;
    auto vec = [&](const glm::dvec3& d) { o << "(" << d.x << "," << d.y << "," << d.z << ")"; };
    o << std::setprecision(9) << "triple " << v.i << " (" << v.sweep.kind[v.i] << ") channel " << v.c << " NoL=" << v.NoL()
      << " NoV=" << v.NoV() << " LoV=" << v.LoV() << " N=";
    vec(v.N());
    o << " L=";
    vec(v.L());
    o << " V=";
    vec(v.V());
    o << ": kernel " << v.k << ", reference " << v.r;
    return o.str();
}

// The q-quantile (0..1) of xs (reordered), 0 when empty.
inline double quantile(std::vector<double>& xs, double q) {
    if (xs.empty()) return 0.0;
    const auto at = xs.begin() + std::ptrdiff_t(std::min(xs.size() - 1, std::size_t(q * double(xs.size()))));
    std::nth_element(xs.begin(), at, xs.end());
    return *at;
}

// The kernel of `m` on each of `sweeps` against its reference, each value against allowed(value) (above).
template <typename Allowance>
KernelVsReference check_kernel_against_reference(const Material& m, Allowance&& allowed,
                                                 const std::vector<const DirectionSweep*>& sweeps = {&sweep()},
                                                 double rel_floor = 1e-3) {
    KernelVsReference e;
    e.what = describe(m);
    e.rel_floor = rel_floor;
    std::vector<double> abs_errs, rel_errs;
    std::size_t total = 0;
    for (const DirectionSweep* s : sweeps) total += 3 * s->size();
    abs_errs.reserve(total);
    rel_errs.reserve(total);
    Shader shader(runtime());
    for (const DirectionSweep* s : sweeps) {
        const std::vector<float> out = shader.eval_directions(m, s->N, s->L, s->V, s->P);
        std::vector<glm::dvec3> ref(s->size());
        for (std::size_t i = 0; i < s->size(); ++i) ref[i] = ref::eval_material(s->dN[i], s->dL[i], s->dV[i], s->dP[i], m);
        for (std::size_t i = 0; i < s->size(); ++i)
            for (int c = 0; c < 3; ++c) {
                const Compared v{*s, out, ref, i, c, out[3 * i + std::size_t(c)], ref[i][c]};
                ++e.values;
                if (!std::isfinite(v.k)) {
                    if (e.non_finite++ == 0) e.first_non_finite = describe(v);
                    continue;
                }
                if (v.k < 0.0) ++e.negative;
                const double a = allowed(v);
                if (a < 0.0) { ++e.exempt; continue; }
                ++e.compared;
                const double err = v.err();
                abs_errs.push_back(err);
                e.max_abs = std::max(e.max_abs, err);
                if (std::abs(v.r) >= rel_floor) {
                    rel_errs.push_back(err / std::abs(v.r));
                    e.max_rel = std::max(e.max_rel, rel_errs.back());
                }
                if (err > a) ++e.failures;
                const double ratio = a > 0.0 ? err / a : (err > 0.0 ? HUGE_VAL : 0.0);
                if (ratio > e.worst_ratio || e.worst.empty()) {
                    e.worst_ratio = std::max(e.worst_ratio, ratio);
                    e.worst = describe(v);
                }
            }
    }
    e.p99_abs = quantile(abs_errs, 0.99);
    e.p99_rel = quantile(rel_errs, 0.99);
    return e;
}

// The Catch checks of a tally: no NaN/Inf, no value past its bound, at least min_compared values compared (so
// the bound is not vacuous); prints the summary line.
inline void expect_within(const KernelVsReference& e, std::size_t min_compared = 1) {
    std::cout << "  " << e.summary() << "\n";
    INFO(e.summary() << "; worst: " << e.worst << (e.non_finite ? "; first NaN/Inf: " + e.first_non_finite : ""));
    CHECK(e.non_finite == 0);
    CHECK(e.failures == 0);
    CHECK(e.compared >= min_compared);
}

// The bound of a model whose error is set by the float rounding of its inputs: B is how far the exact value r can
// move under that rounding (per value, e.g. from slope() or the reference's change over the dot products' error).
// Where the value is not tiny (|r| >= value_floor) and well conditioned (B <= cond_rel |r|) the kernel must be
// within tight_rel |r| of the reference; elsewhere within tight_rel (|r| + B) + B + underflow (the kernel's own
// rounding is relative to what it may return, |r| + B).
struct ConditionedBound {
    double tight_rel = 2e-6, value_floor = 1e-3, cond_rel = 1e-6, underflow = 0.0;
    bool conditioned(double r, double B) const { return std::abs(r) >= value_floor && B <= cond_rel * std::abs(r); }
    double operator()(double r, double B) const {
        return conditioned(r, B) ? tight_rel * std::abs(r) : tight_rel * (std::abs(r) + B) + B + underflow;
    }
};

// The harness with a ConditionedBound: input_bound(v) is the bound B of value v's triple, per channel (called once
// per triple). Also counts the conditioned values and the rest, and the largest relative error where conditioned.
struct ConditionedResult {
    KernelVsReference e;
    std::size_t cond = 0, rest = 0;
    double max_rel_cond = 0.0;
};
template <typename InputBound>
ConditionedResult check_conditioned(const Material& m, const ConditionedBound& bound, InputBound&& input_bound) {
    ConditionedResult res;
    glm::dvec3 B(0.0);
    const DirectionSweep* bound_sweep = nullptr;
    std::size_t bound_of = 0;
    res.e = check_kernel_against_reference(m, [&](const Compared& v) {
        if (bound_sweep != &v.sweep || v.i != bound_of) {
            B = input_bound(v);
            bound_sweep = &v.sweep;
            bound_of = v.i;
        }
        if (bound.conditioned(v.r, B[v.c])) {
            ++res.cond;
            res.max_rel_cond = std::max(res.max_rel_cond, v.err() / std::abs(v.r));
        } else {
            ++res.rest;
        }
        return bound(v.r, B[v.c]);
    });
    return res;
}

// The same, with the exact value computed here.
inline double slope(const glm::dvec3& N, const glm::dvec3& L, const glm::dvec3& V, const Material& m, int c) {
    return slope(N, L, V, m, c, ref::eval_material(N, L, V, {}, m)[c]);
}

// ---- the white furnace ---------------------------------------------------------------------------------------
// Directional albedo under the value convention (value = pi f_r NoL): (1/pi) * integral over the upper hemisphere
// of value(L, V) dL for a fixed view V (N = +z), by a midpoint rule on one of three grids, from the reference or
// from the kernel. The grid is the family's choice: what resolves its lobe and its kinks.
//   cos_theta          midpoints in (cos theta, phi): uniform in solid angle (smooth diffuse models)
//   cos_theta_squared  cos theta = t^2 at midpoints in t: denser at grazing (mu^k with small k, Minnaert)
//   half_vector        midpoints in (theta_h, phi_h) of the half vector, L = 2 (V.H) H - V, weight 4 VoH: resolves
//                      narrow specular lobes (Cook-Torrance); nodes with V.H <= 0 or L below the horizon dropped
// phi runs over (0, phi_max): phi_max = pi integrates half the hemisphere and doubles it, for models that depend
// on the azimuth only through cos(phi_i - phi_r) with V in the xz plane. over_view integrates over V with L fixed
// instead: (1/pi) * integral of f_r NoV dV = integral of value NoV / (pi NoL) dV.
struct Furnace {
    enum class Grid { cos_theta, cos_theta_squared, half_vector };
    Grid grid = Grid::cos_theta;
    int n_theta = 256, n_phi = 512;
    double phi_max = 2.0 * M_PI;
    bool over_view = false;

    struct Node {
        glm::dvec3 W;   // the integrated direction (L, or V when over_view)
        double weight;  // quadrature weight times 1/pi (and the mirror's 2)
    };
    // The nodes for the fixed direction F (V, or L when over_view), unit, in the upper hemisphere.
    std::vector<Node> nodes(const glm::dvec3& F) const {
        std::vector<Node> out;
        const double mirror = 2.0 * M_PI / phi_max, d_phi = phi_max / n_phi;
        for (int i = 0; i < n_theta; ++i)
            for (int j = 0; j < n_phi; ++j) {
                const double phi = phi_max * (j + 0.5) / n_phi;
                if (grid == Grid::half_vector) {
                    const double th = (i + 0.5) / n_theta * (M_PI / 2), st = std::sin(th);
                    const glm::dvec3 H{st * std::cos(phi), st * std::sin(phi), std::cos(th)};
                    const double VoH = glm::dot(F, H);
                    const glm::dvec3 L = 2.0 * VoH * H - F;
                    if (VoH <= 0.0 || L.z <= 0.0) continue;
                    out.push_back({L, 4.0 * VoH * st * (M_PI / 2 / n_theta) * d_phi * mirror / M_PI});
                    continue;
                }
                const double t = (i + 0.5) / n_theta;
                const double mu = grid == Grid::cos_theta ? t : t * t;
                const double jac = grid == Grid::cos_theta ? 1.0 : 2.0 * t;   // d mu / dt
                const double s = std::sqrt(1.0 - mu * mu);
                double w = jac * (1.0 / n_theta) * d_phi * mirror / M_PI;
                if (over_view) w *= mu / F.z;   // value NoV / NoL
                out.push_back({{s * std::cos(phi), s * std::sin(phi), mu}, w});
            }
        return out;
    }
};

// The directional albedo of `m` seen from (or, over_view, lit from) each of `fixed` (unit, z > 0), channel c,
// from the double reference.
inline double furnace_reference(const Material& m, const glm::dvec3& fixed, const Furnace& f, int c = 1) {
    const glm::dvec3 N{0, 0, 1};
    double sum = 0.0;
    for (const Furnace::Node& n : f.nodes(fixed)) {
        const glm::dvec3 L = f.over_view ? fixed : n.W, V = f.over_view ? n.W : fixed;
        sum += n.weight * ref::eval_material(N, L, V, {}, m)[c];
    }
    return sum;
}

// The same from the kernel, one launch for every fixed direction.
inline std::vector<double> furnace_kernel(const Material& m, const std::vector<glm::dvec3>& fixed, const Furnace& f,
                                          int c = 1) {
    std::vector<float> N, L, V, P;
    std::vector<std::vector<Furnace::Node>> all;
    for (const glm::dvec3& F : fixed) {
        all.push_back(f.nodes(F));
        for (const Furnace::Node& n : all.back()) {
            const glm::dvec3 l = f.over_view ? F : n.W, v = f.over_view ? n.W : F;
            for (int k = 0; k < 3; ++k) {
                N.push_back(k == 2 ? 1.0f : 0.0f);
                L.push_back(float(l[k]));
                V.push_back(float(v[k]));
                P.push_back(0.0f);
            }
        }
    }
    Shader shader(runtime());
    const std::vector<float> out = shader.eval_directions(m, N, L, V, P);
    std::vector<double> res;
    std::size_t idx = 0;
    for (const auto& nodes : all) {
        double sum = 0.0;
        for (const Furnace::Node& n : nodes) sum += n.weight * out[3 * idx++ + std::size_t(c)];
        res.push_back(sum);
    }
    return res;
}

// A view (or light) direction at `deg` degrees from N = +z, in the xz plane.
inline glm::dvec3 at_angle(double deg) { return {std::sin(deg * M_PI / 180.0), 0.0, std::cos(deg * M_PI / 180.0)}; }

}  // namespace shadelab::test
