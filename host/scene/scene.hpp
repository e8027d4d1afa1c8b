// Scene files: one JSON document describing a camera, meshes with their materials, lights, a background
// and the images to write. docs/batch.md is the schema (every key, its type, default and range);
// scenes/ holds one example per feature.
//
// Parsing validates everything that can be checked without loading a mesh (types, ranges, model names
// and parameters through resolve_material, unknown keys) and throws shadelab::Error with ONE line that
// names the file and the field: "scene 'scenes/x.json': meshes[0].material.albedo: expected 3 numbers".
#pragma once
#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "mesh/mesh.hpp"
#include "models/material.hpp"
#include "raster/camera.hpp"
#include "shade/shader.hpp"

namespace shadelab {

struct SceneCamera {
    // true: framed on the bounds of all (transformed) meshes, looking from `view_from`;
    // false: placed at `position`, looking at `target` (default: the centre of the bounds).
    bool fit = true;
    glm::dvec3 view_from{0.0, 0.25, 1.0};
    glm::dvec3 position{0.0, 0.0, 3.0};
    glm::dvec3 target{0.0};
    bool has_target = false;
    glm::dvec3 up{0.0, 1.0, 0.0};
    double fov_deg = 35.0;       // vertical, degrees
};

struct SceneMesh {
    std::string path;            // as resolved: relative to the scene file's folder, usable from the cwd
    std::string path_written;    // as written in the scene (for messages)
    glm::dmat4 transform{1.0};   // object -> world
    Material material;           // resolved (defaults filled, ranges checked)
    bool cull_backfaces = false;
};

// Output paths as resolved against the batch's output folder (empty = not written).
struct SceneOutputs {
    std::string png;             // 8-bit sRGB colour (+ coverage alpha)
    std::string exr;             // linear float colour (+ coverage alpha)
    std::string depth;           // linear float, one channel: view-space depth, 0 where no surface
    std::string normal;          // linear float RGBA: world-space normal xyz, alpha = coverage
    std::vector<std::string> all() const;
};

struct Scene {
    std::string file;            // the scene file as given
    std::string name;            // job name, used for {name} in output paths
    SceneCamera camera;
    int width = 512, height = 512;
    std::vector<SceneMesh> meshes;
    std::vector<Light> lights;
    glm::dvec3 ambient{0.0};
    glm::dvec4 background{0.0, 0.0, 0.0, 0.0};
    Precision precision = Precision::Precise;
    bool per_vertex = false;     // shade the vertices and interpolate (Gouraud), as `render --per-vertex`
    SceneOutputs outputs;
    std::vector<std::string> warnings;   // things worth telling the user that are not errors
};

struct SceneLoadOptions {
    std::string out_dir = "out";         // relative output paths are taken relative to this folder
    // Template mode: replaces the path of the scene's single mesh entry (the template may omit "path").
    // Relative to the current directory, as given on the command line.
    std::string mesh_override;
};

// Reads and validates a scene file. Throws shadelab::Error "scene '<file>': <field>: <what>".
Scene load_scene(const std::string& file, const SceneLoadOptions& options = {});

// The same from an already-parsed document; `file` is used for messages and to resolve mesh paths.
Scene parse_scene(const nlohmann::json& doc, const std::string& file, const SceneLoadOptions& options = {});

// The scene's meshes loaded (by `loader`, e.g. a cache) and moved to world space, their joint bounds,
// and the camera the scene asks for. Throws shadelab::Error "scene '<file>': meshes[i] '<path>': ...".
struct SceneGeometry {
    std::vector<Mesh> meshes;
    Bounds bounds;
    Camera camera;
    std::size_t triangles = 0;
};
SceneGeometry load_scene_geometry(const Scene& s, const std::function<Mesh(const std::string&)>& loader);

// The planner's view of a scene: its world meshes, materials, camera, size, lights and ambient.
// (Declared here, defined in host/plan/scene_plan.cpp, so scene parsing does not depend on the planner.)
struct PlanInput;
PlanInput plan_input_for(const Scene& s, const SceneGeometry& geometry);

// The camera of a scene over the given bounds (framed on them, or placed as the scene says).
Camera scene_camera(const Scene& s, const Bounds& b);

// The keys every object of the schema accepts (for docs and the unknown-key message).
const std::vector<std::string>& scene_keys(const std::string& object);   // "scene", "camera", "mesh", ...

}  // namespace shadelab
