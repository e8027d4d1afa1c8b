// The batch runner: many scenes (or one template scene over a folder of meshes) shaded in one process,
// with one OpenCL context and one program cache for the whole batch.
//
//   jobs   = sorted list of (scene file, mesh override) pairs; --shard i/N keeps index % N == i - 1
//   per job: parse + validate the scene, skip it if its outputs are newer than the scene and its meshes,
//            load the meshes, rasterise (on a std::async thread while the previous job shades, unless
//            overlap is off), shade each mesh's fragments with its material, write the images atomically
//            (on a std::async thread while the next job shades, unless overlap is off)
//   the models of the jobs to render that can share a program get one per light count and precision
//   (Shader::prepare_many), built before the first job needing it shades
//   a failing job is reported in one line "scene 'x.json': ..." and the batch goes on;
//   a JSON and a CSV report give, per job, fragments, rasterisation and kernel time, Mfrag/s and the error.
#pragma once
#include <cstddef>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "cl/runtime.hpp"
#include "pipeline/pipeline.hpp"
#include "scene/progress.hpp"

namespace shadelab {

struct BatchOptions {
    std::vector<std::string> scenes;   // scene files, or folders (every *.json directly inside)
    std::string mesh_dir;              // template mode: every .obj .off .ply .stl directly inside ...
    std::string template_scene;        // ... shaded with this scene (its single mesh entry is replaced);
                                       // may be combined with `scenes`: one job list holds both
    std::string out_dir = "out";       // relative output paths of the scenes are relative to this folder
    std::string report;                // JSON report path (CSV beside it, same stem); empty: default below
    int shard_index = 1;               // 1-based
    int shard_count = 1;
    bool force = false;                // re-render outputs that are up to date
    bool overlap = true;               // rasterise job i+1 and write job i-1 while job i shades
    int raster_threads = 0;            // 0: all hardware threads
    ProgressStyle progress = ProgressStyle::Auto;
    double tolerance = 0.0;            // > 0: plan each job (docs/planner.md) and shade with the chosen config
    bool tolerance_relative = false;   // the tolerance is a max relative error, not a max Delta E 2000
    bool tolerance_catalogue = true;   // the plan searches the catalogue per material (docs/planner.md)
    std::ostream* log = nullptr;       // progress, failures, summary; nullptr: std::cerr
};

struct BatchJob {
    std::size_t index = 0;             // position in the full sorted list (before sharding)
    std::string scene;                 // scene file (template mode: the template)
    std::string mesh;                  // template mode: the mesh replacing the scene's mesh path; else empty
    std::string label() const;         // "scene 'x.json'" or "scene 't.json' with mesh 'm.obj'"
};

struct JobResult {
    enum class Status { Ok, Skipped, Failed };
    BatchJob job;
    Status status = Status::Ok;
    std::string name;
    std::vector<std::string> outputs;
    std::vector<std::string> models;   // per mesh: "phong" or "gradient(lambert,phong)"
    std::string error;                 // the one-line message for a failed job
    std::vector<std::string> warnings;
    int width = 0, height = 0;
    std::size_t triangles = 0;
    std::size_t fragments = 0;
    // load (parse the scene, load and transform the meshes), raster, build (program builds; 0 when every program
    // was cached), kernel (device time of the shading kernels, profiling events), shade (wall time of shading:
    // build + upload + kernel + download), resolve (images and AOVs), write: the render path's stages.
    pipeline::StageTimes times;
    double mfrag_per_s() const;        // fragments / kernel time, in millions per second (0 if no kernel ran)
};
const char* status_name(JobResult::Status s);

struct BatchSummary {
    std::vector<JobResult> jobs;
    std::size_t planned_total = 0;     // jobs before sharding
    int shard_index = 1, shard_count = 1;
    std::size_t ok = 0, skipped = 0, failed = 0;
    double wall_ms = 0.0;
    double wait_ms = 0.0;              // time the shading thread waited for the next job's rasterisation
    double write_wait_ms = 0.0;        // ... and for the previous job's images to be written
    bool overlap = true;
    std::size_t programs_built = 0;    // by this batch (the runtime may have built others before)
    std::string device;
    std::string report_json, report_csv;
    int exit_code() const { return failed ? 1 : 0; }
};

// "i/N" with 1 <= i <= N; throws shadelab::Error.
std::pair<int, int> parse_shard(const std::string& text);

// The full sorted job list and this shard's part of it. Throws shadelab::Error when there is nothing to
// plan (no scenes, a missing mesh folder or template); a missing scene file is a job that will fail.
std::vector<BatchJob> plan_all_jobs(const BatchOptions& options);
std::vector<BatchJob> plan_batch(const BatchOptions& options);

// Runs the batch with the given runtime (one context and program cache for everything). Never throws
// for a bad scene or mesh: those are failed jobs in the summary. Writes the report files.
BatchSummary run_batch(const BatchOptions& options, Runtime& runtime);

void write_report_json(const BatchSummary& summary, const std::string& path);
void write_report_csv(const BatchSummary& summary, const std::string& path);

}  // namespace shadelab
