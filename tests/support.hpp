// What the test files share: the one OpenCL runtime of the test process, the standard direction sweep,
// the bundled data folders, resolved materials, scratch folders, the slope of a model under small turns
// of its directions (the rounding part of the kernel-vs-reference bounds), the kernel-vs-reference sweep and the
// white furnace (directional albedo) every family's tests use.
#pragma once
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <system_error>
#include <vector>

#include <glm/glm.hpp>

#include "cl/runtime.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"
#include "sweep.hpp"

namespace shadelab::test {

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

// Kernel-vs-reference statistics against a per-value input bound B (how far the exact value can move under
// the float rounding of the kernel's inputs). Where the value is not tiny (|r| >= value_floor) and well
// conditioned (B <= cond_rel |r|) the kernel must be within tight_rel |r| of the reference; elsewhere within
// tight_rel (|r| + B) + B + underflow (the kernel's own rounding is relative to what it may return, |r| + B).
struct ConditionedStats {
    double tight_rel = 2e-6, value_floor = 1e-3, cond_rel = 1e-6, underflow = 0.0;   // the bounds, set first
    double max_abs = 0.0, max_rel = 0.0, max_rel_cond = 0.0, worst_ratio = 0.0;
    std::size_t cond = 0, rest = 0, non_finite = 0, tight_fail = 0, rest_fail = 0, worst = 0;

    // One value: kernel k, reference r, bound B, of triple i.
    void add(std::size_t i, double k, double r, double B) {
        if (!std::isfinite(k)) { ++non_finite; return; }
        const double err = std::abs(k - r), mag = std::abs(r);
        max_abs = std::max(max_abs, err);
        if (mag >= value_floor) max_rel = std::max(max_rel, err / mag);
        if (mag >= value_floor && B <= cond_rel * mag) {
            ++cond;
            max_rel_cond = std::max(max_rel_cond, err / mag);
            if (err > tight_rel * mag) { ++tight_fail; worst = i; }
        } else {
            ++rest;
            const double allowed = tight_rel * (mag + B) + B + underflow;
            if (allowed > 0.0) worst_ratio = std::max(worst_ratio, err / allowed);
            if (err > allowed) { ++rest_fail; worst = i; }
        }
    }
};

// The kernel of `m` over the standard sweep against its reference, each value tallied into `e` (its bounds
// set) with the input bound `bound(i, r)` (per channel) of triple i whose reference value is r.
template <typename Bound>
ConditionedStats conditioned_sweep(const Material& m, ConditionedStats e, Bound&& bound) {
    const DirectionSweep& s = sweep();
    Shader shader(runtime());
    const std::vector<float> out = shader.eval_directions(m, s.N, s.L, s.V, s.P);
    for (std::size_t i = 0; i < s.size(); ++i) {
        const glm::dvec3 r = ref::eval_material(s.dN[i], s.dL[i], s.dV[i], s.dP[i], m);
        const glm::dvec3 B = bound(i, r);
        for (int c = 0; c < 3; ++c) e.add(i, out[3 * i + std::size_t(c)], r[c], B[c]);
    }
    return e;
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
