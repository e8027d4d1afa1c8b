// shadelab render: one mesh, one material, some lights -> one image.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>

#include "app/commands.hpp"
#include "cl/runtime.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/limits.hpp"
#include "image/image.hpp"
#include "mesh/mesh.hpp"
#include "models/catalogue.hpp"
#include "raster/raster.hpp"
#include "plan/planner.hpp"
#include "shade/gouraud.hpp"
#include "shade/shader.hpp"

namespace shadelab::app {

namespace {

struct RenderArgs {
    std::string mesh;
    std::string output = "out/render.png";
    std::string model = "lambert";
    std::vector<std::string> params;
    std::string albedo = "0.8,0.8,0.8";
    std::string specular = "1,1,1";
    std::vector<std::string> lights;
    std::string ambient = "0,0,0";
    std::string view_from = "0,0.25,1";
    std::string eye, target, up = "0,1,0";
    double fov = 35.0;
    std::string size = "512x512";
    std::string background = "0,0,0,0";
    bool cull = false;
    bool quiet = false;
    std::string precision = "precise";
    bool per_vertex = false;
    double tolerance = 0.0;            // > 0: plan (docs/planner.md) and render the cheapest config within it
    std::string metric = "de2000";
    std::string max_memory;            // overrides the memory limit (core/limits.hpp)
    bool no_catalogue = false;         // --tolerance without the per-material catalogue search (the old planner)
};


void parse_size(const std::string& s, int& w, int& h) {
    int a = 0, b = 0;
    char x = 0, extra = 0;
    if (std::sscanf(s.c_str(), "%d%c%d%c", &a, &x, &b, &extra) != 3 || (x != 'x' && x != 'X'))
        throw Error("--size expects WIDTHxHEIGHT such as 512x512, got '" + s + "'");
    if (a < 1 || b < 1 || a > 16384 || b > 16384) throw Error("--size " + s + ": each side must be in [1, 16384]");
    w = a;
    h = b;
}

void run_render(RenderArgs a) {
    if (log_level() == LogLevel::Quiet) a.quiet = true;   // the global -q means what render's own -q means
    using clock = std::chrono::steady_clock;
    auto ms = [](auto t0, auto t1) { return std::chrono::duration<double, std::milli>(t1 - t0).count(); };
    encoding_for(a.output);   // reject a bad extension before any work

    require_model_name(a.model, "--model");
    Material mat;
    mat.model = a.model;
    for (const auto& p : a.params) {
        const auto kv = parse_param(p);
        mat.params[kv.first] = kv.second;
    }
    mat.albedo = parse_vec3(a.albedo, "--albedo", 0.0, kMaxColour);
    mat.specular = parse_vec3(a.specular, "--specular", 0.0, kMaxColour);
    mat = resolve_material(mat, "--model " + a.model);

    std::vector<Light> lights;
    for (const auto& l : a.lights) lights.push_back(parse_light(l));
    if (a.lights.empty()) lights.push_back(Light{Light::Type::Directional, {1.0, 1.0, 1.0}, {1, 1, 1}, 1.0, 0.0});

    int w = 0, h = 0;
    parse_size(a.size, w, h);
    if (!a.max_memory.empty()) set_memory_limit(parse_bytes(a.max_memory, "--max-memory"));
    check_memory("--size " + a.size, double(w) * double(h) * kRenderBytesPerPixel);
    const glm::dvec3 ambient = parse_vec3(a.ambient, "--ambient", 0.0, kMaxColour);
    const glm::dvec4 background = parse_vec4(a.background, "--background", 1.0);
    for (int c = 0; c < 3; ++c) in_range(background[c], "--background", -kMaxColour, kMaxColour);
    in_range(background[3], "--background alpha", 0.0, 1.0);

    const auto t0 = clock::now();
    MeshLoadReport report;
    Mesh mesh = load_mesh(a.mesh, &report);
    const auto t1 = clock::now();
    if (!a.quiet) {
        std::cerr << "mesh " << a.mesh << ": " << report.triangles_out << " triangles, " << report.vertices_in
                  << " vertices, normals " << (report.normals_from_file ? "from file" : "computed (area-weighted)")
                  << "\n";
        for (const auto& note : report.notes) std::cerr << "  repaired: " << note << "\n";
    }

    Camera cam;
    if (!a.eye.empty()) {
        cam.eye = parse_vec3(a.eye, "--eye", -kMaxCoordinate, kMaxCoordinate);
        cam.target = a.target.empty() ? mesh.bounds().centre() : parse_vec3(a.target, "--target", -kMaxCoordinate, kMaxCoordinate);
        cam.up = parse_vec3(a.up, "--up", -kMaxCoordinate, kMaxCoordinate);
        cam.fov_y_deg = a.fov;
        const double dist = glm::length(cam.eye - cam.target) + mesh.bounds().radius() * 4.0;
        cam.z_near = std::max(1e-4, dist * 1e-4);
        cam.z_far = dist * 4.0;
    } else {
        cam = Camera::fit(mesh.bounds(), parse_vec3(a.view_from, "--view-from"), a.fov, double(w) / h);
    }

    RasterOptions ro;
    ro.width = w;
    ro.height = h;
    ro.cull_backfaces = a.cull;
    RasterStats rs;
    const FragmentBuffer fb = rasterize(mesh, cam, ro, &rs);
    const auto t2 = clock::now();
    if (fb.empty())
        std::cerr << "warning: the mesh covers no pixel from this camera (eye " << cam.eye.x << "," << cam.eye.y
                  << "," << cam.eye.z << "): the image is background only; check --eye/--target/--view-from\n";

    Runtime rt;
    Shader shader(rt);
    ShadeSetup setup;
    setup.material = mat;
    setup.lights = lights;
    setup.ambient = ambient;
    setup.view = glm::dvec4(cam.eye, 1.0);
    setup.precision = parse_precision(a.precision);
    bool per_vertex = a.per_vertex;
    double plan_ms = 0.0;   // stated apart from shading, which starts after the plan
    if (a.tolerance > 0.0) {
        PlanInput pin;
        pin.camera = cam;
        pin.width = w;
        pin.height = h;
        pin.items.push_back(PlanItem{mesh, mat, a.cull, -1, glm::dmat4(1.0)});
        pin.lights = lights;
        pin.ambient = setup.ambient;
        PlanOptions po;
        po.tolerance = a.tolerance;
        po.catalogue = !a.no_catalogue;
        if (a.metric == "relative") po.metric = PlanMetric::Relative;
        else if (a.metric != "de2000") throw Error("--metric must be 'de2000' or 'relative', got '" + a.metric + "'");
        const Plan plan = make_plan(rt, pin, po);
        if (!a.quiet) std::cerr << format_plan(plan, po);
        setup.material = plan.materials.front();
        setup.lights = plan.kept_lights;
        setup.precision = plan.chosen.config.precision;
        per_vertex = plan.chosen.config.per_vertex;
        plan_ms = plan.planning_ms;
    }
    const auto t2s = clock::now();
    ShadeTiming st;
    const auto rgb = per_vertex ? interpolate_to_fragments(fb, mesh, shade_vertices(shader, mesh, setup, &st))
                                : shader.shade(fb, setup, &st);
    const auto t3 = clock::now();
    const Image img = compose_image(fb, rgb, background);
    write_image(a.output, img);
    const auto t4 = clock::now();
    if (!a.quiet) {
        std::cerr << "device " << rt.device_description() << "\n";
        std::cerr << "load " << ms(t0, t1) << " ms, rasterise " << ms(t1, t2) << " ms (" << fb.size()
                  << " fragments), "
                  << (a.tolerance > 0.0 ? "plan " + std::to_string(plan_ms) + " ms, " : std::string()) << "shade "
                  << ms(t2s, t3) << " ms (kernel " << st.kernel_ms << " ms, build "
                  << st.build_ms << " ms), write " << ms(t3, t4) << " ms\n";
    }
    std::cout << a.output << "\n";
}

}  // namespace

void add_render_command(CLI::App& app) {
    auto args = std::make_shared<RenderArgs>();
    auto* cmd = app.add_subcommand("render", "Shade one mesh with one model and write an image (.png sRGB, .exr .tif .fits linear, ...)");
    cmd->add_option("mesh", args->mesh, "Mesh file: .obj .off .ply .stl")->required();
    cmd->add_option("-o,--output", args->output, std::string("Output image: ") + kOutputFormats)
        ->capture_default_str();
    cmd->add_option("-m,--model", args->model, "Lighting model (see 'shadelab models')")->capture_default_str();
    cmd->add_option("-p,--param", args->params, "Model parameter name=value (repeatable)");
    cmd->add_option("--albedo", args->albedo, "Diffuse colour r,g,b (linear)")->capture_default_str();
    cmd->add_option("--specular", args->specular, "Specular colour r,g,b (linear)")->capture_default_str();
    cmd->add_option("-l,--light", args->lights,
                    "Light: dir:x,y,z[:r,g,b[:intensity]] (direction TO the light) or "
                    "point:x,y,z[:r,g,b[:intensity[:range]]] (repeatable; default dir:1,1,1)");
    cmd->add_option("--ambient", args->ambient, "Ambient light r,g,b (multiplied by albedo)")->capture_default_str();
    cmd->add_option("--view-from", args->view_from,
                    "Direction from the mesh centre to the camera; the camera is framed to fit the mesh")
        ->capture_default_str();
    cmd->add_option("--eye", args->eye, "Camera position x,y,z (overrides --view-from)");
    cmd->add_option("--target", args->target, "Camera target x,y,z (default: mesh centre)");
    cmd->add_option("--up", args->up, "Camera up vector")->capture_default_str();
    cmd->add_option("--fov", args->fov, "Vertical field of view in degrees")->capture_default_str()->check(CLI::Range(1.0, 170.0));
    cmd->add_option("--size", args->size, "Image size WIDTHxHEIGHT")->capture_default_str();
    cmd->add_option("--background", args->background, "Background r,g,b[,a] (linear; alpha 0 = transparent)")
        ->capture_default_str();
    cmd->add_flag("--cull", args->cull, "Cull back faces");
    cmd->add_option("--precision", args->precision, "Kernel precision: precise or fast (docs/precision.md)")
        ->capture_default_str();
    cmd->add_flag("--per-vertex", args->per_vertex, "Shade at vertices and interpolate (Gouraud) instead of per pixel");
    cmd->add_option("--tolerance", args->tolerance,
                    "Plan first: render the cheapest configuration whose error stays within this (docs/planner.md)");
    cmd->add_option("--metric", args->metric, "Tolerance metric: de2000 (max Delta E 2000) or relative")
        ->capture_default_str();
    cmd->add_flag("--no-catalogue", args->no_catalogue,
                  "With --tolerance: only the requested model or Lambert, no catalogue search (docs/planner.md)");
    cmd->add_flag("-q,--quiet", args->quiet, "Print only the output path");
    cmd->add_option("--max-memory", args->max_memory,
                    "Refuse sizes needing more memory than this (e.g. 32G; default: the machine's memory, or SHADELAB_MAX_MEMORY)");
    cmd->callback([args] { run_render(*args); });
}

}  // namespace shadelab::app
