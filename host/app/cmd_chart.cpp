// shadelab chart: speed against accuracy for every model x precision mode (with the Pareto front), and error
// against tessellation and per-vertex evaluation (host/speed/).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <unistd.h>

#include "app/commands.hpp"
#include "cl/runtime.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "core/log.hpp"
#include "core/assets.hpp"
#include "mesh/mesh.hpp"
#include "models/catalogue.hpp"
#include "speed/chart.hpp"
#include "speed/score.hpp"
#include "speed/subdivision.hpp"

namespace fs = std::filesystem;

namespace shadelab::app {

namespace {

struct ChartArgs {
    std::string out = "out/chart";
    std::vector<std::string> meshes;   // empty: the bundled spot.obj and teapot.obj
    std::string size = "256x256";
    std::vector<std::string> models;   // empty: the whole catalogue
    std::vector<std::string> modes{"precise", "fast"};
    std::string view_from = "0.57,0.25,-0.82";   // spot's three-quarter face (as on the contact sheet)
    long long fragments = 1 << 21;
    int repeats = 3;
    int rounds = 2;
    std::vector<std::string> subdiv_models{"lambert", "blinn_phong"};
    std::vector<int> sphere_levels{0, 1, 2, 3, 4, 5, 6};
    std::vector<int> mesh_levels{0, 1, 2};
    int mesh_reference_level = 3;
    bool no_subdivision = false;
};

// Fails before the long run when the folder cannot be written.
void check_writable(const std::string& dir) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
        throw Error("cannot create the output folder --out '" + dir + "'" + (ec ? ": " + ec.message() : "") +
                    ": choose a writable folder");
    const fs::path probe = fs::path(dir) / (".chart_probe" + std::to_string(::getpid()));
    { std::ofstream f(probe); f << "x"; if (!f.flush()) { fs::remove(probe, ec); throw Error("cannot write into the output folder --out '" + dir + "': choose a writable folder"); } }
    fs::remove(probe, ec);
}

// What the user typed, checked before the long run.
struct ChartPlan {
    int w = 0, h = 0;
    std::vector<std::string> models;
    std::vector<Precision> modes;
    glm::dvec3 view_from{0.0};
};

ChartPlan check_chart_args(const ChartArgs& a) {
    ChartPlan c;
    const ImageSize size = parse_size(a.size, "--size", 8, 4096, "256x256");
    c.w = size.width;
    c.h = size.height;
    if (a.fragments < 1000 || a.fragments > 64ll << 20) throw Error("--fragments must be in [1000, 67108864]");
    if (a.repeats < 1 || a.repeats > 100) throw Error("--repeats must be in [1, 100]");
    if (a.rounds < 1 || a.rounds > 20) throw Error("--rounds must be in [1, 20]");
    c.models = a.models;
    if (c.models.empty())
        for (const auto& m : model_catalogue()) c.models.push_back(m.name);
    for (const auto& m : c.models) require_model_name(m, "--models");
    for (const auto& m : a.subdiv_models) require_model_name(m, "--subdiv-models");
    for (const auto& m : a.modes) c.modes.push_back(parse_precision(m));
    if (c.modes.empty()) throw Error("--modes is empty: give precise, fast or both");
    c.view_from = parse_vec3(a.view_from, "--view-from");
    if (!(glm::length(c.view_from) > 0.0)) throw Error("--view-from must not be the zero vector");
    for (int l : a.sphere_levels)
        if (l < 0 || l > 8) throw Error("--sphere-levels: " + std::to_string(l) + " is out of range, use 0..8");
    for (int l : a.mesh_levels)
        if (l < 0 || l > a.mesh_reference_level)
            throw Error("--mesh-levels: " + std::to_string(l) + " must be in 0..--mesh-reference-level (" +
                        std::to_string(a.mesh_reference_level) + ")");
    if (a.mesh_reference_level < 0 || a.mesh_reference_level > 5) throw Error("--mesh-reference-level must be in 0..5");
    check_writable(a.out);
    plot::find_gnuplot();   // a missing gnuplot fails now, not after minutes of scoring
    return c;
}

// Every model x mode scored once, then further timing rounds over every row, keeping each row's best: load from
// other processes comes in bursts, and a burst during one model's slot would otherwise decide its place.
std::vector<speed::ChartRow> score_rows(const ChartArgs& a, const ChartPlan& c, speed::Scorer& scorer) {
    std::vector<speed::ChartRow> rows;
    const std::size_t total = c.models.size() * c.modes.size();
    for (const auto& name : c.models) {
        const Material m = speed::chart_material(name);
        for (Precision p : c.modes) {
            speed::ChartRow r;
            r.score = scorer.score(m, p);
            rows.push_back(r);
            const auto& e = r.score.error;
            shadelab::log_out() << "[" << rows.size() << "/" << total << "] " << std::left << std::setw(30) << name << std::setw(8)
                      << precision_name(p) << std::right << std::setw(9) << num(r.score.fragments_per_s * 1e-6, 4)
                      << " Mfrag/s   dE00 p99 " << std::setw(9) << num(e.de_p99, 3) << "   rel max " << std::setw(9)
                      << num(e.rel_max, 3) << "\n";
        }
    }
    for (int round = 2; round <= a.rounds; ++round) {
        shadelab::log_out() << "chart: timing round " << round << " of " << a.rounds << "\n";
        for (auto& r : rows) {
            const double ms = scorer.time_kernel(speed::chart_material(r.score.model), r.score.precision);
            if (ms < r.score.kernel_ms) {
                r.score.kernel_ms = ms;
                r.score.fragments_per_s = double(r.score.timed_fragments) / (ms * 1e-3);
            }
        }
    }
    speed::mark_fronts(rows);
    return rows;
}

void print_fronts(const std::vector<speed::ChartRow>& rows) {
    shadelab::log_out() << "Pareto front (p99 Delta E 2000):";
    for (const auto& r : rows)
        if (r.front_de) shadelab::log_out() << " " << r.score.model << "/" << precision_name(r.score.precision);
    shadelab::log_out() << "\nPareto front (max relative error):";
    for (const auto& r : rows)
        if (r.front_rel) shadelab::log_out() << " " << r.score.model << "/" << precision_name(r.score.precision);
    shadelab::log_out() << "\n";
}

void run_subdivision(Runtime& rt, const ChartArgs& a, const ChartPlan& c, const speed::ScoreView& view,
                     const Mesh& mesh, const std::vector<Light>& lights) {
    speed::SubdivisionOptions o;
    o.width = c.w;
    o.height = c.h;
    o.view_from = c.view_from;
    o.lights = lights;
    shadelab::log_out() << "chart: subdivision - icosphere levels and Loop levels of " << view.name << "\n";
    auto sub = speed::sphere_subdivision(rt, a.subdiv_models, a.sphere_levels, o);
    shadelab::log_out() << "  icosphere done (" << sub.size() << " rows)\n";
    const auto mesh_rows =
        speed::mesh_subdivision(rt, view.name, mesh, a.subdiv_models, a.mesh_levels, a.mesh_reference_level, o);
    sub.insert(sub.end(), mesh_rows.begin(), mesh_rows.end());
    const std::string scsv = (fs::path(a.out) / "subdivision.csv").string();
    const std::string spng = (fs::path(a.out) / "subdivision.png").string();
    speed::subdivision_table(sub).write(scsv);
    speed::plot_subdivision(scsv, spng, sub,
                            std::to_string(c.w) + "x" + std::to_string(c.h) + "; " + view.name +
                                " reference: Loop level " + std::to_string(a.mesh_reference_level) +
                                "; icosphere reference: the exact sphere, ray-cast in double");
    std::cout << scsv << "\n" << spng << "\n";
}

void run_chart(const ChartArgs& a) {
    using clock = std::chrono::steady_clock;
    const auto t_start = clock::now();
    const ChartPlan c = check_chart_args(a);

    std::vector<Mesh> loaded;
    std::vector<speed::ScoreView> views;
    std::string mesh_names;
    const std::vector<std::string> meshes =
        a.meshes.empty() ? std::vector<std::string>{bundled_mesh("spot.obj"), bundled_mesh("teapot.obj")} : a.meshes;
    for (const auto& p : meshes) {
        loaded.push_back(load_mesh(p));
        const std::string name = fs::path(p).filename().string();
        views.push_back(speed::make_view(name, loaded.back(), c.view_from, c.w, c.h));
        mesh_names += (mesh_names.empty() ? "" : " + ") + name;
    }
    Runtime rt;
    speed::ScoreOptions so;
    so.lights = speed::chart_lights(c.view_from);
    so.timed_fragments = std::size_t(a.fragments);
    so.timing_repeats = a.repeats;
    speed::Scorer scorer(rt, views, so);
    shadelab::log_out() << "chart: " << c.models.size() << " models x " << c.modes.size() << " modes on " << mesh_names
              << " at " << c.w << "x" << c.h << "; speed over " << scorer.timed_fragments() << " fragments, best of "
              << a.repeats << " x " << a.rounds << " rounds; device " << rt.device_description() << "\n";

    const std::vector<speed::ChartRow> rows = score_rows(a, c, scorer);
    const std::string csv = (fs::path(a.out) / "speed_accuracy.csv").string();
    const std::string png = (fs::path(a.out) / "speed_accuracy.png").string();
    speed::speed_table(rows).write(csv);
    const std::string subtitle = mesh_names + ", " + std::to_string(c.w) + "x" + std::to_string(c.h) +
                                 " each; speed over " + std::to_string(scorer.timed_fragments()) + " fragments; " +
                                 rt.device_description();
    speed::plot_speed_accuracy(csv, png, rows, subtitle);
    std::cout << csv << "\n" << png << "\n";
    print_fronts(rows);
    if (!a.no_subdivision) run_subdivision(rt, a, c, views.front(), loaded.front(), so.lights);
    shadelab::log_out() << "chart: done in " << num(std::chrono::duration<double>(clock::now() - t_start).count(), 3) << " s\n";
}

}  // namespace

