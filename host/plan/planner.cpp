#include "plan/planner.hpp"
#include "pipeline/pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "color/image_compare.hpp"
#include "core/error.hpp"
#include "image/image.hpp"
#include "models/catalogue.hpp"
#include "raster/raster.hpp"
#include "reference/reference.hpp"
#include "plan/substitute.hpp"
#include "shade/gouraud.hpp"

namespace shadelab {

namespace {

using clock_type = std::chrono::steady_clock;

// One rasterisation of every item at one size (and tessellation): per item a one-mesh job of the render path
// (host/pipeline/) and its fragments, which the candidates are shaded and timed with.
struct Frame {
    int width = 0, height = 0;
    std::vector<pipeline::Job> jobs;
    std::vector<pipeline::Frame> items;
    const FragmentBuffer& fragments(std::size_t k) const { return items[k].fb; }
};

Frame raster_frame(const PlanInput& in, int w, int h, int level) {
    Frame f;
    f.width = w;
    f.height = h;
    for (const PlanItem& it : in.items) {
        Mesh m = it.mesh;
        if (it.icosphere_level >= 0 && level >= 0 && level != it.icosphere_level) {
            m = make_icosphere(level);
            m.transform(it.icosphere_transform);
        }
        // Each item rasterised on its own by the render path: the planner shades and times every item's
        // fragments whole, then composes by depth as the render path's merge does.
        pipeline::Job job;
        job.meshes.push_back(pipeline::JobMesh{std::move(m), Material{}, it.cull_backfaces});
        job.camera = in.camera;
        job.width = w;
        job.height = h;
        job.ambient = in.ambient;
        pipeline::StageTimes times;
        f.items.push_back(pipeline::raster(job, times));
        f.jobs.push_back(std::move(job));
    }
    return f;
}

// Nearest item wins per pixel (ties: the earlier item), as the batch renderer composes meshes.
Image compose(const Frame& f, const std::vector<std::vector<float>>& planes) {
    Image img(f.width, f.height, 4);
    std::vector<float> zbuf(std::size_t(f.width) * f.height, std::numeric_limits<float>::infinity());
    for (std::size_t k = 0; k < f.items.size(); ++k) {
        const FragmentBuffer& fb = f.fragments(k);
        const std::size_t n = fb.size();
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t p = std::size_t(fb.pixel[i]);
            if (!(fb.depth[i] < zbuf[p])) continue;
            zbuf[p] = fb.depth[i];
            for (std::size_t c = 0; c < 3; ++c) img.pixels[p * 4 + c] = planes[k][c * n + i];
            img.pixels[p * 4 + 3] = 1.0f;
        }
    }
    return img;
}

struct Shaded {
    std::vector<std::vector<float>> planes;
    double time_ms = 0.0;   // the shade stage's kernel device time (+ its interpolation, per vertex)
};

// The material item k renders with under cfg: its catalogue substitute, or the requested one (or Lambert).
Material item_material(const PlanInput& in, std::size_t k, const PlanConfig& cfg, const std::vector<Material>& subs) {
    return cfg.catalogue ? subs[k] : plan_material(in.items[k].material, cfg);
}

// Every item shaded by the render path's shade stage under cfg, timed by its StageTimes (the clock the render
// report uses): kernel device time, plus the host interpolation of per-vertex shading.
Shaded shade_frame(Shader& shader, Frame& f, const PlanInput& in, const std::vector<Light>& lights,
                   const PlanConfig& cfg, const std::vector<Material>& subs) {
    Shaded s;
    for (std::size_t k = 0; k < f.items.size(); ++k) {
        pipeline::Job& job = f.jobs[k];
        job.meshes.front().material = item_material(in, k, cfg, subs);
        job.lights = lights;
        job.precision = cfg.precision;
        job.per_vertex = cfg.per_vertex;
        pipeline::StageTimes times;
        s.planes.push_back(pipeline::shade(shader, job, f.items[k], times));
        s.time_ms += times.kernel_ms + times.interpolate_ms;
    }
    return s;
}

// The lights that contribute to some fragment of some mesh (for its model: a wrap model lights the back side, so
// the test is the reference itself, not NoL); the others go to plan.dropped_lights.
void drop_silent_lights(const PlanInput& in, const Frame& full, Plan& plan) {
    for (std::size_t j = 0; j < in.lights.size(); ++j) {
        bool contributes = false;
        for (std::size_t k = 0; k < full.items.size() && !contributes; ++k) {
            const FragmentBuffer& fb = full.fragments(k);
            for (std::size_t i = 0; i < fb.size() && !contributes; ++i) {
                const glm::dvec3 P{fb.px[i], fb.py[i], fb.pz[i]}, N{fb.nx[i], fb.ny[i], fb.nz[i]};
                const glm::dvec3 v = ref::shade_point(P, N, glm::normalize(in.camera.eye - P), in.items[k].material,
                                                      {in.lights[j]}, glm::dvec3(0.0));
                contributes = v.x != 0.0 || v.y != 0.0 || v.z != 0.0;
            }
        }
        if (contributes) plan.kept_lights.push_back(in.lights[j]);
        else
            plan.dropped_lights.push_back("light " + std::to_string(j + 1) +
                                          (in.lights[j].type == Light::Type::Directional ? " (directional)" : " (point)") +
                                          ": contributes nothing to any fragment, compiled out");
    }
}

// The verification size (the image reduced to about opt.verify_pixels), noted in the plan.
void choose_verify_size(const PlanInput& in, const PlanOptions& opt, Plan& plan) {
    const double pixels = double(in.width) * in.height;
    const double scale = pixels > opt.verify_pixels ? std::sqrt(opt.verify_pixels / pixels) : 1.0;
    plan.verify_width = std::max(1, int(std::lround(in.width * scale)));
    plan.verify_height = std::max(1, int(std::lround(in.height * scale)));
    if (scale < 1.0)
        plan.notes.push_back("errors verified at " + std::to_string(plan.verify_width) + "x" +
                             std::to_string(plan.verify_height) + " (reduced from " + std::to_string(in.width) + "x" +
                             std::to_string(in.height) + "); timings at full resolution");
}

Image reference_image(const PlanInput& in, const Frame& verify) {
    std::vector<std::vector<float>> planes;
    for (std::size_t k = 0; k < verify.items.size(); ++k)
        planes.push_back(ref::shade_fragments(verify.fragments(k), in.items[k].material, in.lights, in.ambient,
                                              in.camera.eye));
    return compose(verify, planes);
}

// The catalogue search's substitutes (one per item), when asked for and possible.
std::vector<Material> search_catalogue(Runtime& runtime, const PlanInput& in, const PlanOptions& opt, Plan& plan) {
    std::vector<Material> subs;
    if (!opt.catalogue) return subs;
    if (in.lights.empty()) {
        plan.notes.push_back("the catalogue search needs at least one light: skipped");
        return subs;
    }
    plan.catalogue = plan_substitutions(runtime, in, opt);
    plan.catalogue_searched = true;
    for (const auto& it : plan.catalogue.items) subs.push_back(it.chosen);
    return subs;
}

// Every combination of the dimensions that applies to the scene; the requested configuration first.
std::vector<PlanConfig> plan_configs(const PlanInput& in, const PlanOptions& opt, const std::vector<int>& levels,
                                     bool any_substitute) {
    bool can_simplify = false;
    for (const auto& it : in.items) can_simplify = can_simplify || (it.material.model != "lambert" && it.material.children.empty());
    std::vector<PlanConfig> configs;
    auto add_all = [&](bool simplify, bool catalogue) {
        for (Precision p : {Precision::Precise, Precision::Fast})
            for (bool pv : {false, true})
                for (int l : levels)
                    if (!pv || opt.allow_per_vertex) configs.push_back(PlanConfig{simplify, catalogue, p, pv, l});
    };
    add_all(false, false);
    if (can_simplify) add_all(true, false);
    if (any_substitute) add_all(false, true);
    return configs;
}

// One configuration: its error against the reference at the verification size and its full-resolution time, best
// of at least opt.timing_repeats runs and more for small scenes (until 25 ms of shading have been timed, at most 40
// runs), so sub-millisecond kernels are not compared on jitter.
PlanMeasure measure_config(Shader& shader, const PlanInput& in, const PlanOptions& opt, const PlanConfig& cfg,
                           Frame& verify, Frame& full, const Image& reference, const std::vector<Light>& lights,
                           const std::vector<Material>& subs) {
    PlanMeasure m;
    m.config = cfg;
    const Shaded v = shade_frame(shader, verify, in, lights, cfg, subs);
    const ImageDiff d = compare_images(compose(verify, v.planes), reference, 1e-3);
    m.de_max = d.de_max;
    m.de_p99 = d.de_p99;
    m.de_mean = d.de_mean;
    m.rel_max = d.rel_max;
    // Pixels covered by one render only (a coarser sphere's silhouette) count as full errors.
    if (d.coverage_mismatch) { m.de_max = std::max(m.de_max, 100.0); m.rel_max = std::max(m.rel_max, 1.0); }
    m.error = opt.metric == PlanMetric::DeltaE2000 ? m.de_max : m.rel_max;
    m.within = m.error <= opt.tolerance;
    double best = std::numeric_limits<double>::infinity(), spent = 0.0;
    for (int r = 0; r < 40 && (r < std::max(1, opt.timing_repeats) || spent < 25.0); ++r) {
        const double t = shade_frame(shader, full, in, lights, cfg, subs).time_ms;
        best = std::min(best, t);
        spent += t;
    }
    m.time_ms = best;
    return m;
}

// The requested configuration is the first candidate; the cheapest within the tolerance replaces it only for a
// clear gain (5%): timings on a shared machine jitter, and an equal-cost change (fast mode of a model without
// transcendental calls) is no reason to move off what was asked.
void choose(Plan& plan) {
    plan.requested = plan.candidates.front();
    plan.chosen = plan.requested;
    for (auto& m : plan.candidates) {
        m.speedup = m.time_ms > 0.0 ? plan.requested.time_ms / m.time_ms : 1.0;
        if (m.within && m.time_ms < 0.95 * plan.chosen.time_ms) plan.chosen = m;
    }
    plan.chosen.speedup = plan.chosen.time_ms > 0.0 ? plan.requested.time_ms / plan.chosen.time_ms : 1.0;
    if (!plan.requested.within)
        plan.notes.push_back("even the requested configuration is off the double reference by more than the tolerance "
                             "(float rounding): the requested configuration is kept");
}

}  // namespace

