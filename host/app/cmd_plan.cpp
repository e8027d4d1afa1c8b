// shadelab plan: the cheapest configuration of a scene within a stated error (docs/planner.md).
#include <fstream>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "plan/planner.hpp"
#include "scene/scene.hpp"

namespace shadelab::app {

void add_plan_command(CLI::App& app) {
    struct Args {
        std::string scene;
        double tolerance = 1.0;
        std::string metric = "de2000";
        int verify_pixels = 256 * 256;
        std::string json;
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
        Runtime rt;
        const Plan p = make_plan(rt, in, o);
        std::cout << "scene " << a->scene << ": " << s.width << "x" << s.height << ", " << geo.meshes.size() << " mesh(es), "
                  << s.lights.size() << " light(s)\n"
                  << format_plan(p, o);
        if (!a->json.empty()) {
            nlohmann::json j;
            j["scene"] = a->scene;
            j["tolerance"] = o.tolerance;
            j["metric"] = a->metric;
            j["verify"] = {p.verify_width, p.verify_height};
            j["dropped_lights"] = p.dropped_lights;
            j["chosen"] = p.chosen.config.label();
            for (const auto& c : p.candidates)
                j["candidates"].push_back({{"config", c.config.label()}, {"de2000_max", c.de_max}, {"de2000_p99", c.de_p99},
                                           {"relative_max", c.rel_max}, {"time_ms", c.time_ms}, {"speedup", c.speedup},
                                           {"within", c.within}});
            write_text_atomically(a->json, "report", j.dump(2) + "\n");
        }
    });
}

}  // namespace shadelab::app
