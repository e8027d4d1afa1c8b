// Scene files: every example loads; every schema error names the file and the field; parsed values.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"
#include "models/catalogue.hpp"
#include "scene/scene.hpp"
#include "support.hpp"

using namespace shadelab;
namespace fs = std::filesystem;

namespace {

// A private folder for the scene files these tests write, removed when the test process ends.
const fs::path& scratch() {
    static const fs::path dir = test::scratch_dir("scene");
    return dir;
}

std::string write_scene(const std::string& name, const std::string& text) {
    const fs::path p = scratch() / name;
    std::ofstream(p) << text;
    return p.string();
}

// A valid scene around one mesh entry, with `mesh_extra` spliced into the mesh object and `top_extra`
// into the top level, so each error case changes one thing.
std::string scene_text(const std::string& mesh_extra = "", const std::string& top_extra = "") {
    return "{ \"meshes\": [ { \"path\": \"" + test::kData + "/scene_quad.obj\"" + mesh_extra + " } ]" + top_extra + " }";
}

std::string error_of(const std::string& file, const SceneLoadOptions& opt = {}) {
    try {
        load_scene(file, opt);
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}
}  // namespace

TEST_CASE("every example scene in scenes/ loads and validates", "[scene]") {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(test::kScenes)) {
        if (e.path().extension() != ".json") continue;
        INFO(e.path().string());
        Scene s;
        REQUIRE_NOTHROW(s = load_scene(e.path().string()));
        CHECK(!s.meshes.empty());
        CHECK(!s.outputs.all().empty());
        for (const auto& m : s.meshes) CHECK(fs::exists(m.path));
        for (const auto& w : s.warnings) std::cout << e.path().filename().string() << ": warning: " << w << "\n";
        ++n;
    }
    CHECK(n >= 6);
    // Templates take their mesh from the command line.
    for (const auto& e : fs::directory_iterator(test::kScenes + "/templates")) {
        INFO(e.path().string());
        SceneLoadOptions opt;
        opt.mesh_override = test::kMeshes + "/teapot.obj";
        Scene s;
        REQUIRE_NOTHROW(s = load_scene(e.path().string(), opt));
        CHECK(s.name == "teapot");
        CHECK(s.meshes.size() == 1);
        CHECK(s.meshes[0].path == opt.mesh_override);
        ++n;
    }
}

