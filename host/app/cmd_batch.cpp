// shadelab batch: many scenes (or one template over a folder of meshes) in one process;
// shadelab contact: every model on a sphere and a mesh, labelled, in one image.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "app/commands.hpp"
#include "cl/runtime.hpp"
#include "core/error.hpp"
#include "image/image.hpp"
#include "core/log.hpp"
#include "scene/batch.hpp"
#include "scene/report_merge.hpp"
#include "scene/contact.hpp"
#include "scene/scene.hpp"

namespace shadelab::app {

namespace {

struct BatchArgs {
    std::vector<std::string> scenes;
    std::string manifest;
    std::string meshes, scene_template;
    std::string out = "out";
    std::string report;
    std::string shard = "1/1";
    std::string progress = "auto";
    bool force = false;
    bool no_overlap = false;
    bool contact = false;
    bool list = false;
    double tolerance = 0.0;
    std::string metric = "de2000";
    bool no_catalogue = false;
};

struct ContactArgs {
    ContactOptions opt;
    std::vector<std::string> models;
    std::string precision = "precise";
};

void print_contact(const ContactResult& r) {
    log_out() << "contact sheet: " << r.models << " models, " << r.width << "x" << r.height << ", "
              << (r.labelled ? "labels in " + r.font : "labels in " + r.legend) << ", " << int(r.ms) << " ms\n";
    std::cout << r.output << "\n";
}

// One scene file per line of the manifest, relative to its folder; '#' starts a comment line.
std::vector<std::string> read_manifest(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw Error("manifest '" + path + "': cannot open it: check the path");
    std::vector<std::string> out;
    std::string line;
    int number = 0;
    const std::filesystem::path base = std::filesystem::path(path).parent_path();
    while (std::getline(in, line)) {
        ++number;
        const auto b = line.find_first_not_of(" \t\r"), e = line.find_last_not_of(" \t\r");
        if (b == std::string::npos || line[b] == '#') continue;
        const std::string entry = line.substr(b, e - b + 1);
        const std::filesystem::path p(entry);
        out.push_back(p.is_absolute() ? entry : (base / p).string());
    }
    if (out.empty()) throw Error("manifest '" + path + "' lists no scene file (one per line)");
    return out;
}

void run_batch_command(const BatchArgs& a) {
    BatchOptions o;
    o.scenes = a.scenes;
    if (!a.manifest.empty())
        for (auto& s : read_manifest(a.manifest)) o.scenes.push_back(std::move(s));
    o.mesh_dir = a.meshes;
    o.template_scene = a.scene_template;
    o.out_dir = a.out;
    o.report = a.report;
    const auto shard = parse_shard(a.shard);
    o.shard_index = shard.first;
    o.shard_count = shard.second;
    o.force = a.force;
    o.overlap = !a.no_overlap;
    o.progress = parse_progress_style(a.progress);
    if (log_level() == LogLevel::Quiet) o.progress = parse_progress_style("quiet");   // the global -q
    o.log = &log_out();
    if (a.tolerance < 0.0) throw Error("--tolerance must be > 0 (0 = off)");
    o.tolerance = a.tolerance;
    if (a.metric != "de2000" && a.metric != "relative") throw Error("--metric must be 'de2000' or 'relative', got '" + a.metric + "'");
    o.tolerance_relative = a.metric == "relative";
    o.tolerance_catalogue = !a.no_catalogue;
    if (a.list) {
        // The jobs this shard would run, in order: a dry run for checking a sharding plan.
        for (const auto& j : plan_batch(o)) std::cout << j.index << "\t" << j.scene << (j.mesh.empty() ? "" : "\t" + j.mesh) << "\n";
        return;
    }
    Runtime rt;
    const BatchSummary s = run_batch(o, rt);
    // Results on stdout (logs went to stderr): every image this run wrote or found up to date, then the report.
    for (const auto& j : s.jobs)
        if (j.status != JobResult::Status::Failed)
            for (const auto& f : j.outputs) std::cout << f << "\n";
    std::cout << s.report_json << "\n" << s.report_csv << "\n";
    if (a.contact) {
        ContactOptions co;
        co.output = (std::filesystem::path(a.out) / "contact_sheet.png").string();
        print_contact(make_contact_sheet(co, rt));
    }
    if (s.failed)
        throw Error("batch: " + std::to_string(s.failed) + " of " + std::to_string(s.jobs.size()) +
                    " jobs failed (each is a 'scene ...' line above; details in " + s.report_json + ")");
}

// shadelab report merge: the shards' reports -> the report an unsharded run writes.
void add_report_command(CLI::App& app) {
    struct MergeArgs {
        std::vector<std::string> reports;
        std::string out;
        bool allow_missing = false;
    };
    auto ma = std::make_shared<MergeArgs>();
    auto* rep = app.add_subcommand("report", "Work with batch reports");
    rep->require_subcommand(1);
    auto* merge = rep->add_subcommand("merge", "Merge the reports of a sharded batch (--shard i/N) into the report an "
                                               "unsharded run writes (JSON, and the CSV beside it)");
    merge->add_option("reports", ma->reports, "The shards' JSON reports")->required();
    merge->add_option("-o,--output", ma->out, "The merged report (.json; a .csv is written beside it)")->required();
    merge->add_flag("--allow-missing", ma->allow_missing, "Merge even when some shards' reports are not given");
    merge->callback([ma] {
        std::vector<BatchSummary> shards;
        for (const auto& r : ma->reports) shards.push_back(read_report_json(r));
        BatchSummary merged = merge_reports(shards, ma->reports, ma->allow_missing);
        merged.report_json = ma->out;
        merged.report_csv = std::filesystem::path(ma->out).replace_extension(".csv").string();
        write_report_json(merged, merged.report_json);
        write_report_csv(merged, merged.report_csv);
        log_out() << "report merge: " << shards.size() << " shards, " << merged.jobs.size() << " of "
                  << merged.planned_total << " jobs (" << merged.ok << " ok, " << merged.skipped << " up to date, "
                  << merged.failed << " failed)\n";
        std::cout << merged.report_json << "\n" << merged.report_csv << "\n";
        if (merged.failed) throw Error("report merge: " + std::to_string(merged.failed) + " jobs failed (see the report)");
    });
}

// shadelab contact: every model on a sphere and a mesh (host/scene/contact.hpp).
void add_contact_command(CLI::App& app) {
    auto c = std::make_shared<ContactArgs>();
    auto* con = app.add_subcommand("contact",
                                   "One image with every model of the catalogue (default parameters) on a sphere "
                                   "and on a mesh, labelled");
    con->add_option("-o,--output", c->opt.output, std::string("Output image: ") + kOutputFormats)->capture_default_str();
    con->add_option("--mesh", c->opt.mesh, "The real mesh shown beside the sphere (default: the bundled spot.obj)");
    con->add_option("--turn", c->opt.mesh_turn_deg, "Turn the mesh this many degrees about +y")->capture_default_str();
    con->add_option("--cell", c->opt.cell, "Side of each rendered square in pixels")->capture_default_str();
    con->add_option("--columns", c->opt.columns, "Model tiles per row (0: about 4:3)")->capture_default_str();
    con->add_option("-m,--model", c->models, "Only these models (repeatable; default: the whole catalogue)");
    con->add_option("--precision", c->precision, "Kernel precision of every tile: precise or fast (docs/precision.md)")
        ->capture_default_str();
    con->add_flag("--per-vertex", c->opt.per_vertex, "Shade every tile at the vertices and interpolate (Gouraud)");
    con->footer("No --tolerance (the sheet shows each model as it is, not a cheaper stand-in) and no AOVs (every tile "
                "has the same sphere and mesh: 'render --depth/--normal' writes them).");
    con->callback([c] {
        ContactOptions o = c->opt;
        o.precision = parse_precision(c->precision);
        for (const auto& m : c->models) require_model_name(m, "--model");
        o.models = c->models;
        Runtime rt;
        const ContactResult r = make_contact_sheet(o, rt);
        print_contact(r);
        if (!r.failed.empty())
            throw Error("contact sheet: " + std::to_string(r.failed.size()) + " models failed to shade (listed above); "
                        "the sheet was written with their tiles empty");
    });
}

}  // namespace

void add_batch_command(CLI::App& app) {
    auto a = std::make_shared<BatchArgs>();
    auto* cmd = app.add_subcommand(
        "batch",
        "Shade many scene files (or one template scene over a folder of meshes) in one process; schema in docs/batch.md");
    cmd->add_option("scenes", a->scenes, "Scene files (.json) or folders of them");
    cmd->add_option("--manifest", a->manifest,
                    "A text file with one scene file per line (relative to the manifest's folder; blank lines and "
                    "lines starting with # are skipped), added to the scenes given");
    cmd->add_option("--meshes", a->meshes, "Template mode: shade every .obj .off .ply .stl in this folder ...");
    cmd->add_option("--scene", a->scene_template, "... with this template scene (its one mesh entry is replaced)");
    cmd->add_option("-o,--out", a->out, "Folder that relative output paths of the scenes are written under")
        ->capture_default_str();
    cmd->add_option("--report", a->report,
                    "Report path (.json; a .csv is written beside it). Default: OUT/batch_report.json "
                    "(OUT/batch_report_shardIofN.json when sharded)");
    cmd->add_option("--shard", a->shard,
                    "i/N: run only the jobs whose index in the sorted job list satisfies index % N == i-1")
        ->capture_default_str();
    cmd->add_flag("--force", a->force, "Re-render outputs that are newer than their scene and meshes");
    cmd->add_option("--tolerance", a->tolerance,
                    "Plan each job and shade with the cheapest configuration within this error (docs/planner.md); "
                    "per-pixel candidates only (a scene asks for per vertex with \"per_vertex\": true)");
    cmd->add_option("--metric", a->metric, "Tolerance metric: de2000 (max Delta E 2000) or relative")->capture_default_str();
    cmd->add_flag("--no-catalogue", a->no_catalogue,
                  "With --tolerance: only the requested model or Lambert per job, no catalogue search (docs/planner.md)");
    cmd->add_flag("--no-overlap", a->no_overlap,
                  "Rasterise each job right before it shades instead of during the previous job's shading");
    cmd->add_option("--progress", a->progress, "auto (bar on a terminal, lines otherwise), bar, lines or quiet")
        ->capture_default_str();
    cmd->add_flag("--contact", a->contact, "Also write OUT/contact_sheet.png (see 'shadelab contact')");
    cmd->add_flag("--list", a->list, "Print this shard's jobs (index, scene, mesh) and exit without rendering");
    cmd->callback([a] { run_batch_command(*a); });

    add_report_command(app);
    add_contact_command(app);
}

}  // namespace shadelab::app
