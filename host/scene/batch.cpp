// The batch runner (see batch.hpp for the shape of a run).
#include "scene/batch.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <future>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/atomic_file.hpp"
#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "core/limits.hpp"
#include "image/image.hpp"
#include "mesh/mesh.hpp"
#include "pipeline/pipeline.hpp"
#include "plan/plan_job.hpp"
#include "plan/planner.hpp"
#include "raster/raster.hpp"
#include "scene/scene.hpp"
#include "shade/shade_program.hpp"
#include "shade/shader.hpp"

namespace fs = std::filesystem;

namespace shadelab {

namespace {

using clock_type = std::chrono::steady_clock;
double ms_since(clock_type::time_point t0) {
    return std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();
}

bool is_mesh_file(const fs::path& p) {
    const std::string e = lower_ext(p.string());
    return e == ".obj" || e == ".off" || e == ".ply" || e == ".stl";
}

std::string model_label(const Material& m) {
    std::string s = m.model;
    if (!m.children.empty()) {
        s += "(";
        for (std::size_t i = 0; i < m.children.size(); ++i) s += (i ? "," : "") + m.children[i].model;
        s += ")";
    }
    return s;
}

// Loaded meshes, kept across jobs (several scenes often share one mesh). Keyed by path and modification
// time; a few entries only, oldest dropped first.
class MeshCache {
public:
    Mesh get(const std::string& path) {
        std::error_code ec;
        const auto mtime = fs::last_write_time(path, ec);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            for (const auto& e : entries_)
                if (e.path == path && e.mtime == mtime) return e.mesh;
        }
        Mesh m = load_mesh(path);
        std::lock_guard<std::mutex> lock(mutex_);
        entries_.push_back({path, mtime, m});
        if (entries_.size() > kEntries) entries_.erase(entries_.begin());
        return m;
    }

private:
    static constexpr std::size_t kEntries = 8;
    struct Entry {
        std::string path;
        fs::file_time_type mtime;
        Mesh mesh;
    };
    std::mutex mutex_;
    std::vector<Entry> entries_;
};

// A job after parsing and rasterisation, ready to shade (or already settled: skipped or failed).
struct Prepared {
    JobResult result;
    Scene scene;
    pipeline::Job job;                     // the scene as the render path takes it (planned when --tolerance)
    pipeline::Frame frame;
    bool settled = false;                  // skipped or failed: nothing to shade
    std::vector<pipeline::OutputImage> images;   // shaded, waiting to be written
};

// Outputs are up to date when each exists and is newer than the scene file and every mesh it reads.
bool up_to_date(const Scene& s) {
    std::error_code ec;
    auto newest = fs::last_write_time(s.file, ec);
    if (ec) return false;
    for (const auto& m : s.meshes) {
        const auto t = fs::last_write_time(m.path, ec);
        if (ec) return false;
        newest = std::max(newest, t);
    }
    for (const auto& o : s.outputs.all()) {
        const auto t = fs::last_write_time(o, ec);
        if (ec || !(t > newest)) return false;
    }
    return true;
}


class Runner {
public:
    Runner(const BatchOptions& o, Runtime& rt) : opt_(o), rt_(rt), shader_(rt) {}

    BatchSummary run();

private:
    void run_jobs(const std::vector<BatchJob>& jobs, BatchSummary& sum, std::ostream& log);
    Prepared prepare(const BatchJob& job);
    void shade(Prepared& p);
    static void write(Prepared& p);
    std::string claim_outputs_note(const BatchJob& job, const Scene& s);
    void write_reports(BatchSummary& sum) const;
    void remove_stale(std::ostream& log) const;
    void log_summary(std::ostream& log, const BatchSummary& sum, std::size_t all_jobs) const;
    void index_outputs(const std::vector<BatchJob>& all);
    void plan_shared_programs(const std::vector<BatchJob>& jobs);
    void prepare_shared_program(Prepared& p);

