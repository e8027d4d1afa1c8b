// A scene as the planner sees it (shared by `shadelab plan`, `batch --tolerance` and the tests).
#include "plan/plan_job.hpp"
#include "plan/planner.hpp"
#include "scene/scene.hpp"

namespace shadelab {

PlanInput plan_input_for(const Scene& s, const SceneGeometry& g) {
    PlanInput in;
    in.camera = g.camera;
    in.width = s.width;
    in.height = s.height;
    for (std::size_t i = 0; i < g.meshes.size(); ++i)
        in.items.push_back(PlanItem{g.meshes[i], s.meshes[i].material, s.meshes[i].cull_backfaces, -1, glm::dmat4(1.0)});
    in.lights = s.lights;
    in.ambient = s.ambient;
    return in;
}

Plan plan_job(Runtime& runtime, pipeline::Job& job, PlanOptions options, pipeline::StageTimes& times) {
    PlanInput pin;
    pin.camera = job.camera;
    pin.width = job.width;
    pin.height = job.height;
    for (const auto& m : job.meshes) pin.items.push_back(PlanItem{m.mesh, m.material, m.cull_backfaces, -1, glm::dmat4(1.0)});
    pin.lights = job.lights;
    pin.ambient = job.ambient;
    Plan plan = make_plan(runtime, pin, options);
    for (std::size_t i = 0; i < job.meshes.size(); ++i) job.meshes[i].material = plan.materials[i];
    job.lights = plan.kept_lights;
    job.precision = plan.chosen.config.precision;
    job.per_vertex = plan.chosen.config.per_vertex;
    times.plan_ms += plan.planning_ms;
    return plan;
}

}  // namespace shadelab
