// shadelab render: one mesh, one material, some lights -> one image.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>

#include "app/commands.hpp"
#include "cl/runtime.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "core/log.hpp"
#include "core/limits.hpp"
#include "image/image.hpp"
#include "mesh/mesh.hpp"
#include "pipeline/pipeline.hpp"
#include "plan/plan_job.hpp"
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
    std::string depth, normal;         // AOVs: view-space depth, world-space normal (.exr)
};


Material material_of(const RenderArgs& a) {
    require_model_name(a.model, "--model");
    Material mat;
    mat.model = a.model;
    for (const auto& p : a.params) add_param(mat, p);
    mat.albedo = parse_vec3(a.albedo, "--albedo", 0.0, kMaxColour);
    mat.specular = parse_vec3(a.specular, "--specular", 0.0, kMaxColour);
    return resolve_material(mat, "--model " + a.model);
}

Camera camera_of(const RenderArgs& a, const Mesh& mesh, int w, int h) {
    if (a.eye.empty()) return Camera::fit(mesh.bounds(), parse_vec3(a.view_from, "--view-from"), a.fov, double(w) / h);
    Camera cam;
    cam.eye = parse_vec3(a.eye, "--eye", -kMaxCoordinate, kMaxCoordinate);
    cam.target = a.target.empty() ? mesh.bounds().centre() : parse_vec3(a.target, "--target", -kMaxCoordinate, kMaxCoordinate);
    cam.up = parse_vec3(a.up, "--up", -kMaxCoordinate, kMaxCoordinate);
    cam.fov_y_deg = a.fov;
    const double dist = glm::length(cam.eye - cam.target) + mesh.bounds().radius() * 4.0;
    cam.z_near = std::max(1e-4, dist * 1e-4);
    cam.z_far = dist * 4.0;
    return cam;
}

// An AOV output (--depth, --normal) must be a linear float format, as a scene's "depth" and "normal".
std::string aov_path(const std::string& path, const std::string& option) {
    if (!path.empty() && encoding_for(path) != Encoding::Linear)
        throw Error(option + " '" + path + "' is not a linear float format: use .exr");
    return path;
}

// Everything but the mesh: options checked before any work.
pipeline::Job job_of(const RenderArgs& a) {
    encoding_for(a.output);   // reject a bad extension before any work
    pipeline::Job job;
    job.meshes.push_back(pipeline::JobMesh{Mesh{}, material_of(a), a.cull});
    for (const auto& l : a.lights) job.lights.push_back(parse_light(l));
    if (a.lights.empty()) job.lights.push_back(Light{Light::Type::Directional, {1.0, 1.0, 1.0}, {1, 1, 1}, 1.0, 0.0});
    const ImageSize size = parse_size(a.size, "--size", 1, 16384);
    job.width = size.width;
    job.height = size.height;
    if (!a.max_memory.empty()) set_memory_limit(parse_bytes(a.max_memory, "--max-memory"));
    check_memory("--size " + a.size, double(job.width) * double(job.height) * kRenderBytesPerPixel);
    job.ambient = parse_vec3(a.ambient, "--ambient", 0.0, kMaxColour);
    job.background = parse_vec4(a.background, "--background", 1.0);
    for (int c = 0; c < 3; ++c) in_range(job.background[c], "--background", -kMaxColour, kMaxColour);
    in_range(job.background[3], "--background alpha", 0.0, 1.0);
    job.precision = parse_precision(a.precision);
    job.per_vertex = a.per_vertex;
    job.triangle_ids = a.per_vertex || a.tolerance > 0.0;   // the plan may choose per-vertex shading of this frame
    job.outputs.colour = {a.output};
    job.outputs.depth = aov_path(a.depth, "--depth");
    job.outputs.normal = aov_path(a.normal, "--normal");
    return job;
}

PlanOptions plan_options(const RenderArgs& a) {
    PlanOptions po;
    po.tolerance = a.tolerance;
    po.catalogue = !a.no_catalogue;
    if (a.metric == "relative") po.metric = PlanMetric::Relative;
    else if (a.metric != "de2000") throw Error("--metric must be 'de2000' or 'relative', got '" + a.metric + "'");
    return po;
}

// A render is a one-job batch: the job described by the options, run through the same stages (host/pipeline/).
void run_render(RenderArgs a) {
    if (log_level() == LogLevel::Quiet) a.quiet = true;   // the global -q means what render's own -q means
    pipeline::Job job = job_of(a);
    const PlanOptions po = a.tolerance > 0.0 ? plan_options(a) : PlanOptions{};

    pipeline::StageTimes times;
    const auto t0 = std::chrono::steady_clock::now();
    MeshLoadReport report;
    job.meshes.front().mesh = load_mesh(a.mesh, &report);
    times.load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const Mesh& mesh = job.meshes.front().mesh;
    if (!a.quiet) {
        std::cerr << "mesh " << a.mesh << ": " << report.triangles_out << " triangles, " << report.vertices_in
                  << " vertices, normals " << (report.normals_from_file ? "from file" : "computed (area-weighted)")
                  << "\n";
        for (const auto& note : report.notes) std::cerr << "  repaired: " << note << "\n";
    }
    job.camera = camera_of(a, mesh, job.width, job.height);

    Runtime rt;
    Shader shader(rt);
    const pipeline::Frame frame = pipeline::raster(job, times);
    if (frame.fb.empty())
        std::cerr << "warning: the mesh covers no pixel from this camera (eye " << job.camera.eye.x << ","
                  << job.camera.eye.y << "," << job.camera.eye.z
                  << "): the image is background only; check --eye/--target/--view-from\n";
    if (a.tolerance > 0.0) {
        const Plan plan = plan_job(rt, job, po, times);
        if (!a.quiet) std::cerr << format_plan(plan, po);
    }
    const auto rgb = pipeline::shade(shader, job, frame, times);
    pipeline::resolve_and_write(job, frame, rgb, times);
    if (!a.quiet) {
        std::cerr << "device " << rt.device_description() << "\n";
        std::cerr << frame.fb.size() << " fragments; " << pipeline::describe(times) << "\n";
    }
    for (const auto& o : job.outputs.all()) std::cout << o << "\n";
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
    cmd->add_option("--depth", args->depth, "Also write the view-space depth (AOV, one linear channel, 0 where no surface): .exr");
    cmd->add_option("--normal", args->normal, "Also write the world-space normal (AOV, RGBA, alpha = coverage): .exr");
    cmd->add_flag("-q,--quiet", args->quiet, "Print only the output path(s)");
    cmd->add_option("--max-memory", args->max_memory,
                    "Refuse sizes needing more memory than this (e.g. 32G; default: the machine's memory, or SHADELAB_MAX_MEMORY)");
    cmd->callback([args] { run_render(*args); });
}

}  // namespace shadelab::app
