// A scene as the planner sees it (shared by `shadelab plan`, `batch --tolerance` and the tests).
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

}  // namespace shadelab