    const BatchOptions& opt_;
    Runtime& rt_;
    Shader shader_;
    MeshCache meshes_;
    std::map<std::string, std::size_t> first_writer_;   // output path -> index of the first job writing it
    std::map<std::size_t, std::string> job_labels_;
    std::set<std::string> output_folders_;               // every folder an output of the batch goes to
    // The materials of the jobs to render, by what their shade kernels share (every light's kind, in order, and
    // the precision; a scene's view is always a perspective one, prepare_many's default): each group's models are
    // built into programs of many models (Shader::prepare_many) when its first job shades, instead of one program
    // per model (docs/speed.md, "A warm batch").
    struct SharedPrograms {
        std::vector<Material> materials;
        std::vector<Light> lights;           // the first job's: prepare_many needs their count and kinds only
        Precision precision = Precision::Precise;
        bool prepared = false;
    };
    std::map<std::string, SharedPrograms> shared_;
};

// The kernels of two jobs can share a program when these agree (shade_program's defines besides the model's).
std::string shared_program_group(const std::vector<Light>& lights, Precision precision) {
    return light_kinds(lights) + " " + precision_name(precision);   // the count and every light's kind
}

// Two jobs writing the same file would race (and the last one would silently win). Every job of the full
// list is parsed once up front (cheap: no meshes are read), so every shard agrees on which job owns a
// path: the first in the sorted list. Jobs whose scene does not parse are left to fail on their own.
void Runner::index_outputs(const std::vector<BatchJob>& all) {
    for (const auto& j : all) {
        job_labels_[j.index] = j.label();
        try {
            const Scene s = load_scene(j.scene, SceneLoadOptions{opt_.out_dir, j.mesh});
            for (const auto& o : s.outputs.all()) {
                first_writer_.emplace(fs::path(o).lexically_normal().string(), j.index);
                output_folders_.insert(fs::path(o).lexically_normal().parent_path().string());
            }
        } catch (const std::exception&) {   // the job fails on its own, in turn, with its message
        }
    }
}

// The groups of shared_ for `jobs`, from their scene files (parsed again: cheap, no meshes are read). Jobs
// whose outputs are up to date are left out (they will not shade), and so is everything when the jobs are
// planned (--tolerance: the plan chooses the models).
void Runner::plan_shared_programs(const std::vector<BatchJob>& jobs) {
    if (opt_.tolerance > 0.0) return;
    for (const auto& j : jobs) {
        try {
            const Scene s = load_scene(j.scene, SceneLoadOptions{opt_.out_dir, j.mesh});
            if (!opt_.force && up_to_date(s)) continue;
            SharedPrograms& g = shared_[shared_program_group(s.lights, s.precision)];
            if (g.materials.empty()) {
                g.lights = s.lights;
                g.precision = s.precision;
            }
            for (const auto& m : s.meshes) g.materials.push_back(m.material);
        } catch (const std::exception&) {   // the job fails on its own, in turn, with its message
        }
    }
}

// Before the job's first shade: its group's programs of many models, built once for the whole batch. The
// time is the job's build time. A failed build leaves each model to build its own program, as without it.
void Runner::prepare_shared_program(Prepared& p) {
    const auto it = shared_.find(shared_program_group(p.job.lights, p.job.precision));
    if (it == shared_.end() || it->second.prepared) return;
    SharedPrograms& g = it->second;
    g.prepared = true;
    const auto t0 = clock_type::now();
    try {
        shader_.prepare_many(g.materials, g.lights, g.precision);
    } catch (const Error& e) {
        p.result.warnings.push_back(std::string("the shared program of this batch's models did not build, each "
                                                "model builds its own: ") + e.what());
    }
    const double ms = ms_since(t0);
    p.result.times.build_ms += ms;
    p.result.times.shade_ms += ms;
}

std::string Runner::claim_outputs_note(const BatchJob& job, const Scene& s) {
    for (const auto& o : s.outputs.all()) {
        const auto it = first_writer_.find(fs::path(o).lexically_normal().string());
        if (it != first_writer_.end() && it->second != job.index)
            return "output '" + o + "' is also written by " + job_labels_[it->second] +
                   ", earlier in the batch: give this scene another name or outputs (e.g. \"{scene}_{mesh}.png\")";
    }
    return {};
}

// The scene as the render path takes it: its world meshes (moved out of `geo`), camera, lights and outputs.
pipeline::Job job_for(const Scene& s, SceneGeometry& geo, int raster_threads) {
    pipeline::Job job;
    for (std::size_t i = 0; i < geo.meshes.size(); ++i)
        job.meshes.push_back(pipeline::JobMesh{std::move(geo.meshes[i]), s.meshes[i].material, s.meshes[i].cull_backfaces});
    job.camera = geo.camera;
    job.width = s.width;
    job.height = s.height;
    job.lights = s.lights;
    job.ambient = s.ambient;
    job.background = s.background;
    job.precision = s.precision;
    job.per_vertex = s.per_vertex;
    for (const auto* o : {&s.outputs.png, &s.outputs.exr})
        if (!o->empty()) job.outputs.colour.push_back(*o);
    job.outputs.depth = s.outputs.depth;
    job.outputs.normal = s.outputs.normal;
    job.raster_threads = raster_threads;
    return job;
}

// --tolerance: the job planned on its own geometry, the choice told in a warning line. Per-pixel candidates
// only, so that a batch's plans are what they were before per-vertex scenes existed (docs/batch.md).
std::string plan_note(Runtime& rt, const BatchOptions& opt, pipeline::Job& job, pipeline::StageTimes& times) {
    std::vector<std::string> requested;
    for (const auto& m : job.meshes) requested.push_back(m.material.model);
    PlanOptions po;
    po.tolerance = opt.tolerance;
    po.metric = opt.tolerance_relative ? PlanMetric::Relative : PlanMetric::DeltaE2000;
    po.allow_per_vertex = false;
    po.catalogue = opt.tolerance_catalogue;
    const Plan plan = plan_job(rt, job, po, times);
    std::ostringstream note;
    note << "plan: " << plan.chosen.config.label() << " (error " << plan.chosen.error << ", measured speed-up "
         << plan.chosen.speedup << "x, planning " << plan.planning_ms << " ms";
    if (plan.chosen.config.catalogue)
        for (std::size_t k = 0; k < plan.materials.size(); ++k)
            if (plan.materials[k].model != requested[k])
                note << ", mesh " << (k + 1) << " " << requested[k] << " -> " << plan.materials[k].model;
    if (!plan.dropped_lights.empty()) note << ", " << plan.dropped_lights.size() << " light(s) compiled out";
    note << ")";
    return note.str();
}

// Fills the report fields the scene file alone gives.
void describe_scene(JobResult& r, const Scene& s) {
    r.name = s.name;
    r.outputs = s.outputs.all();
    r.warnings = s.warnings;
    r.width = s.width;
    r.height = s.height;
    for (const auto& m : s.meshes) r.models.push_back(model_label(m.material));
}

void fail(Prepared& p, const std::string& message) {
    p.result.status = JobResult::Status::Failed;
    p.result.error = message;
    p.settled = true;
    p.images.clear();
}

Prepared Runner::prepare(const BatchJob& job) {
    Prepared p;
    JobResult& r = p.result;
    r.job = job;
    const auto t0 = clock_type::now();
    try {
        p.scene = load_scene(job.scene, SceneLoadOptions{opt_.out_dir, job.mesh});
        const Scene& s = p.scene;
        describe_scene(r, s);
        const std::string clash = claim_outputs_note(job, s);
        if (!clash.empty()) throw Error("scene '" + s.file + "': " + clash);
        if (!opt_.force && up_to_date(s)) {
            r.status = JobResult::Status::Skipped;
            p.settled = true;
            r.times.load_ms = ms_since(t0);
            return p;
        }
        check_memory("scene '" + s.file + "': resolution " + std::to_string(s.width) + "x" + std::to_string(s.height),
                     double(s.width) * double(s.height) * kRenderBytesPerPixel);
        SceneGeometry geo = load_scene_geometry(s, [this](const std::string& path) { return meshes_.get(path); });
        r.triangles = geo.triangles;
        p.job = job_for(s, geo, opt_.raster_threads);
        p.result.times.load_ms = ms_since(t0);
        if (opt_.tolerance > 0.0) r.warnings.push_back(plan_note(rt_, opt_, p.job, p.result.times));
        p.job.triangle_ids = p.job.per_vertex;   // planned above (per-pixel candidates only): the job is final
        p.frame = pipeline::raster(p.job, p.result.times);
        r.fragments = p.frame.fb.size();
        if (p.frame.fb.empty())
            r.warnings.push_back("the meshes cover no pixel from this camera: the images hold the background only");
    } catch (const Error& e) {
        fail(p, e.what());
        if (p.result.times.load_ms == 0.0) p.result.times.load_ms = ms_since(t0);
    } catch (const std::exception& e) {
        fail(p, job.label() + ": internal error: " + e.what());
    }
    return p;
}

void Runner::shade(Prepared& p) {
    const Scene& s = p.scene;
    try {
        prepare_shared_program(p);
        const auto rgb = pipeline::shade(shader_, p.job, p.frame, p.result.times);
        // The images, composed here; written by write() (on its own thread when overlapping).
        p.images = pipeline::resolve(p.job, p.frame, rgb, p.result.times);
        p.frame = pipeline::Frame{};   // not needed any more: free it before the next job's arrives
    } catch (const Error& e) {
        const std::string what = e.what();
        fail(p, what.rfind("scene '", 0) == 0 ? what : "scene '" + s.file + "': " + what);
    } catch (const std::exception& e) {
        fail(p, "scene '" + s.file + "': internal error: " + e.what());
    }
}

// Writes every image atomically (write_image: temporary file, then rename). Never throws.
void Runner::write(Prepared& p) {
    try {
        pipeline::write(p.images, p.result.times);
    } catch (const Error& e) {
        fail(p, "scene '" + p.scene.file + "': " + e.what());
    } catch (const std::exception& e) {
        fail(p, "scene '" + p.scene.file + "': internal error while writing: " + e.what());
    }
    p.images.clear();
}

std::string job_line(const JobResult& r, std::size_t pos, std::size_t count) {
    const std::string head = "[" + std::to_string(pos) + "/" + std::to_string(count) + "] ";
    std::string outs;
    for (const auto& o : r.outputs) outs += (outs.empty() ? "" : ", ") + o;
    if (r.status == JobResult::Status::Skipped) return head + "up to date: " + r.job.label() + " (" + outs + ")";
    std::string line = head + "ok: " + r.job.label() + ": " + std::to_string(r.fragments) + " fragments, raster " +
                       fixed(r.times.raster_ms, 1) + " ms, kernel " + fixed(r.times.kernel_ms, 1) + " ms (" +
                       fixed(r.mfrag_per_s(), 1) + " Mfrag/s)";
    if (r.times.build_ms > 0.0) line += ", build " + fixed(r.times.build_ms, 0) + " ms";
    return line + " -> " + outs;
}

// Reports each finished job, in job order: its warnings, its line on the progress display, its count in the summary.
class JobReporter {
public:
    JobReporter(BatchSummary& sum, Progress& progress, std::size_t count) : sum_(sum), progress_(progress), count_(count) {}

