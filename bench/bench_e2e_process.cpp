// The whole process around the frame (issue 13 item 6): what is not shading.
//   writes:   shadelab's write_image against `oiiotool` writing the same pixels with the same settings (PNG zlib
//             level and row filter, EXR compression), for each setting: time (best of N), the ratio, the file size;
//   builds:   the whole catalogue's programs (every model, precise and fast, one light) built and run once on a
//             tiny fragment buffer, each case in a fresh process: PoCL's kernel cache cold or warm, shadelab's
//             program-binary cache off, cold or warm;
//   start-up: fresh `shadelab` processes (--version, a small render), and the render with OpenImageIO and GDAL
//             preloaded, as when the program linked them (host/image/image_io.hpp); --startup-only runs it alone;
//   meshes:   OpenMesh's readers (the full loader, cache off) on the bundled meshes against the mesh cache's miss
//             (which stores the entry) and hit, best of N; --meshes-only runs this table alone.
// A benchmark, not a test: --smoke runs a tiny size so the suite checks it still works.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <OpenImageIO/imageio.h>

#include "bench_util.hpp"
#include "contact_cold.hpp"
#include "plan_cold.hpp"
#include "cl/runtime.hpp"
#include "core/error.hpp"
#include "image/image.hpp"
#include "core/format.hpp"
#include "mesh/mesh.hpp"
#include "mesh/mesh_cache.hpp"
#include "models/catalogue.hpp"
#include "raster/camera.hpp"
#include "raster/raster.hpp"
#include "shade/shader.hpp"
#include "shade/shade_program.hpp"

using namespace shadelab;
namespace fs = std::filesystem;
using clock_type = std::chrono::steady_clock;

namespace {

double ms_since(clock_type::time_point t0) {
    return std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();
}

std::string run_capture(const std::string& cmd) {
    std::string out;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) throw Error("cannot run '" + cmd + "'");
    char buf[4096];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    const int rc = pclose(p);
    if (rc != 0) throw Error("'" + cmd + "' failed (exit " + std::to_string(rc) + "): " + out.substr(0, 300));
    return out;
}

// The "-o" line of `oiiotool --runstats`: seconds spent in the output operation (encoding and writing).
double oiiotool_write_ms(const std::string& args) {
    const std::string out = run_capture("oiiotool --runstats " + args + " 2>&1");
    const auto at = out.find("\n      -o");
    if (at == std::string::npos) throw Error("oiiotool --runstats printed no '-o' time: " + out.substr(0, 300));
    const auto colon = out.find(':', at);
    return 1000.0 * std::stod(out.substr(colon + 1));
}

// A frame of `mesh` at w x h shaded with Lambert: the pixels the writes are timed on (a real render: a mesh
// on a transparent background, as `shadelab render` writes it).
Image render(Runtime& rt, const Mesh& mesh, int w, int h) {
    RasterOptions ro;
    ro.width = w;
    ro.height = h;
    const Camera cam = Camera::fit(mesh.bounds(), {0.0, 0.25, 1.0}, 35.0, double(w) / double(h));
    const FragmentBuffer fb = rasterize(mesh, cam, ro);
    ShadeSetup s;
    s.material.model = "lambert";
    s.material = resolve_material(s.material);
    s.lights.push_back(Light{Light::Type::Directional, {1.0, 1.0, 1.0}, {1.0, 1.0, 1.0}, 1.0, 0.0});
    s.view = glm::dvec4(cam.eye, 1.0);
    Shader shader(rt);
    return compose_image(fb, shader.shade(fb, s), glm::dvec4(0.0));
}