TEST_CASE("schema errors name the file and the field", "[scene]") {
    struct Case {
        const char* what;
        std::string text;
        std::vector<std::string> expect;   // substrings of the message besides the file name
    };
    const std::vector<Case> cases{
        {"wrong type", scene_text("", ", \"camera\": { \"fov\": \"wide\" }"), {"camera.fov", "expected a number", "string"}},
        {"fov out of range", scene_text("", ", \"camera\": { \"fov\": 200 }"), {"camera.fov", "allowed [1, 170]"}},
        {"unknown model", scene_text(", \"material\": { \"model\": \"no_such_model\" }"),
         {"meshes[0].material", "unknown model 'no_such_model'", "lambert"}},
        {"out-of-range parameter", scene_text(", \"material\": { \"model\": \"oren_nayar\", \"params\": { \"sigma\": 3 } }"),
         {"meshes[0].material", "parameter 'sigma'", "allowed range is [0, 1.5708]"}},
        {"unknown parameter", scene_text(", \"material\": { \"model\": \"lambert\", \"params\": { \"k\": 1 } }"),
         {"meshes[0].material", "has no parameter 'k'"}},
        {"missing mesh", "{ \"meshes\": [ { \"path\": \"no_such_mesh.obj\" } ] }",
         {"meshes[0].path", "'no_such_mesh.obj' not found", "relative to the scene file's folder"}},
        {"no meshes", "{ \"lights\": [] }", {"meshes", "missing"}},
        {"unknown key", scene_text(", \"material\": { \"albdo\": [1, 1, 1] }"),
         {"meshes[0].material.albdo", "unknown key", "did you mean 'albedo'"}},
        {"unknown top-level key", scene_text("", ", \"resolutoin\": [4, 4]"), {"resolutoin", "did you mean 'resolution'"}},
        {"albedo shape", scene_text(", \"material\": { \"albedo\": [1, 1] }"), {"meshes[0].material.albedo", "3 numbers"}},
        {"negative albedo", scene_text(", \"material\": { \"albedo\": [1, -1, 1] }"), {"meshes[0].material.albedo[1]", "out of range"}},
        {"resolution", scene_text("", ", \"resolution\": [0, 10]"), {"resolution[0]", "allowed [1, 16384]"}},
        {"fractional resolution", scene_text("", ", \"resolution\": [10.5, 10]"), {"resolution[0]", "whole number"}},
        {"light type", scene_text("", ", \"lights\": [ { \"type\": \"spot\" } ]"), {"lights[0].type", "'spot'"}},
        {"light without direction", scene_text("", ", \"lights\": [ { \"type\": \"directional\" } ]"), {"lights[0]", "direction"}},
        {"zero direction", scene_text("", ", \"lights\": [ { \"type\": \"directional\", \"direction\": [0, 0, 0] } ]"),
         {"lights[0].direction", "zero vector"}},
        {"negative intensity", scene_text("", ", \"lights\": [ { \"type\": \"point\", \"position\": [0, 0, 1], \"intensity\": -1 } ]"),
         {"lights[0].intensity", "out of range"}},
        {"range on a directional light", scene_text("", ", \"lights\": [ { \"type\": \"directional\", \"direction\": [0, 0, 1], \"range\": 3 } ]"),
         {"lights[0].range", "only point lights"}},
        {"output extension", scene_text("", ", \"outputs\": { \"png\": \"x.exr\" }"), {"outputs.png", "not an 8-bit sRGB format"}},
        {"unsupported extension", scene_text("", ", \"outputs\": { \"exr\": \"x.doc\" }"), {"outputs.exr", "unsupported extension"}},
        {"unknown placeholder", scene_text("", ", \"outputs\": { \"png\": \"{date}.png\" }"), {"outputs.png", "'{date}'"}},
        {"same file twice", scene_text("", ", \"outputs\": { \"exr\": \"a.exr\", \"depth\": \"a.exr\" }"), {"already written"}},
        {"unknown material name", scene_text(", \"material\": \"gold\""), {"meshes[0].material", "no material named 'gold'"}},
        {"bad library entry", scene_text("", ", \"materials\": { \"m\": { \"model\": \"phong\", \"params\": { \"n\": -3 } } }"),
         {"materials.m", "parameter 'n'"}},
        {"matrix and translate", scene_text(", \"transform\": { \"matrix\": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], \"translate\": [1, 0, 0] }"),
         {"meshes[0].transform.translate", "cannot be combined"}},
        {"singular matrix", scene_text(", \"transform\": { \"matrix\": [1,0,0,0, 0,0,0,0, 0,0,1,0, 0,0,0,1] }"),
         {"meshes[0].transform.matrix", "singular"}},
        {"zero scale", scene_text(", \"transform\": { \"scale\": [1, 0, 1] }"), {"meshes[0].transform.scale", "zero scale"}},
        {"fit and position", scene_text("", ", \"camera\": { \"fit\": true, \"position\": [0, 0, 3] }"), {"camera", "fit"}},
        {"precision", scene_text("", ", \"precision\": \"sloppy\""), {"precision", "'sloppy'"}},
        {"background alpha", scene_text("", ", \"background\": [0, 0, 0, 2]"), {"background[3]", "[0, 1]"}},
        {"not an object", "[1, 2, 3]", {"expected an object"}},
        {"invalid JSON", "{ \"meshes\": [ { \"path\": \"a.obj\" } ,, ] }", {"not valid JSON", "line 1"}},
    };
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const std::string file = write_scene("error_" + std::to_string(i) + ".json", cases[i].text);
        const std::string msg = error_of(file);
        INFO(cases[i].what << ": " << msg);
        CHECK(msg.find("scene '" + file + "': ") == 0);
        for (const auto& e : cases[i].expect) CHECK(msg.find(e) != std::string::npos);
        CHECK(msg.find('\n') == std::string::npos);   // one line
    }
    const std::string missing = (scratch() / "no_such_scene.json").string();
    CHECK(error_of(missing) == "scene '" + missing + "': file not found");
}