void add_chart_command(CLI::App& app) {
    auto a = std::make_shared<ChartArgs>();
    auto* cmd = app.add_subcommand(
        "chart", "Speed (fragments/s) against error vs the double reference for every model x precision mode, "
                 "with the Pareto front; and error against subdivision level, per pixel vs per vertex");
    cmd->add_option("--out", a->out, "Output folder: speed_accuracy.csv/.png, subdivision.csv/.png")->capture_default_str();
    cmd->add_option("--mesh", a->meshes, "Mesh(es) to score on (repeatable; default: the bundled spot.obj and teapot.obj); the first is also Loop-subdivided")
        ->capture_default_str();
    cmd->add_option("--size", a->size, "Render size of each mesh WIDTHxHEIGHT")->capture_default_str();
    cmd->add_option("--models", a->models, "Models, comma-separated (default: the whole catalogue)")->delimiter(',');
    cmd->add_option("--modes", a->modes, "Precision modes, comma-separated: precise,fast")->delimiter(',')->capture_default_str();
    cmd->add_option("--view-from", a->view_from, "Direction from each mesh's centre to the camera")->capture_default_str();
    cmd->add_option("--fragments", a->fragments, "Timed buffer: at least this many fragments (the renders' repeated)")
        ->capture_default_str();
    cmd->add_option("--repeats", a->repeats, "Kernel timings per model x mode per round (the best is kept)")->capture_default_str();
    cmd->add_option("--rounds", a->rounds, "Timing rounds over all models (each row keeps its best time)")->capture_default_str();
    cmd->add_option("--subdiv-models", a->subdiv_models, "Models of the subdivision chart, comma-separated")
        ->delimiter(',')->capture_default_str();
    cmd->add_option("--sphere-levels", a->sphere_levels, "Icosphere levels, comma-separated")->delimiter(',')->capture_default_str();
    cmd->add_option("--mesh-levels", a->mesh_levels, "Loop subdivision levels of the first mesh, comma-separated")
        ->delimiter(',')->capture_default_str();
    cmd->add_option("--mesh-reference-level", a->mesh_reference_level,
                    "Loop level of the first mesh the double reference is computed on")->capture_default_str();
    cmd->add_flag("--no-subdivision", a->no_subdivision, "Skip the subdivision chart");
    cmd->callback([a] { run_chart(*a); });
}

}  // namespace shadelab::app
