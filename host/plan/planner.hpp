// The planner: model no more than a scene needs. Given a scene and the error a user accepts, it measures
// cheaper configurations against the precise per-pixel double reference and keeps the cheapest one that
// stays within the tolerance. Every choice is verified by rendering, never predicted only.
//
// Configurations tried (the same choice applied to every mesh of the scene):
//   model      the requested one, or Lambert with the same albedo (Oren-Nayar at small sigma, Minnaert at
//              its Lambert k, specular terms that never reach the tolerance all reduce to it);
//   precision  precise or fast (kernels/common.cl);
//   evaluation per pixel, or per vertex (Gouraud: shade the vertices, interpolate);
//   tessellation  for icosphere meshes (analytic spheres), coarser levels;
//   catalogue  with PlanOptions::catalogue (the default of plan/render/batch --tolerance): per material, the
//              substitute the catalogue search found (host/plan/substitute.hpp), combined with every
//              precision, evaluation and tessellation above and verified like every other candidate.
// Lights that contribute exactly nothing to any fragment (below every surface's horizon for this model,
// beyond their range) are dropped from every configuration, so their code is compiled out.
#pragma once
#include <string>
#include <vector>

#include "cl/runtime.hpp"
#include "mesh/mesh.hpp"
#include "models/material.hpp"
#include "raster/camera.hpp"
#include "shade/shader.hpp"

namespace shadelab {

struct PlanItem {
    Mesh mesh;                 // world space
    Material material;
    bool cull_backfaces = false;
    int icosphere_level = -1;  // >= 0: the mesh is make_icosphere(level) (transformed): coarser levels are tried
    glm::dmat4 icosphere_transform{1.0};
};

struct PlanInput {
    Camera camera;
    int width = 512, height = 512;
    std::vector<PlanItem> items;
    std::vector<Light> lights;
    glm::dvec3 ambient{0.0};
};

enum class PlanMetric { DeltaE2000, Relative };   // max Delta E 2000, or max relative error (linear values)

struct PlanOptions {
    double tolerance = 1.0;
    PlanMetric metric = PlanMetric::DeltaE2000;
    int verify_pixels = 256 * 256;   // verification renders are reduced to about this many pixels (stated)
    bool allow_per_vertex = true;    // false: per-pixel candidates only (the batch renderer's path)
    int timing_repeats = 3;          // at least N kernel timings at full resolution, more for small scenes (best kept)
    bool catalogue = false;          // also search the catalogue per material (host/plan/substitute.hpp)
    // The catalogue search's programs built ahead, all at once, on this many threads (0: every hardware
    // thread); -1: each built when first used, one after another (the old way, kept for bench_e2e_process).
    int build_threads = 0;
};

struct PlanConfig {
    bool simplify_to_lambert = false;
    bool catalogue = false;          // each mesh with its catalogue substitute (Plan::catalogue)
    Precision precision = Precision::Precise;
    bool per_vertex = false;
    int icosphere_level = -1;        // -1: as requested
    std::string label() const;
};

struct PlanMeasure {
    PlanConfig config;
    double de_max = 0.0, de_p99 = 0.0, de_mean = 0.0;   // Delta E 2000 against the reference
    double rel_max = 0.0;                                // max relative error where the reference >= 1e-3
    double error = 0.0;                                  // the metric the tolerance applies to
    double time_ms = 0.0;                                // full-resolution shading cost (best of N)
    double speedup = 1.0;                                // requested time / this time
    bool within = false;
    bool applicable = true;                              // false: the option changes nothing here
};

// The catalogue search's result (host/plan/substitute.hpp).
struct Substitution {
    std::size_t item = 0;
    Material requested;
    Material chosen;                 // == requested when nothing cheaper stays within the tolerance
    double fit_rel_rms = 0.0;        // the fit's own error on the material's fragments (grey)
    double error = 0.0;              // verified: the plan metric of the scene with this substitution alone
    double model_speedup = 1.0;      // this mesh's full-resolution shading time, requested / chosen
    int tried = 0;                   // candidates fitted and verified
};

struct SubstitutionPlan {
    std::vector<Substitution> items;
    double error = 0.0;              // verified: every substitution at once
    bool within = false;
    double requested_ms = 0.0, chosen_ms = 0.0, speedup = 1.0;   // full-resolution shading time, best of runs
    double planning_ms = 0.0;        // the whole search (fits, verifications, timings)
    // Where it went: building the programs ahead, ranking the catalogue by kernel speed, fitting,
    // verification (the frames rasterised, the reference, the requested and candidate renders compared),
    // full-resolution timings.
    double build_ms = 0.0;           // building the search's programs ahead (PlanOptions::build_threads)
    double rank_ms = 0.0, fit_ms = 0.0, verify_ms = 0.0, timing_ms = 0.0;
    int verify_width = 0, verify_height = 0;
};

struct Plan {
    PlanMeasure requested;
    PlanMeasure chosen;
    std::vector<PlanMeasure> candidates;
    std::vector<std::string> dropped_lights;   // "light 2 (directional): contributes 0 to every fragment"
    std::vector<Light> kept_lights;
    int verify_width = 0, verify_height = 0;
    std::vector<std::string> notes;
    std::vector<Material> materials;   // per item: what the chosen configuration renders it with
    bool catalogue_searched = false;
    SubstitutionPlan catalogue;        // when searched: the per-material substitutes the catalogue candidates use
    double planning_ms = 0.0;          // the whole plan: catalogue search, verifications, timings
};

Plan make_plan(Runtime& runtime, const PlanInput& input, const PlanOptions& options);

// The materials a configuration renders with (Lambert keeps the albedo, and a Cook-Torrance-like "kd"
// diffuse weight if the model has one).
Material plan_material(const Material& requested, const PlanConfig& config);

// Prints the plan as a table.
std::string format_plan(const Plan& plan, const PlanOptions& options);

}  // namespace shadelab