TEST_CASE("keys starting with an underscore are comments - JSON comments are allowed", "[scene]") {
    const std::string file = write_scene(
        "comments.json", "// a comment line\n{ \"_comment\": \"free text\", \"meshes\": [ { \"_note\": 1, \"path\": \"" +
                             test::kData + "/scene_quad.obj\" } ], \"outputs\": { \"_why\": \"x\", \"png\": \"a.png\" } }");
    Scene s;
    REQUIRE_NOTHROW(s = load_scene(file));
    CHECK(s.outputs.png == (fs::path("out") / "a.png").string());
}

TEST_CASE("parsed values: defaults, transform order, lights, outputs, names", "[scene]") {
    const std::string file = write_scene(
        "values.json",
        "{ \"meshes\": [ { \"path\": \"" + test::kData + "/scene_quad.obj\", "
        "\"transform\": { \"translate\": [1, 2, 3], \"rotate\": [0, 90, 0], \"scale\": 2 } } ], "
        "\"lights\": [ { \"type\": \"point\", \"position\": [0, 1, 0], \"color\": [0.5, 0.25, 1], \"intensity\": 4, \"range\": 10 } ], "
        "\"background\": [0.1, 0.2, 0.3], "
        "\"outputs\": { \"png\": \"{name}/{scene}-{mesh}.png\", \"depth\": \"/abs/d.exr\" } }");
    SceneLoadOptions opt;
    opt.out_dir = "results";
    const Scene s = load_scene(file, opt);
    CHECK(s.name == "values");
    CHECK(s.width == 512);
    CHECK(s.height == 512);
    CHECK(s.camera.fit);
    CHECK(s.meshes[0].material.model == "lambert");
    CHECK(s.meshes[0].material.albedo == glm::dvec3(0.8));
    // scale, then rotate 90 degrees about y (x -> -z), then translate: (1, 0, 0) -> (2, 0, 0) -> (0, 0, -2) -> (1, 2, 1)
    const glm::dvec4 p = s.meshes[0].transform * glm::dvec4(1, 0, 0, 1);
    CHECK(p.x == Approx(1.0).margin(1e-12));
    CHECK(p.y == Approx(2.0).margin(1e-12));
    CHECK(p.z == Approx(1.0).margin(1e-12));
    REQUIRE(s.lights.size() == 1);
    CHECK(s.lights[0].type == Light::Type::Point);
    CHECK(s.lights[0].colour == glm::dvec3(0.5, 0.25, 1));
    CHECK(s.lights[0].intensity == 4);
    CHECK(s.lights[0].range == 10);
    CHECK(s.background == glm::dvec4(0.1, 0.2, 0.3, 1.0));   // three numbers: opaque
    CHECK(s.outputs.png == (fs::path("results") / "values" / "values-scene_quad.png").string());
    CHECK(s.outputs.depth == "/abs/d.exr");
    CHECK(s.outputs.exr.empty());

    // No "lights" key: one white directional light from (1, 1, 1); "lights": [] means none (and a warning).
    const Scene d = load_scene(write_scene("default_light.json", scene_text()));
    REQUIRE(d.lights.size() == 1);
    CHECK(d.lights[0].type == Light::Type::Directional);
    CHECK(d.background == glm::dvec4(0.0));
    const Scene dark = load_scene(write_scene("no_light.json", scene_text("", ", \"lights\": []")));
    CHECK(dark.lights.empty());
    CHECK(dark.warnings.size() == 1);

    // A 4x4 matrix written row by row (translation in the last column).
    const Scene m = load_scene(write_scene(
        "matrix.json", scene_text(", \"transform\": { \"matrix\": [[1,0,0,5],[0,1,0,6],[0,0,1,7],[0,0,0,1]] }")));
    const glm::dvec4 q = m.meshes[0].transform * glm::dvec4(0, 0, 0, 1);
    CHECK(q == glm::dvec4(5, 6, 7, 1));
}