// Raw pixels to a file oiiotool reads back untouched: uncompressed TIFF (8-bit) or EXR (float).
void write_raw(const std::string& path, const Image& img, bool eight_bit) {
    auto out = OIIO::ImageOutput::create(path);
    OIIO::ImageSpec spec(img.width, img.height, img.channels, eight_bit ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    spec.alpha_channel = 3;
    spec.attribute("compression", "none");
    spec.attribute("oiio:UnassociatedAlpha", 1);
    bool ok = out && out->open(path, spec);
    if (ok && eight_bit) ok = out->write_image(OIIO::TypeDesc::UINT8, encode_srgb8(img).data());
    else if (ok) ok = out->write_image(OIIO::TypeDesc::FLOAT, img.pixels.data());
    if (!ok || !out->close()) throw Error("cannot write '" + path + "'");
}

void bench_writes(Runtime& rt, const Mesh& mesh, int w, int h, int reps, const fs::path& tmp) {
    const Image img = render(rt, mesh, w, h);
    const std::string raw8 = (tmp / "raw8.tif").string(), rawf = (tmp / "rawf.exr").string();
    write_raw(raw8, img, true);
    write_raw(rawf, img, false);
    std::printf("\n== image writes, %dx%d RGBA (%s): shadelab write_image against oiiotool's '-o' on the same pixels\n"
                "   (oiiotool reads an uncompressed file first; only its -o step is timed, from --runstats)\n",
                w, h, mesh.source.substr(mesh.source.find_last_of('/') + 1).c_str());
    std::printf("%-26s %12s %12s %8s %12s %s\n", "setting", "shadelab", "oiiotool", "ratio", "size", "");
    struct Case {
        std::string label, ext;
        ImageWriteOptions opt;
        std::string oiio_args;
    };
    std::vector<Case> cases;
    // PNG: each zlib level with shadelab's row filter, oiiotool given the same filter; and level 1 with libpng's
    // default filtering (all five filters tried per row: png:filter 0) on both sides. These rows give shadelab
    // zlib's memLevel 8, as OpenImageIO has it (oiiotool cannot set it), so both sides have the same settings;
    // the last PNG row is shadelab's default (memLevel 6) against oiiotool at the same level and filter.
    const ImageWriteOptions defaults;
    const int filter = defaults.png_filter;
    const std::string oiio_png = raw8 + " --attrib png:filter " + std::to_string(filter) + " --attrib png:compressionLevel ";
    for (int level : {6, 1, 3, 9}) {
        ImageWriteOptions o;
        o.png_level = level;
        o.png_mem_level = 8;
        cases.push_back({"png zlib " + std::to_string(level), ".png", o, oiio_png + std::to_string(level)});
    }
    {
        ImageWriteOptions o;
        o.png_filter = 0;
        o.png_mem_level = 8;
        cases.push_back({"png zlib 1, filter 0", ".png", o,
                         raw8 + " --attrib png:compressionLevel " + std::to_string(o.png_level) + " --attrib png:filter 0"});
    }
    cases.push_back({"png zlib " + std::to_string(defaults.png_level) + ", memLevel " +
                         std::to_string(defaults.png_mem_level) + " (default)",
                     ".png", defaults, oiio_png + std::to_string(defaults.png_level)});
    for (const char* c : {"zip", "piz", "zips", "rle", "none", "dwaa"}) {
        ImageWriteOptions o;
        o.exr_compression = c;
        cases.push_back({std::string("exr ") + c + (c == ImageWriteOptions().exr_compression ? " (default)" : ""), ".exr",
                         o, rawf + " --compression " + c});
    }
    for (const Case& c : cases) {
        const std::string ours = (tmp / ("ours" + c.ext)).string(), theirs = (tmp / ("theirs" + c.ext)).string();
        double best_ours = 1e30, best_theirs = 1e30;
        for (int r = 0; r < reps; ++r) {
            const auto t0 = clock_type::now();
            write_image(ours, img, c.opt);
            best_ours = std::min(best_ours, ms_since(t0));
            best_theirs = std::min(best_theirs, oiiotool_write_ms(c.oiio_args + " -o " + theirs));
        }
        std::printf("%-26s %10.1fms %10.1fms %7.2fx %10.1fMB %s\n", c.label.c_str(), best_ours, best_theirs,
                    best_theirs / best_ours, double(fs::file_size(ours)) / 1e6,
                    best_ours <= best_theirs ? "" : "(shadelab slower)");
    }
}

// --- process start-up: what a command costs before and around its work ------------------------------------------
// `shadelab --version` and a small render (spot, 512x512, PNG) as fresh processes, best and median of N wall
// times; and the same render with OpenImageIO and GDAL preloaded (LD_PRELOAD, the libraries the image plug-in
// links): what every process paid while the program linked them (host/image/image_io.hpp), timed alternately.
std::string plugin_libraries(const fs::path& plugin) {
    std::string libs, line;
    std::istringstream ldd(run_capture("ldd '" + plugin.string() + "' 2>&1"));
    while (std::getline(ldd, line)) {
        const auto arrow = line.find("=> ");
        if (arrow == std::string::npos) continue;
        const std::string path = line.substr(arrow + 3, line.find(" (", arrow) - arrow - 3);
        if (path.find("libOpenImageIO.so") != std::string::npos || path.find("libgdal.so") != std::string::npos)
            libs += (libs.empty() ? "" : " ") + path;
    }
    return libs;
}

void bench_startup(const std::string& self, const fs::path& tmp, int reps) {
    const fs::path dir = fs::path(self).parent_path(), bin = dir / "shadelab", plugin = dir / "libshadelab_imageio.so";
    if (!fs::exists(bin) || !fs::exists(plugin)) {
        std::printf("\n== process start-up: skipped (no shadelab or libshadelab_imageio.so beside this program)\n");
        return;
    }
    const std::string preload = plugin_libraries(plugin);
    const std::string render = "'" + bin.string() + "' -q render '" + std::string(SHADELAB_SOURCE_DIR) +
                               "/meshes/spot.obj' --size 512x512 -o '" + (tmp / "startup.png").string() + "' > /dev/null";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"shadelab --version", "'" + bin.string() + "' --version > /dev/null"},
        {"shadelab render spot 512x512 -o .png", render},
        {"  the same, OpenImageIO and GDAL preloaded", "LD_PRELOAD='" + preload + "' " + render}};
    std::vector<std::vector<double>> ms(cases.size());
    for (int r = 0; r < std::max(reps, 5); ++r)
        for (std::size_t c = 0; c < cases.size(); ++c) {
            const auto t0 = clock_type::now();
            run_capture(cases[c].second);
            ms[c].push_back(ms_since(t0));
        }
    std::printf("\n== process start-up: fresh processes, wall time, %zu runs each, alternated (preloaded: %s)\n",
                ms[0].size(), preload.empty() ? "nothing found" : preload.c_str());
    std::printf("%-46s %10s %10s\n", "command", "best ms", "median ms");
    std::vector<double> median(cases.size());
    for (std::size_t c = 0; c < cases.size(); ++c) {
        std::sort(ms[c].begin(), ms[c].end());
        median[c] = ms[c][ms[c].size() / 2];
        std::printf("%-46s %10.1f %10.1f\n", cases[c].first.c_str(), ms[c].front(), median[c]);
    }
    std::printf("render with the libraries preloaded / without: %.2fx (medians)\n", median[2] / median[1]);
}