std::string PlanConfig::label() const {
    std::string s = catalogue ? "catalogue per material" : simplify_to_lambert ? "lambert" : "as requested";
    s += std::string(", ") + precision_name(precision);
    s += per_vertex ? ", per vertex" : ", per pixel";
    if (icosphere_level >= 0) s += ", icosphere level " + std::to_string(icosphere_level);
    return s;
}

Material plan_material(const Material& requested, const PlanConfig& config) {
    if (!config.simplify_to_lambert || requested.model == "lambert" || !requested.children.empty()) return requested;
    Material m;
    m.model = "lambert";
    m.albedo = requested.albedo;
    const auto kd = requested.params.find("kd");   // Cook-Torrance-like diffuse weight
    if (kd != requested.params.end()) m.albedo *= kd->second;
    return resolve_material(m);
}

Plan make_plan(Runtime& runtime, const PlanInput& in_raw, const PlanOptions& opt) {
    if (in_raw.items.empty()) throw Error("plan: the scene has no meshes");
    if (!(opt.tolerance > 0.0) || !std::isfinite(opt.tolerance))
        throw Error("plan: tolerance must be a finite number > 0 (Delta E 2000 or relative error)");
    const auto t_start = clock_type::now();
    PlanInput in = in_raw;
    for (auto& it : in.items) it.material = resolve_material(it.material);
    Shader shader(runtime);
    Plan plan;

    // Full resolution: the fragments the timings and the light test run on; errors at the verification size.
    Frame full = raster_frame(in, in.width, in.height, -1);
    drop_silent_lights(in, full, plan);
    choose_verify_size(in, opt, plan);
    Frame verify = raster_frame(in, plan.verify_width, plan.verify_height, -1);
    const Image reference = reference_image(in, verify);

    // The catalogue search per material (fits, each verified and timed); its substitutes become one more
    // dimension, combined with the others and verified again below.
    const std::vector<Material> subs = search_catalogue(runtime, in, opt, plan);
    bool any_substitute = false;
    for (const auto& it : plan.catalogue.items) any_substitute = any_substitute || it.chosen.model != it.requested.model;
    int sphere_level = -1;
    for (const auto& it : in.items) sphere_level = std::max(sphere_level, it.icosphere_level);
    std::vector<int> levels{-1};
    for (int l = sphere_level - 1; l >= std::max(0, sphere_level - 3); --l) levels.push_back(l);
    std::vector<Frame> full_levels, verify_levels;   // per entry of `levels`
    for (int l : levels) {
        full_levels.push_back(l < 0 ? full : raster_frame(in, in.width, in.height, l));
        verify_levels.push_back(l < 0 ? verify : raster_frame(in, plan.verify_width, plan.verify_height, l));
    }
    for (const PlanConfig& cfg : plan_configs(in, opt, levels, any_substitute)) {
        const std::size_t li = std::size_t(std::find(levels.begin(), levels.end(), cfg.icosphere_level) - levels.begin());
        plan.candidates.push_back(measure_config(shader, in, opt, cfg, verify_levels[li], full_levels[li], reference,
                                                 plan.kept_lights, subs));
    }
    choose(plan);
    for (std::size_t k = 0; k < in.items.size(); ++k) plan.materials.push_back(item_material(in, k, plan.chosen.config, subs));
    plan.planning_ms = std::chrono::duration<double, std::milli>(clock_type::now() - t_start).count();
    return plan;
}