    void operator()(Prepared& done) {
        JobResult& r = done.result;
        ++reported_;
        for (const auto& w : r.warnings) progress_.message("warning: " + r.job.label() + ": " + w);
        if (r.status == JobResult::Status::Failed) {
            ++sum_.failed;
            progress_.finish(false, false, r.error);
        } else if (r.status == JobResult::Status::Skipped) {
            ++sum_.skipped;
            progress_.finish(true, true, job_line(r, reported_, count_));
        } else {
            ++sum_.ok;
            progress_.finish(true, false, job_line(r, reported_, count_));
        }
        sum_.jobs.push_back(std::move(r));
    }

private:
    BatchSummary& sum_;
    Progress& progress_;
    std::size_t count_;
    std::size_t reported_ = 0;
};

// The jobs of this shard (--shard I/N): every N-th of the full list, starting at the I-th.
std::vector<BatchJob> shard_jobs(const std::vector<BatchJob>& all, const BatchOptions& opt) {
    std::vector<BatchJob> jobs;
    for (const auto& j : all)
        if (int(j.index % std::size_t(opt.shard_count)) == opt.shard_index - 1) jobs.push_back(j);
    return jobs;
}

BatchSummary Runner::run() {
    std::ostream& log = opt_.log ? *opt_.log : std::cerr;
    const auto t0 = clock_type::now();
    const std::vector<BatchJob> all = plan_all_jobs(opt_);
    const std::vector<BatchJob> jobs = shard_jobs(all, opt_);
    index_outputs(all);
    plan_shared_programs(jobs);

    BatchSummary sum;
    sum.planned_total = all.size();
    sum.shard_index = opt_.shard_index;
    sum.shard_count = opt_.shard_count;
    sum.overlap = opt_.overlap;
    sum.device = rt_.device_description();
    const std::size_t built0 = rt_.programs_built();

    remove_stale(log);
    run_jobs(jobs, sum, log);
    sum.wall_ms = ms_since(t0);
    sum.programs_built = rt_.programs_built() - built0;

    write_reports(sum);
    log_summary(log, sum, all.size());
    return sum;
}

// Job i+1 is parsed, loaded and rasterised on its own thread while job i shades on this one (overlap), or
// right before it shades (deferred: no second thread). Job i's images are written on their own thread while
// job i+1 shades (writing PNG and EXR is single-threaded and often the longest stage); results are reported
// in job order.
void Runner::run_jobs(const std::vector<BatchJob>& jobs, BatchSummary& sum, std::ostream& log) {
    Progress progress(jobs.size(), log, opt_.progress);
    auto launch = [&](std::size_t i) {
        return std::async(opt_.overlap ? std::launch::async : std::launch::deferred,
                          [this, &jobs, i] { return prepare(jobs[i]); });
    };
    std::future<Prepared> next;
    if (!jobs.empty()) next = launch(0);
    std::future<void> writing;
    Prepared written;
    JobReporter report(sum, progress, jobs.size());
    auto finish_writing = [&] {
        if (!writing.valid()) return;
        const auto tw = clock_type::now();
        writing.get();
        sum.write_wait_ms += ms_since(tw);
        report(written);
    };
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        progress.start(fs::path(jobs[i].scene).filename().string() +
                       (jobs[i].mesh.empty() ? "" : " + " + fs::path(jobs[i].mesh).filename().string()));
        const auto tw = clock_type::now();
        Prepared p = next.get();
        if (opt_.overlap) sum.wait_ms += ms_since(tw);
        if (i + 1 < jobs.size()) next = launch(i + 1);
        if (!p.settled) shade(p);
        finish_writing();
        if (p.images.empty()) {
            report(p);
        } else if (opt_.overlap) {
            written = std::move(p);
            writing = std::async(std::launch::async, [&written] { write(written); });
        } else {
            write(p);
            report(p);
        }
    }
    finish_writing();
    progress.close();
}