// --- program builds: each case in a fresh process (PoCL reads its cache settings at start-up) ---------------

// Builds and runs every catalogue model (precise and fast) once; prints "builds <ms> total <ms> programs <n>
// cached <n>".
// With build_threads > 0 the programs are first built on that many threads (Runtime::prebuild), then run.
int child_builds(int max_models, int build_threads) {
    Runtime rt;
    Shader shader(rt);
    FragmentBuffer fb;
    fb.width = 4;
    fb.height = 1;
    for (int i = 0; i < 4; ++i) fb.push_back(0, 0, 0, 0, 0, 1, i, 1.0f);
    const auto t0 = clock_type::now();
    std::vector<ShadeSetup> setups;
    for (const ModelInfo& info : model_catalogue()) {
        if (max_models > 0 && int(setups.size()) >= 2 * max_models) break;
        Material m;
        m.model = info.name;
        add_demo_children(m, info);
        m = resolve_material(m);
        for (Precision p : {Precision::Precise, Precision::Fast}) {
            ShadeSetup s;
            s.material = m;
            s.lights.push_back(Light{Light::Type::Directional, {1.0, 1.0, 1.0}, {1.0, 1.0, 1.0}, 1.0, 0.0});
            s.precision = p;
            setups.push_back(s);
        }
    }
    if (build_threads > 0) {
        std::vector<ProgramRequest> programs;
        for (const ShadeSetup& s : setups)
            programs.push_back(shade_program(s.material, s.lights, s.precision, rt.vector_width(), is_perspective(s.view)));
        prebuild(rt, programs, unsigned(build_threads));
    }
    for (const ShadeSetup& s : setups) shader.shade(fb, s);
    std::printf("builds %.1f total %.1f programs %zu cached %zu rejected %zu\n", 1000.0 * rt.build_seconds(),
                ms_since(t0), rt.programs_built(), rt.programs_from_cache(), rt.cache_entries_rejected());
    return 0;
}

