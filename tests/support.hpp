// What the test files share: the one OpenCL runtime of the test process, the standard direction sweep,
// the bundled data folders, resolved materials, scratch folders, and the slope of a model under small turns
// of its directions (the rounding part of the kernel-vs-reference bounds).
#pragma once
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <system_error>

#include <glm/glm.hpp>

#include "cl/runtime.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"
#include "sweep.hpp"

namespace shadelab::test {

// The folders the build names: example scenes, bundled meshes, test data.
inline const std::string kScenes = std::string(SHADELAB_SOURCE_DIR) + "/scenes";
inline const std::string kMeshes = SHADELAB_MESH_DIR;
inline const std::string kData = SHADELAB_TEST_DATA_DIR;

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

}  // namespace shadelab::test