// Temporaries of an earlier run killed while writing (kill -9, power off): never complete, so removed.
void Runner::remove_stale(std::ostream& log) const {
    std::size_t stale = remove_stale_temporaries(opt_.out_dir);
    for (const auto& f : output_folders_)
        if (fs::path(f).lexically_normal() != fs::path(opt_.out_dir).lexically_normal()) stale += remove_stale_temporaries(f);
    if (stale)
        log << "batch: removed " << stale << " unfinished temporary file" << (stale == 1 ? "" : "s")
            << " left by an interrupted run\n";
}

// The JSON report (and the CSV beside it): --report, else OUT/batch_report[_shardIofN].json.
void Runner::write_reports(BatchSummary& sum) const {
    fs::path json_path = opt_.report;
    if (json_path.empty()) {
        std::string stem = "batch_report";
        if (opt_.shard_count > 1)
            stem += "_shard" + std::to_string(opt_.shard_index) + "of" + std::to_string(opt_.shard_count);
        json_path = fs::path(opt_.out_dir) / (stem + ".json");
    }
    fs::path csv_path = json_path;
    csv_path.replace_extension(".csv");
    sum.report_json = json_path.string();
    sum.report_csv = csv_path.string();
    write_report_json(sum, sum.report_json);
    write_report_csv(sum, sum.report_csv);
}

