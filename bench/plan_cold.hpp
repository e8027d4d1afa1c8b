// bench_e2e_process's planning rows (issue 11: "state how long planning takes next to how long rendering
// takes"; issue 13 item 6: the cold first run): `shadelab plan` of each bundled scene in a fresh process, with
// PoCL's and shadelab's program caches empty (cold) or filled by the run before (warm), the catalogue search's
// programs built ahead on every hardware thread (PlanOptions::build_threads, the default) or each at first use
// (the old way); next to it the render of the chosen configuration (raster, shade, resolve: the pipeline's
// StageTimes, programs already built by the plan).
#pragma once
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "pipeline/pipeline.hpp"
#include "plan/planner.hpp"
#include "scene/scene.hpp"

namespace shadelab::bench {

// The child: plans `scene_file` and renders the plan once; prints "plan <ms> search <ms> programs <ms> render <ms>".
inline int child_plan(const std::string& scene_file, int build_threads) {
    const Scene s = load_scene(scene_file);
    const SceneGeometry geo = load_scene_geometry(s, [](const std::string& p) { return load_mesh(p); });
    const PlanInput in = plan_input_for(s, geo);
    PlanOptions o;
    o.catalogue = true;
    o.build_threads = build_threads;
    Runtime rt;
    const Plan p = make_plan(rt, in, o);
    pipeline::Job job;
    for (std::size_t k = 0; k < in.items.size(); ++k)
        job.meshes.push_back(pipeline::JobMesh{in.items[k].mesh, p.materials[k], in.items[k].cull_backfaces});
    job.camera = in.camera;
    job.width = in.width;
    job.height = in.height;
    job.lights = p.kept_lights;
    job.ambient = in.ambient;
    job.precision = p.chosen.config.precision;
    job.per_vertex = p.chosen.config.per_vertex;
    Shader shader(rt);
    const pipeline::StageTimes t = pipeline::run_job(shader, job).times;
    std::printf("plan %.1f search %.1f programs %.1f render %.1f\n", p.planning_ms, p.catalogue.planning_ms,
                p.catalogue.build_ms, t.raster_ms + t.shade_ms + t.resolve_ms);
    return 0;
}

struct PlanRun {
    double plan_ms = 0, search_ms = 0, programs_ms = 0, render_ms = 0;
};

// Runs the child in a fresh process with the given caches; `run` is bench_e2e_process's command runner.
template <class Run>
PlanRun run_plan_child(Run run, const std::string& self, const std::string& scene, const std::string& pocl_cache,
                       const std::string& program_cache, int build_threads) {
    const std::string out = run("POCL_CACHE_DIR='" + pocl_cache + "' SHADELAB_PROGRAM_CACHE='" + program_cache + "' '" +
                                self + "' --child-plan '" + scene + "' --build-threads " + std::to_string(build_threads));
    PlanRun r;
    if (std::sscanf(out.c_str(), "plan %lf search %lf programs %lf render %lf", &r.plan_ms, &r.search_ms,
                    &r.programs_ms, &r.render_ms) != 4)
        throw Error("unexpected output of the plan child: " + out.substr(0, 200));
    return r;
}

// One row per scene and case: planning (of which the catalogue search, of which building the programs ahead) and
// rendering, and the ratio of the cold plan the old way to this one.
template <class Run>
void bench_planning(Run run, const std::string& self, const std::filesystem::path& tmp,
                    const std::vector<std::string>& scenes) {
    std::printf("\n== planning (shadelab plan, catalogue search, tolerance 1), fresh process each; render = the chosen "
                "configuration's raster + shade + resolve\n");
    std::printf("%-18s %-44s %10s %10s %10s %10s\n", "scene", "case", "plan", "search", "programs", "render");
    int n = 0;
    for (const std::string& scene : scenes) {
        const std::string name = std::filesystem::path(scene).filename().string();
        const std::string base = (tmp / ("plan-" + std::to_string(n++))).string();
        struct Step {
            const char* label;
            std::string pocl, programs;
            int threads;
        };
        const std::vector<Step> steps = {
            {"cold, each program built at first use (old)", base + "-pocl-a", base + "-prog-a", -1},
            {"cold, programs built ahead in parallel", base + "-pocl-b", base + "-prog-b", 0},
            {"warm (caches of the run before)", base + "-pocl-b", base + "-prog-b", 0},
        };
        double old_cold = 0;
        for (const Step& s : steps) {
            const PlanRun r = run_plan_child(run, self, scene, s.pocl, s.programs, s.threads);
            if (old_cold == 0) old_cold = r.plan_ms;
            std::printf("%-18s %-44s %8.0fms %8.0fms %8.0fms %8.1fms   %.2fx the old cold plan\n", name.c_str(),
                        s.label, r.plan_ms, r.search_ms, r.programs_ms, r.render_ms, old_cold / r.plan_ms);
        }
    }
}

}  // namespace shadelab::bench