struct BuildRun {
    double build_ms = 0, total_ms = 0;
    std::size_t programs = 0, cached = 0;
};

BuildRun run_child(const std::string& self, const std::string& pocl_cache, const std::string& program_cache, int max_models,
                   int build_threads) {
    const std::string cmd = "POCL_CACHE_DIR='" + pocl_cache + "' SHADELAB_PROGRAM_CACHE='" + program_cache + "' '" +
                            self + "' --child-builds --build-models " + std::to_string(max_models) +
                            " --build-threads " + std::to_string(build_threads);
    const std::string out = run_capture(cmd);
    BuildRun r;
    std::size_t rejected = 0;
    if (std::sscanf(out.c_str(), "builds %lf total %lf programs %zu cached %zu rejected %zu", &r.build_ms, &r.total_ms,
                    &r.programs, &r.cached, &rejected) != 5)
        throw Error("unexpected output of the build child: " + out.substr(0, 200));
    return r;
}

void bench_builds(const std::string& self, const fs::path& tmp, int max_models) {
    std::printf("\n== program builds: %s catalogue model%s, precise and fast, built and run once (fresh process each)\n",
                max_models > 0 ? ("the first " + std::to_string(max_models)).c_str() : "every",
                max_models == 1 ? "" : "s");
    std::printf("%-52s %10s %10s %9s %7s\n", "case", "build", "process", "programs", "cached");
    const std::string pocl_a = (tmp / "pocl-a").string(), pocl_b = (tmp / "pocl-b").string();
    const std::string cache = (tmp / "programs").string();
    struct Step {
        const char* label;
        std::string pocl, programs;
        int threads;   // 0: each program built when first used, one after another (the old way)
    };
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    const std::vector<Step> steps = {
        {"cold: PoCL cache empty, shadelab cache off", pocl_a, "off", 0},
        {"PoCL cache warm, shadelab cache off", pocl_a, "off", 0},
        {"cold: PoCL cache empty, shadelab cache empty", pocl_b, cache, 0},
        {"warm: shadelab cache warm (PoCL cache warm)", pocl_b, cache, 0},
        {"shadelab cache warm, PoCL cache empty", (tmp / "pocl-c").string(), cache, 0},
        {"cold, prebuilt on 1 thread", (tmp / "pocl-d").string(), "off", 1},
        {"cold, prebuilt on every hardware thread", (tmp / "pocl-e").string(), "off", int(hw)},
    };
    double cold = 0;
    for (const Step& s : steps) {
        const BuildRun r = run_child(self, s.pocl, s.programs, max_models, s.threads);
        if (cold == 0) cold = r.total_ms;
        std::printf("%-52s %8.0fms %8.0fms %9zu %7zu   %.2fx the cold run\n", s.label, r.build_ms, r.total_ms, r.programs,
                    r.cached, cold / r.total_ms);
    }
}