// The summary: counts, the time of each stage summed over the jobs, throughput, then every failure again
// (they may have scrolled away).
void Runner::log_summary(std::ostream& log, const BatchSummary& sum, std::size_t all_jobs) const {
    pipeline::StageTimes t;
    std::size_t frags = 0;
    for (const auto& r : sum.jobs) {
        t += r.times;
        frags += r.fragments;
    }
    log << "batch: " << sum.jobs.size() << " jobs";
    if (opt_.shard_count > 1) log << " (shard " << opt_.shard_index << "/" << opt_.shard_count << " of " << all_jobs << ")";
    log << ": " << sum.ok << " rendered, " << sum.skipped << " up to date, " << sum.failed << " failed; wall "
        << fixed(sum.wall_ms / 1000.0, 2) << " s, " << sum.programs_built << " programs built\n";
    log << "  stages: " << pipeline::describe(t) << "; " << frags << " fragments, "
        << fixed(t.kernel_ms > 0 ? double(frags) / t.kernel_ms / 1000.0 : 0.0, 1) << " Mfrag/s in the kernel\n";
    log << "  overlap " << (opt_.overlap ? "on" : "off");
    if (opt_.overlap)
        log << " (shading waited " << fixed(sum.wait_ms, 0) << " ms for rasterisation, " << fixed(sum.write_wait_ms, 0)
            << " ms for writing)";
    log << "; device " << sum.device << "\n";
    for (const auto& r : sum.jobs)
        if (r.status == JobResult::Status::Failed) log << "  failed: " << r.error << "\n";
    log << "report: " << sum.report_json << ", " << sum.report_csv << "\n";
}


}  // namespace

