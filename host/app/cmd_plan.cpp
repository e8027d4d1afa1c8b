// shadelab plan: the cheapest configuration of a scene within a stated error (docs/planner.md).
#include <fstream>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "plan/planner.hpp"
#include "plan/substitute.hpp"
#include "scene/scene.hpp"

namespace shadelab::app {

void add_plan_command(CLI::App& app) {
    struct Args {
        std::string scene;
        double tolerance = 1.0;
        std::string metric = "de2000";
        int verify_pixels = 256 * 256;
        std::string json;
        bool catalogue = false;      // accepted for scripts written when the search was opt-in
        bool no_catalogue = false;
    };
    auto a = std::make_shared<Args>();
    auto* cmd = app.add_subcommand("plan", "Find the cheapest configuration of a scene whose image stays within a tolerance");
    cmd->add_option("scene", a->scene, "Scene file (.json, docs/batch.md)")->required();
    cmd->add_option("--tolerance", a->tolerance, "Accepted error: max Delta E 2000, or max relative error with --metric relative")
        ->capture_default_str();
    cmd->add_option("--metric", a->metric, "de2000 or relative")->capture_default_str();
    cmd->add_option("--verify-pixels", a->verify_pixels, "Verification renders are reduced to about this many pixels")
        ->capture_default_str();
    cmd->add_option("--json", a->json, "Also write every candidate's figures as JSON here");
    auto* with = cmd->add_flag("--catalogue", a->catalogue,
                               "Search the catalogue per material (the default; kept for older scripts): cheaper models "
                               "fitted to each material on its own fragments, each verified against the double reference");
    cmd->add_flag("--no-catalogue", a->no_catalogue,
                  "Only the requested model or Lambert, the same for every mesh (the planner before issue 11)")
        ->excludes(with);
    cmd->callback([a] {
        const Scene s = load_scene(a->scene);
        const SceneGeometry geo = load_scene_geometry(s, [](const std::string& p) { return load_mesh(p); });
        const PlanInput in = plan_input_for(s, geo);
        PlanOptions o;
        o.tolerance = a->tolerance;
        if (a->metric == "relative") o.metric = PlanMetric::Relative;
        else if (a->metric != "de2000") throw Error("--metric must be 'de2000' or 'relative', got '" + a->metric + "'");
        if (a->verify_pixels < 64) throw Error("--verify-pixels must be at least 64");
        o.verify_pixels = a->verify_pixels;
        o.catalogue = !a->no_catalogue;
        Runtime rt;
        const Plan p = make_plan(rt, in, o);
        std::cout << "scene " << a->scene << ": " << s.width << "x" << s.height << ", " << geo.meshes.size() << " mesh(es), "
                  << s.lights.size() << " light(s)\n"
                  << format_plan(p, o);
        const SubstitutionPlan& sp = p.catalogue;
        if (!a->json.empty()) {
            nlohmann::json j;
            j["scene"] = a->scene;
            j["tolerance"] = o.tolerance;
            j["metric"] = a->metric;
            j["verify"] = {p.verify_width, p.verify_height};
            j["dropped_lights"] = p.dropped_lights;
            j["chosen"] = p.chosen.config.label();
            j["planning_ms"] = p.planning_ms;
            for (std::size_t k = 0; k < p.materials.size(); ++k) {
                nlohmann::json params = nlohmann::json::object();
                for (const auto& [name, v] : p.materials[k].params) params[name] = v;
                j["materials"].push_back({{"mesh", k + 1}, {"requested", in.items[k].material.model},
                                          {"model", p.materials[k].model}, {"params", params},
                                          {"albedo", {p.materials[k].albedo.x, p.materials[k].albedo.y, p.materials[k].albedo.z}}});
            }
            for (const auto& c : p.candidates)
                j["candidates"].push_back({{"config", c.config.label()}, {"de2000_max", c.de_max}, {"de2000_p99", c.de_p99},
                                           {"relative_max", c.rel_max}, {"time_ms", c.time_ms}, {"speedup", c.speedup},
                                           {"within", c.within}});
            if (p.catalogue_searched) {
                for (const auto& it : sp.items) {
                    nlohmann::json params = nlohmann::json::object();
                    for (const auto& [k, v] : it.chosen.params) params[k] = v;
                    j["substitutions"].push_back({{"mesh", it.item + 1}, {"requested", it.requested.model},
                                                  {"chosen", it.chosen.model}, {"params", params},
                                                  {"albedo", {it.chosen.albedo.x, it.chosen.albedo.y, it.chosen.albedo.z}},
                                                  {"error", it.error}, {"fit_rel_rms", it.fit_rel_rms},
                                                  {"model_speedup", it.model_speedup}});
                }
                j["catalogue"] = {{"error", sp.error}, {"within", sp.within}, {"speedup", sp.speedup},
                                  {"requested_ms", sp.requested_ms}, {"chosen_ms", sp.chosen_ms},
                                  {"planning_ms", sp.planning_ms}};
            }
            write_text_atomically(a->json, "report", j.dump(2) + "\n");
        }
    });
}

}  // namespace shadelab::app
