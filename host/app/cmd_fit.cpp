// shadelab fit: fit one catalogue model to another (or every model, --all) over a domain, with the error that
// remains, standard errors and diagnostics in words (host/fit/).
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>

#include "app/commands.hpp"
#include "cl/runtime.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "fit/all.hpp"
#include "fit/atlas.hpp"
#include "fit/fit.hpp"
#include "fit/report.hpp"
#include "models/catalogue.hpp"

namespace fs = std::filesystem;

namespace shadelab::app {

namespace {

struct FitArgs {
    std::string target;
    std::vector<std::string> target_params;
    std::string model;
    std::vector<std::string> fixed;
    bool all = false;
    std::string over = "hemisphere";
    std::string metric = "rel-rms";
    std::string json;
    std::string out_dir;
    std::size_t samples = 65536;
    std::uint64_t seed = 1;
    double phase = -1.0;
    bool at_normal = false;
    double min_cos = 0.0;
    double albedo = 0.8;
    double specular = 1.0;
    double model_specular = -1.0;
    bool no_limb_check = false;
    std::string precision = "precise";
    std::vector<std::string> models;   // --all: a subset
    std::string atlas;                 // --atlas DOCS: write the fidelity atlas
    std::string centre;                // disc images: x,y in pixels
    double radius = -1.0;
    double pa = 0.0;
    std::string scene;                 // an EXR with AOVs: the scene file it was rendered from
    std::string normal, depth;         // its AOVs (default: the scene's outputs next to the image)
};

std::map<std::string, double> params_of(const std::vector<std::string>& ps) {
    std::map<std::string, double> m;
    for (const auto& p : ps) {
        const auto kv = parse_param(p);
        m[kv.first] = kv.second;
    }
    return m;
}

void run_fit(const FitArgs& a) {
    if (!a.atlas.empty()) {
        Runtime rt;
        fit::AtlasOptions o;
        o.docs_dir = a.atlas;
        o.seed = a.seed;
        o.samples = a.samples;
        for (const auto& f : fit::write_atlas(rt, o, std::cerr)) std::cout << f << "\n";
        return;
    }
    auto ends_with = [](const std::string& s, const std::string& e) {
        return s.size() >= e.size() && s.compare(s.size() - e.size(), e.size(), e) == 0;
    };
    const bool image = ends_with(a.over, ".png") || ends_with(a.over, ".exr") || ends_with(a.over, ".tif") ||
                       ends_with(a.over, ".tiff") || ends_with(a.over, ".fits") || ends_with(a.over, ".fit");
    const bool aov = image && !a.scene.empty();
    if (!a.scene.empty() && !image)
        throw UsageError("--scene names the scene of a rendered --over IMAGE.exr; to fit over a scene's fragments use --over SCENE.json");
    if (!aov && (!a.normal.empty() || !a.depth.empty()))
        throw UsageError("--normal and --depth are the AOVs of a batch render: give them with --over IMAGE.exr --scene SCENE.json");
    if (aov && a.phase >= 0.0)
        throw UsageError("--over " + a.over + " --scene: the scene's lights and camera give the geometry, drop --phase");
    if (image) {
        if (!a.target.empty()) throw Error("--over " + a.over + ": the image is the target, drop --target");
        if (a.phase < 0.0 && !aov)
            throw UsageError("--over " + a.over + ": give --scene SCENE.json for a batch render with normal and depth AOVs, "
                        "or the sun's --phase (degrees) and --pa of a disc image");
    } else if (a.target.empty()) {
        throw Error("give the target model with --target MODEL (shadelab models lists them)");
    }
    if (a.all == !a.model.empty())
        throw Error(a.all ? "--all fits every model: drop --model" : "give the model to fit with --model MODEL, or --all");
    const bool scene = a.over != "hemisphere" && !image;
    if (scene && !ends_with(a.over, ".json"))
        throw Error("--over '" + a.over + "': give hemisphere, a scene file (.json) or a disc image (.png .exr .tif .fits)");
    const std::vector<std::string> metrics = scene || aov ? std::vector<std::string>{"rel-rms", "de2000-mean", "de2000-p99", "de2000-max"}
                                                   : std::vector<std::string>{"rel-rms"};
    if (std::find(metrics.begin(), metrics.end(), a.metric) == metrics.end()) {
        std::string list;
        for (const auto& m : metrics) list += (list.empty() ? "" : ", ") + m;
        throw Error("--metric '" + a.metric + "' is not available on this domain: use " + list);
    }
    if (image && (a.at_normal || a.min_cos > 0.0))
        throw Error("--at-normal and --min-cos restrict the hemisphere domain: drop them with a disc image");
    if (scene && (a.phase >= 0.0 || a.at_normal || a.min_cos > 0.0))
        throw Error("--phase, --at-normal and --min-cos restrict the hemisphere domain: drop them with --over SCENE.json");
    if (!(a.albedo > 0.0 && a.albedo <= 1.0)) throw Error("--albedo must be in (0, 1]");
    if (!(a.specular >= 0.0) || !std::isfinite(a.specular)) throw Error("--specular must be finite and >= 0");
    if (a.model_specular != -1.0 && (!(a.model_specular >= 0.0) || !std::isfinite(a.model_specular)))
        throw Error("--model-specular must be finite and >= 0");
    if (a.all && a.out_dir.empty()) throw Error("--all writes a table and a chart: give the folder with -o DIR");
    Runtime rt;
    std::unique_ptr<fit::Problem> problem_ptr;
    Material target;
    if (image) {
        fit::DiscImageOptions io;
        io.image = a.over;
        if (!a.centre.empty()) {
            const glm::dvec3 c = parse_vec3(a.centre + ",0", "--centre");
            io.cx = c.x;
            io.cy = c.y;
        }
        io.radius = a.radius;
        io.phase_deg = a.phase;
        io.pa_deg = a.pa;
        std::vector<double> values;
        fit::Domain d = aov ? fit::aov_image_domain({a.over, a.scene, a.normal, a.depth}, values)
                            : fit::disc_image_domain(io, values);
        problem_ptr = std::make_unique<fit::Problem>(rt, std::move(d), std::move(values), a.over, parse_precision(a.precision));
        target = problem_ptr->target_material();
        target.albedo = glm::dvec3(a.albedo);
        target.specular = glm::dvec3(a.specular);
    }
    if (!image) {
    target.model = a.target;
    for (const auto& p : a.target_params) add_param(target, p);
    target.albedo = glm::dvec3(a.albedo);
    target.specular = glm::dvec3(a.specular);
    const ModelInfo& tinfo = find_model(a.target);
    add_demo_children(target, tinfo);
    for (auto& c : target.children) c.albedo = glm::dvec3(1.0);
    target = resolve_material(target, "--target " + a.target);
    }
    const auto fixed = params_of(a.fixed);
    if (!a.model.empty()) find_model(a.model);

    fit::HemisphereOptions ho;
    ho.samples = a.samples;
    ho.seed = a.seed;
    ho.has_phase = a.phase >= 0.0;
    ho.phase_deg = a.phase;
    ho.at_normal = a.at_normal;
    ho.min_cos = a.min_cos;
    fit::FitOptions fo;
    fo.limb_check = !a.no_limb_check;
    if (!problem_ptr)
        problem_ptr = std::make_unique<fit::Problem>(rt, scene ? fit::scene_domain(a.over, a.seed) : fit::hemisphere_domain(ho),
                                                     target, parse_precision(a.precision));
    fit::Problem& problem = *problem_ptr;
    if (!a.all) {
        std::string note;
        const fit::ModelShape shape = fit::shape_for(a.model, target, a.model_specular, &note);
        fit::FitResult r = fit::fit_model(problem, shape, fixed, fo);
        r.note = note;
        std::cout << fit::to_text(r);
        if (!a.json.empty()) write_text_atomically(a.json, "fit report", fit::to_json(r).dump(2) + "\n");
        return;
    }
    fit::AllOptions ao;
    ao.fit = fo;
    ao.models = a.models;
    ao.model_specular = a.model_specular;
    ao.out_dir = a.out_dir;
    ao.metric = a.metric;
    const fit::AllResult all = fit::fit_all(rt, problem, ao, std::cerr);
    std::cout << fit::all_table_text(all);
    if (!a.json.empty()) write_text_atomically(a.json, "fit report", fit::to_json(all).dump(2) + "\n");
    for (const auto& f : all.files) std::cout << f << "\n";
}

}  // namespace

void add_fit_command(CLI::App& app) {
    auto a = std::make_shared<FitArgs>();
    auto* cmd = app.add_subcommand(
        "fit", "Fit a catalogue model (or every one, --all) to a target model: parameters, free grey albedo, the "
               "error that remains and whether the fit is well posed");
    cmd->add_option("--target", a->target, "Target model (shadelab models lists them)");
    cmd->add_option("-p,--param", a->target_params, "Target parameter name=value (repeatable)");
    cmd->add_option("--model", a->model, "Model to fit to the target");
    cmd->add_option("--fix", a->fixed, "Hold a parameter of the fitted model at name=value (repeatable)");
    cmd->add_flag("--all", a->all, "Fit every model of the catalogue; table and chart in -o DIR");
    cmd->add_option("--models", a->models, "With --all: only these models, comma-separated")->delimiter(',');
    cmd->add_option("--over", a->over,
                    "Domain of the fit: hemisphere (N = +z, L and V uniform in solid angle), SCENE.json (the fragments "
                    "the scene renders, with its lights), a batch render IMAGE.exr with --scene (its normal and depth "
                    "AOVs give N and P; the pixels are the target) or a disc IMAGE (with --phase, --pa, --centre, "
                    "--radius: the image is the target)")
        ->capture_default_str();
    cmd->add_option("--metric", a->metric,
                    "Error --all sorts by: rel-rms = sqrt(sum (fit - target)^2 / sum target^2); on a scene also "
                    "de2000-mean, de2000-p99, de2000-max. The fit itself minimises rel-rms")
        ->capture_default_str();
    cmd->add_option("--json", a->json, "Write the result as JSON");
    cmd->add_option("-o,--out", a->out_dir, "Folder for --all's table (CSV) and chart (PNG)");
    cmd->add_option("--samples", a->samples, "Sample pairs (L, V) of the hemisphere domain")->capture_default_str();
    cmd->add_option("--seed", a->seed, "Seed of the sample points")->capture_default_str();
    cmd->add_option("--phase", a->phase, "Only pairs with angle(L, V) = G degrees (the lunar case); a disc image's phase");
    cmd->add_flag("--at-normal", a->at_normal, "The view-on-normal slice: V = N");
    cmd->add_option("--centre,--center", a->centre, "Disc image: centre x,y in pixels (default: the image centre)");
    cmd->add_option("--radius", a->radius, "Disc image: radius in pixels (default: 0.45 of the smaller side)");
    cmd->add_option("--pa", a->pa, "Disc image: position angle of the sun, degrees from image up towards image left")
        ->capture_default_str();
    cmd->add_option("--scene", a->scene,
                    "With --over IMAGE.exr: the scene file it was rendered from (camera, size, lights, ambient)");
    cmd->add_option("--normal", a->normal,
                    "With --scene: the normal AOV (default: the scene's outputs.normal in the image's folder)");
    cmd->add_option("--depth", a->depth,
                    "With --scene: the depth AOV (default: the scene's outputs.depth in the image's folder)");
    cmd->add_option("--min-cos", a->min_cos, "Only samples with NoL and NoV >= C")->capture_default_str();
    cmd->add_option("--albedo", a->albedo, "Grey albedo of the target (and of the fitted model, before its free scale)")
        ->capture_default_str();
    cmd->add_option("--specular", a->specular, "Grey specular colour of the target and the fitted model")
        ->capture_default_str();
    cmd->add_option("--model-specular", a->model_specular, "Grey specular colour of the fitted model alone");
    cmd->add_option("--atlas", a->atlas, "Write the fidelity atlas (fidelity.md, data/fidelity, images/fidelity) into DOCS");
    cmd->add_flag("--no-limb-check", a->no_limb_check, "Skip the refit over NoL, NoV >= 0.05");
    cmd->add_option("--precision", a->precision, "Kernel precision mode for the search: precise or fast")
        ->capture_default_str();
    cmd->callback([a] { run_fit(*a); });
}

}  // namespace shadelab::app