// One round per repetition, each mesh loaded four ways back to back (so the load's drift hits them alike): the
// full loader (cache off), the key alone (SHA-256 of the file), a miss that stores the entry (cache emptied first)
// and a hit. The hit must be the full loader's mesh, bit for bit, or the bench fails.
void bench_meshes(const std::vector<std::string>& meshes, int reps, const fs::path& tmp) {
    std::printf("\n== mesh loading: the full loader (OpenMesh's readers + shadelab's checks and repairs) against the mesh "
                "cache, best of %d\n",
                reps);
    std::printf("%-24s %9s %11s %9s %11s %9s %9s %8s\n", "mesh", "triangles", "cache off", "key", "miss+store",
                "cached", "ratio", "entry");
    const fs::path cache = tmp / "meshes";
    for (const std::string& path : meshes) {
        double cold = 1e30, key = 1e30, miss = 1e30, hit = 1e30;
        Mesh want;
        for (int r = 0; r < reps; ++r) {
            auto t0 = clock_type::now();
            want = load_mesh_uncached(path);
            cold = std::min(cold, ms_since(t0));
            t0 = clock_type::now();
            const std::string k = mesh_cache_key(path, lower_ext(path));
            key = std::min(key, ms_since(t0));
            fs::remove_all(cache);
            MeshCacheUse use;
            use.setting = cache.string();
            t0 = clock_type::now();
            load_mesh(path, nullptr, &use);
            miss = std::min(miss, ms_since(t0));
            if (use.hit || !use.written) throw Error("mesh cache: the first load of '" + path + "' was not a miss that stored");
            t0 = clock_type::now();
            const Mesh got = load_mesh(path, nullptr, &use);
            hit = std::min(hit, ms_since(t0));
            if (!use.hit || got.positions != want.positions || got.normals != want.normals || got.triangles != want.triangles)
                throw Error("mesh cache: the second load of '" + path + "' was not a hit equal to the full load");
        }
        const double entry_mb = double(fs::file_size(mesh_cache_entry(cache.string(), mesh_cache_key(path, lower_ext(path))))) / 1e6;
        std::printf("%-24s %9zu %9.1fms %7.1fms %9.1fms %7.1fms %8.1fx %6.1fMB\n",
                    path.substr(path.find_last_of('/') + 1).c_str(), want.triangles.size(), cold, key, miss, hit,
                    cold / hit, entry_mb);
    }
}

}  // namespace