std::string BatchJob::label() const {
    return mesh.empty() ? "scene '" + scene + "'" : "scene '" + scene + "' with mesh '" + mesh + "'";
}

double JobResult::mfrag_per_s() const { return times.kernel_ms > 0.0 ? double(fragments) / times.kernel_ms / 1000.0 : 0.0; }

const char* status_name(JobResult::Status s) {
    switch (s) {
        case JobResult::Status::Ok: return "ok";
        case JobResult::Status::Skipped: return "up_to_date";
        case JobResult::Status::Failed: return "failed";
    }
    return "?";
}

std::pair<int, int> parse_shard(const std::string& text) {
    int i = 0, n = 0;
    char slash = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &i, &slash, &n, &extra) != 3 || slash != '/')
        throw Error("--shard expects i/N such as 2/8 (this machine's share, 1-based), got '" + text + "'");
    if (n < 1 || i < 1 || i > n) throw Error("--shard " + text + ": need 1 <= i <= N");
    return {i, n};
}

std::vector<BatchJob> plan_all_jobs(const BatchOptions& o) {
    if (o.shard_count < 1 || o.shard_index < 1 || o.shard_index > o.shard_count)
        throw Error("shard " + std::to_string(o.shard_index) + "/" + std::to_string(o.shard_count) + ": need 1 <= i <= N");
    std::vector<std::pair<std::string, std::string>> keys;
    std::error_code ec;
    if (o.scenes.empty() && o.mesh_dir.empty() && o.template_scene.empty())
        throw Error("no scenes given: shadelab batch scenes/*.json (or --meshes DIR --scene TEMPLATE.json, or both)");
    if (!o.mesh_dir.empty() || !o.template_scene.empty()) {
        if (o.mesh_dir.empty() || o.template_scene.empty())
            throw Error("template mode needs both --meshes DIR and --scene TEMPLATE.json");
        if (!fs::is_directory(o.mesh_dir, ec)) throw Error("--meshes '" + o.mesh_dir + "': not a folder");
        std::size_t found = 0;
        for (const auto& e : fs::directory_iterator(o.mesh_dir, ec))
            if (e.is_regular_file() && is_mesh_file(e.path())) {
                keys.emplace_back(o.template_scene, e.path().string());
                ++found;
            }
        if (!found) throw Error("--meshes '" + o.mesh_dir + "': no .obj .off .ply or .stl files in this folder");
    }
    for (const auto& s : o.scenes) {
        if (fs::is_directory(s, ec)) {
            std::size_t found = 0;
            for (const auto& e : fs::directory_iterator(s, ec))
                if (e.is_regular_file() && lower_ext(e.path().string()) == ".json") {
                    keys.emplace_back(e.path().string(), std::string());
                    ++found;
                }
            if (!found) throw Error("scene folder '" + s + "' holds no .json files");
        } else {
            keys.emplace_back(s, std::string());   // a missing file becomes a failed job, reported in turn
        }
    }
    // Sorted and without repeats, so the list (and so every shard) is the same on every machine.
    for (auto& k : keys) {
        k.first = fs::path(k.first).lexically_normal().string();
        if (!k.second.empty()) k.second = fs::path(k.second).lexically_normal().string();
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    std::vector<BatchJob> jobs;
    for (std::size_t i = 0; i < keys.size(); ++i) jobs.push_back(BatchJob{i, keys[i].first, keys[i].second});
    return jobs;
}

std::vector<BatchJob> plan_batch(const BatchOptions& o) {
    std::vector<BatchJob> out;
    for (const auto& j : plan_all_jobs(o))
        if (int(j.index % std::size_t(o.shard_count)) == o.shard_index - 1) out.push_back(j);
    return out;
}

BatchSummary run_batch(const BatchOptions& options, Runtime& runtime) { return Runner(options, runtime).run(); }

void write_report_json(const BatchSummary& s, const std::string& path) {
    using nlohmann::json;
    json jobs = json::array();
    for (const auto& r : s.jobs) {
        jobs.push_back({{"index", r.job.index},
                        {"scene", r.job.scene},
                        {"mesh", r.job.mesh},
                        {"name", r.name},
                        {"status", status_name(r.status)},
                        {"outputs", r.outputs},
                        {"models", r.models},
                        {"width", r.width},
                        {"height", r.height},
                        {"triangles", r.triangles},
                        {"fragments", r.fragments},
                        {"load_ms", r.times.load_ms},
                        {"raster_ms", r.times.raster_ms},
                        {"build_ms", r.times.build_ms},
                        {"kernel_ms", r.times.kernel_ms},
                        {"shade_ms", r.times.shade_ms},
                        {"resolve_ms", r.times.resolve_ms},
                        {"write_ms", r.times.write_ms},
                        {"mfrag_per_s", r.mfrag_per_s()},
                        {"error", r.error},
                        {"warnings", r.warnings}});
    }
    const json doc{{"tool", "shadelab batch"},
                   {"device", s.device},
                   {"shard", std::to_string(s.shard_index) + "/" + std::to_string(s.shard_count)},
                   {"planned_total", s.planned_total},
                   {"jobs_in_shard", s.jobs.size()},
                   {"ok", s.ok},
                   {"up_to_date", s.skipped},
                   {"failed", s.failed},
                   {"wall_ms", s.wall_ms},
                   {"overlap", s.overlap},
                   {"wait_for_raster_ms", s.wait_ms},
                   {"wait_for_write_ms", s.write_wait_ms},
                   {"programs_built", s.programs_built},
                   {"jobs", jobs}};
    // Scene and mesh paths come from the file system and need not be UTF-8: such bytes are replaced
    // (U+FFFD) rather than losing the whole report after the batch has run.
    write_text_atomically(path, "report", doc.dump(2, ' ', false, json::error_handler_t::replace) + "\n");
}

void write_report_csv(const BatchSummary& s, const std::string& path) {
    CsvTable t({"index", "scene", "mesh", "name", "status", "outputs", "models", "width", "height", "triangles",
                "fragments", "load_ms", "raster_ms", "build_ms", "kernel_ms", "shade_ms", "resolve_ms", "write_ms",
                "mfrag_per_s", "error"});
    for (const auto& r : s.jobs) {
        std::string outs, models;
        for (const auto& o : r.outputs) outs += (outs.empty() ? "" : ";") + o;
        for (const auto& m : r.models) models += (models.empty() ? "" : ";") + m;
        t.row().add_count(r.job.index).add_quoted(r.job.scene).add_quoted(r.job.mesh).add_quoted(r.name)
            .add_quoted(status_name(r.status)).add_quoted(outs).add_quoted(models).add_count(std::size_t(r.width))
            .add_count(std::size_t(r.height)).add_count(r.triangles).add_count(r.fragments);
        const pipeline::StageTimes& tm = r.times;
        for (double ms : {tm.load_ms, tm.raster_ms, tm.build_ms, tm.kernel_ms, tm.shade_ms, tm.resolve_ms, tm.write_ms,
                          r.mfrag_per_s()})
            t.add_fixed(ms, 3);
        t.add_quoted(r.error);
    }
    write_text_atomically(path, "report", t.text());
}

}  // namespace shadelab