std::string format_plan(const Plan& p, const PlanOptions& opt) {
    std::ostringstream s;
    const char* metric = opt.metric == PlanMetric::DeltaE2000 ? "max Delta E 2000" : "max relative error";
    s << "tolerance: " << metric << " <= " << opt.tolerance << "\n";
    if (p.catalogue_searched) s << format_substitutions(p.catalogue, opt);
    for (const auto& d : p.dropped_lights) s << "dropped " << d << "\n";
    for (const auto& n : p.notes) s << "note: " << n << "\n";
    s << std::left << std::setw(50) << "configuration" << std::right << std::setw(12) << "dE00 max" << std::setw(12)
      << "dE00 p99" << std::setw(12) << "rel max" << std::setw(12) << "time ms" << std::setw(10) << "speed-up" << "\n";
    for (const auto& m : p.candidates) {
        const bool chosen = m.config.label() == p.chosen.config.label();
        s << std::left << std::setw(50) << ((chosen ? "* " : (m.within ? "  " : "x ")) + m.config.label()) << std::right
          << std::setw(12) << std::setprecision(3) << m.de_max << std::setw(12) << m.de_p99 << std::setw(12) << m.rel_max
          << std::setw(12) << std::setprecision(4) << m.time_ms << std::setw(10) << std::setprecision(3) << m.speedup << "\n";
    }
    s << "chosen: " << p.chosen.config.label() << " (" << metric << " " << p.chosen.error << ", measured speed-up "
      << p.chosen.speedup << "x)\n";
    if (p.chosen.config.catalogue)
        for (std::size_t k = 0; k < p.materials.size(); ++k) {
            s << "  mesh " << (k + 1) << " renders with " << p.materials[k].model << "(";
            bool first = true;
            for (const auto& [name, v] : p.materials[k].params)
                s << (first ? "" : ", ") << name << "=" << std::setprecision(5) << v, first = false;
            s << ")\n";
        }
    s << "planning took " << std::setprecision(4) << p.planning_ms << " ms";
    if (p.catalogue_searched)
        s << " (catalogue search " << p.catalogue.planning_ms << " ms; verifying and timing the " << p.candidates.size()
          << " configurations the rest)";
    s << " against " << p.chosen.time_ms << " ms of shading the chosen configuration (" << p.requested.time_ms
      << " ms requested), timed by the render path's shade stage\n";
    s << "(* chosen, x over tolerance; time = full-resolution shading: kernel device time, plus host interpolation for per-vertex)\n";
    return s.str();
}

}  // namespace shadelab