int main(int argc, char** argv) {
    bool smoke = false, child = false, no_planning = false, contact_only = false, meshes_only = false, writes_only = false,
         startup_only = false;
    std::string child_plan_scene, child_contact_out;
    int contact_shared = 1, contact_reps = 2;
    std::vector<std::string> plan_scenes = {std::string(SHADELAB_SOURCE_DIR) + "/scenes/materials.json",
                                            std::string(SHADELAB_SOURCE_DIR) + "/scenes/minimal.json"};
    int reps = 3, build_models = 0, build_threads = 0;
    std::string size = "4096x4096";
    const std::string mesh_dir = std::string(SHADELAB_SOURCE_DIR) + "/meshes";
    std::vector<std::string> meshes = {mesh_dir + "/suzanne.obj", mesh_dir + "/spot.obj", mesh_dir + "/teapot.obj",
                                       mesh_dir + "/stanford-bunny.obj", mesh_dir + "/dragon_vrip_res2.ply"};
    CLI::App app{"bench_e2e_process: image writes against oiiotool, program builds and caches, mesh loading"};
    app.add_flag("--smoke", smoke, "Tiny run for the test suite: 64x64, two models, no timing claims");
    app.add_option("--size", size, "Image size of the write benchmark, WIDTHxHEIGHT")->capture_default_str();
    app.add_option("--reps", reps, "Repetitions (best is reported)")->capture_default_str()->check(CLI::Range(1, 100));
    app.add_option("--build-models", build_models, "Build only the first N catalogue models (0 = all)")
        ->capture_default_str()->check(CLI::Range(0, 1000));
    app.add_option("--build-threads", build_threads, "(internal) build the programs ahead on N threads")
        ->check(CLI::Range(-1, 256));
    app.add_option("--plan-scenes", plan_scenes, "Scenes of the planning rows")->capture_default_str();
    app.add_flag("--no-planning", no_planning, "Skip the planning rows");
    app.add_flag("--meshes-only", meshes_only, "Only the mesh-loading table");
    app.add_flag("--writes-only", writes_only, "Only the image-write table");
    app.add_flag("--startup-only", startup_only, "Only the process start-up table");
    app.add_option("--child-plan", child_plan_scene, "(internal) plan this scene once and print the times");
    app.add_option("--child-contact", child_contact_out, "(internal) write the contact sheet here once, print the times");
    app.add_option("--contact-shared", contact_shared, "(internal) with --child-contact: 1 shared program, 0 per model")
        ->check(CLI::Range(0, 1));
    app.add_option("--contact-reps", contact_reps, "Cold contact-sheet runs of each kind (0: none)")
        ->capture_default_str()->check(CLI::Range(0, 20));
    app.add_flag("--contact-only", contact_only, "Only the cold contact-sheet rows");
    app.add_flag("--child-builds", child, "(internal) build the catalogue once and print the times");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);
        std::cerr << "bench_e2e_process: error: " << e.what() << " (see bench_e2e_process --help)\n";
        return 2;
    }
    try {
        if (child) return child_builds(build_models, build_threads);
        if (!child_contact_out.empty()) return bench::child_contact(child_contact_out, contact_shared != 0);
        if (!child_plan_scene.empty()) return bench::child_plan(child_plan_scene, build_threads);
        int w = 0, h = 0;
        char x = 0;
        if (smoke) size = "64x64", reps = 1, build_models = 2;
        if (std::sscanf(size.c_str(), "%d%c%d", &w, &x, &h) != 3 || x != 'x' || w < 1 || h < 1 || w > 16384 || h > 16384)
            throw Error("--size expects WIDTHxHEIGHT with each side in [1, 16384]; got '" + size + "'");
        const fs::path tmp = fs::temp_directory_path() / ("shadelab-bench-process-" + std::to_string(::getpid()));
        fs::create_directories(tmp);
        std::printf("machine: %u hardware threads, %s\n", std::thread::hardware_concurrency(), bench::cpu_name().c_str());
        std::printf("at the start, %s\n", bench::core_probe().line().c_str());
        const std::string self = fs::canonical("/proc/self/exe").string();
        if (startup_only) {
            bench_startup(self, tmp, reps);
            fs::remove_all(tmp);
            return 0;
        }
        if (contact_only) {
            bench::bench_contact(run_capture, self, tmp, std::max(1, contact_reps));
            fs::remove_all(tmp);
            return 0;
        }
        if (!meshes_only) {
            Runtime rt;
            std::printf("OpenCL: %s\n", rt.device_description().c_str());
            bench_writes(rt, load_mesh_uncached(mesh_dir + "/stanford-bunny.obj"), w, h, reps, tmp);
            if (writes_only) {
                fs::remove_all(tmp);
                return 0;
            }
            bench_startup(self, tmp, reps);
            bench_builds(self, tmp, build_models);
            if (!smoke && contact_reps > 0) bench::bench_contact(run_capture, self, tmp, contact_reps);
            if (!smoke && !no_planning) bench::bench_planning(run_capture, self, tmp, plan_scenes);
        }
        bench_meshes(smoke ? std::vector<std::string>{mesh_dir + "/spot.obj"} : meshes, reps, tmp);
        std::printf("at the end, %s\n", bench::core_probe().line().c_str());
        fs::remove_all(tmp);
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "bench_e2e_process: error: " << e.what() << "\n";
        return 1;
    }
}