TEST_CASE("materials: library names, children checked by the catalogue, unused entries warned", "[scene]") {
    const std::string file = write_scene(
        "library.json", scene_text(", \"material\": \"shiny\"",
                                   ", \"materials\": { \"shiny\": { \"model\": \"phong\", \"params\": { \"n\": 10 }, "
                                   "\"specular\": [0.5, 0.5, 0.5] }, \"spare\": { \"model\": \"lambert\" } }"));
    const Scene s = load_scene(file);
    CHECK(s.meshes[0].material.model == "phong");
    CHECK(s.meshes[0].material.params.at("n") == 10);
    CHECK(s.meshes[0].material.params.size() == find_model("phong").params.size());   // defaults filled
    CHECK(s.meshes[0].material.specular == glm::dvec3(0.5));
    REQUIRE(s.warnings.size() == 1);
    CHECK(s.warnings[0].find("materials.spare") != std::string::npos);

    // Children on a model that blends none: the catalogue's child-count check, with the field path.
    const std::string bad = write_scene(
        "children.json", scene_text(", \"material\": { \"model\": \"lambert\", \"children\": [ { \"model\": \"lambert\" } ] }"));
    const std::string msg = error_of(bad);
    INFO(msg);
    CHECK(msg.find("meshes[0].material") != std::string::npos);
    CHECK(msg.find("blends 0 other models but 1 were given") != std::string::npos);

    // A cycle of names stops with a message instead of recursing forever.
    const std::string cyc = write_scene(
        "cycle.json", scene_text(", \"material\": \"a\"", ", \"materials\": { \"a\": { \"model\": \"lambert\", "
                                                          "\"children\": [\"a\"] } }"));
    CHECK(error_of(cyc).find("too deeply") != std::string::npos);

    // Models that blend two others (gradient), if the catalogue has one.
    for (const auto& info : model_catalogue()) {
        if (info.children != 2) continue;
        const std::string g = write_scene(
            "blend.json", scene_text(", \"material\": { \"model\": \"" + info.name +
                                     "\", \"children\": [ { \"model\": \"lambert\" }, \"spare\" ] }",
                                     ", \"materials\": { \"spare\": { \"model\": \"lambert\", \"albedo\": [0.1, 0.2, 0.3] } }"));
        const Scene b = load_scene(g);
        REQUIRE(b.meshes[0].material.children.size() == 2);
        CHECK(b.meshes[0].material.children[1].albedo == glm::dvec3(0.1, 0.2, 0.3));
        const std::string one = write_scene(
            "blend1.json", scene_text(", \"material\": { \"model\": \"" + info.name + "\", \"children\": [ { \"model\": \"lambert\" } ] }"));
        CHECK(error_of(one).find("blends 2 other models but 1 were given") != std::string::npos);
        break;
    }
}

TEST_CASE("template mode replaces the single mesh and names the job after it", "[scene]") {
    const std::string tmpl = write_scene("tmpl.json", "{ \"meshes\": [ { \"material\": { \"model\": \"lambert\" } } ], "
                                                      "\"outputs\": { \"png\": \"t/{mesh}.png\" } }");
    SceneLoadOptions opt;
    opt.mesh_override = test::kMeshes + "/suzanne.obj";
    const Scene s = load_scene(tmpl, opt);
    CHECK(s.name == "suzanne");
    CHECK(s.outputs.png == (fs::path("out") / "t" / "suzanne.png").string());
    // Two mesh entries cannot be a template.
    const std::string two = write_scene("tmpl2.json", "{ \"meshes\": [ {}, {} ] }");
    CHECK(error_of(two, opt).find("exactly one mesh entry") != std::string::npos);
    // Without the override, a template has no path: a clear message.
    CHECK(error_of(tmpl).find("meshes[0]: missing \"path\"") != std::string::npos);
}
