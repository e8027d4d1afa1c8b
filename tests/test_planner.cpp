// The planner: on scenes built to have a known answer it picks the cheaper equivalent, and the result
// matches the reference; where nothing cheaper is within tolerance it keeps what was asked.
#include <catch2/catch.hpp>

#include <iostream>

#include <filesystem>

#include "plan/planner.hpp"
#include "color/image_compare.hpp"
#include "image/image.hpp"
#include "scene/batch.hpp"
#include "scene/scene.hpp"
#include "support.hpp"

#include <unistd.h>

using namespace shadelab;

namespace {
PlanInput sphere_scene(const Material& m, int level = 4, int size = 128) {
    PlanInput in;
    PlanItem it;
    it.mesh = make_icosphere(level);
    it.material = m;
    in.items.push_back(it);
    in.camera = Camera::fit(it.mesh.bounds(), {0.2, 0.3, 1.0}, 35.0, 1.0);
    in.width = in.height = size;
    in.lights = {Light{Light::Type::Directional, {0.3, 0.8, 0.6}, {1, 1, 1}, 1.0, 0.0}};
    return in;
}

Material mat(const std::string& model, std::map<std::string, double> params = {}) {
    Material m;
    m.model = model;
    m.params = std::move(params);
    m.albedo = {0.7, 0.5, 0.3};
    return m;
}

void print(const char* what, const Plan& p, const PlanOptions& o) { std::cout << "== " << what << "\n" << format_plan(p, o); }
}  // namespace

TEST_CASE("planner: Oren-Nayar with sigma 0 and Minnaert at its Lambert k become Lambert, exactly", "[plan]") {
    PlanOptions o;
    o.tolerance = 0.5;
    for (const Material& m : {mat("oren_nayar", {{"sigma", 0.0}}), mat("minnaert_1941", {{"k", 1.0}}),
                              mat("phong", {{"ks", 0.0}})}) {
        const Plan p = make_plan(test::runtime(), sphere_scene(m), o);
        print(m.model.c_str(), p, o);
        INFO(m.model << ": chosen " << p.chosen.config.label());
        // The Lambert configuration is an exact equivalent here: its error is float rounding only.
        bool found = false;
        for (const auto& c : p.candidates)
            if (c.config.simplify_to_lambert && c.config.precision == Precision::Precise && !c.config.per_vertex) {
                found = true;
                CHECK(c.de_max < 1e-3);
                CHECK(c.within);
            }
        CHECK(found);
        CHECK(p.chosen.within);
        CHECK(p.chosen.error <= o.tolerance);
    }
}

TEST_CASE("planner: a light behind every surface is compiled out", "[plan]") {
    // A quad facing +z, lit by a directional light from -z (never above its horizon for Lambert).
    PlanInput in;
    PlanItem it;
    it.mesh = make_quad();
    it.material = mat("lambert");
    in.items.push_back(it);
    in.camera.eye = {0.1, 0.2, 3.0};
    in.width = in.height = 64;
    in.lights = {Light{Light::Type::Directional, {0.2, 0.1, 1.0}, {1, 1, 1}, 1.0, 0.0},
                 Light{Light::Type::Directional, {0.0, 0.3, -1.0}, {1, 0, 0}, 5.0, 0.0}};
    PlanOptions o;
    const Plan p = make_plan(test::runtime(), in, o);
    print("light behind", p, o);
    REQUIRE(p.dropped_lights.size() == 1);
    CHECK(p.dropped_lights[0].find("light 2") != std::string::npos);
    CHECK(p.kept_lights.size() == 1);
    CHECK(p.requested.de_max < 1e-3);   // dropping it changed nothing: the reference has both lights

    // For Half-Lambert the same light does reach the surface (wrap lighting): it must be kept.
    in.items[0].material = mat("half_lambert");
    const Plan q = make_plan(test::runtime(), in, o);
    CHECK(q.dropped_lights.empty());
}

TEST_CASE("planner: where nothing cheaper is within tolerance it keeps the requested configuration", "[plan]") {
    // A rough Oren-Nayar sphere with a tolerance far below what Lambert or Gouraud can reach.
    PlanOptions o;
    o.tolerance = 0.05;
    const Plan p = make_plan(test::runtime(), sphere_scene(mat("oren_nayar", {{"sigma", 1.2}})), o);
    print("rough oren-nayar, tight tolerance", p, o);
    CHECK_FALSE(p.chosen.config.simplify_to_lambert);
    CHECK_FALSE(p.chosen.config.per_vertex);
    CHECK(p.chosen.within);
    for (const auto& c : p.candidates)
        if (c.config.simplify_to_lambert) CHECK_FALSE(c.within);   // Lambert is visibly different here
}

TEST_CASE("planner: verification at reduced size is stated - speed-ups are measured", "[plan]") {
    PlanOptions o;
    o.verify_pixels = 64 * 64;
    const Plan p = make_plan(test::runtime(), sphere_scene(mat("oren_nayar", {{"sigma", 0.0}}), 3, 160), o);
    CHECK(p.verify_width == 64);
    bool stated = false;
    for (const auto& n : p.notes) stated = stated || n.find("reduced from 160x160") != std::string::npos;
    CHECK(stated);
    for (const auto& c : p.candidates) {
        CHECK(c.time_ms > 0.0);
        CHECK(std::isfinite(c.speedup));
    }
    CHECK(p.chosen.speedup >= 1.0);
}

TEST_CASE("planner: coarser icosphere levels are tried for analytic spheres", "[plan]") {
    PlanInput in = sphere_scene(mat("lambert"), 5, 96);
    in.items[0].icosphere_level = 5;
    PlanOptions o;
    o.tolerance = 1000.0;   // anything goes: the cheapest measured configuration must win
    const Plan p = make_plan(test::runtime(), in, o);
    print("icosphere levels", p, o);
    bool tried_lower = false;
    for (const auto& c : p.candidates) tried_lower = tried_lower || (c.config.icosphere_level >= 0 && c.config.icosphere_level < 5);
    CHECK(tried_lower);
    for (const auto& c : p.candidates) CHECK(p.chosen.time_ms <= c.time_ms / 0.95 + 1e-9);
}

TEST_CASE("planner: on every bundled scene the chosen plan's measured error is within tolerance", "[plan][scene]") {
    namespace fs = std::filesystem;
    std::size_t scenes = 0;
    for (const auto& e : fs::directory_iterator(test::kScenes)) {
        if (e.path().extension() != ".json") continue;
        const Scene s = load_scene(e.path().string());
        const SceneGeometry geo = load_scene_geometry(s, [](const std::string& p) { return load_mesh(p); });
        const PlanInput in = plan_input_for(s, geo);
        PlanOptions o;
        o.tolerance = 1.0;
        o.verify_pixels = 128 * 128;
        o.timing_repeats = 1;
        const Plan p = make_plan(test::runtime(), in, o);
        INFO(e.path().string() << ": chosen " << p.chosen.config.label() << ", error " << p.chosen.error);
        CHECK(p.chosen.within);
        CHECK(p.chosen.error <= o.tolerance);
        CHECK(p.requested.error < 1e-2);   // the requested configuration is the float kernel itself
        CHECK(std::isfinite(p.chosen.speedup));
        CHECK(p.chosen.speedup >= 1.0);
        ++scenes;
    }
    CHECK(scenes >= 5);
}

TEST_CASE("batch --tolerance plans each job and shades with the choice, within tolerance of the plain render",
          "[plan][batch]") {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("shadelab-test-plan-batch-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    std::ostringstream log;
    BatchOptions o;
    o.scenes = {test::kScenes + "/lights.json"};
    o.progress = ProgressStyle::Quiet;
    o.log = &log;
    o.out_dir = (dir / "plain").string();
    const BatchSummary plain = run_batch(o, test::runtime());
    REQUIRE(plain.failed == 0);
    o.out_dir = (dir / "planned").string();
    o.tolerance = 1.0;
    const BatchSummary planned = run_batch(o, test::runtime());
    REQUIRE(planned.failed == 0);
    REQUIRE(planned.jobs.size() == 1);
    bool noted = false;
    for (const auto& w : planned.jobs[0].warnings) noted = noted || w.rfind("plan: ", 0) == 0;
    CHECK(noted);
    std::size_t compared = 0;
    for (const auto& out : planned.jobs[0].outputs) {
        const std::string ext = fs::path(out).extension().string();
        if (ext != ".exr" && ext != ".png") continue;
        ++compared;
        const fs::path rel = fs::relative(out, dir / "planned");
        const ImageDiff d = compare_images(read_image(out), read_image((dir / "plain" / rel).string()));
        INFO(out << ": max Delta E 2000 against the plain render " << d.de_max);
        // The plain render is within float rounding of the reference; 8-bit PNG rounding can add up to
        // about half a code value on each side.
        CHECK(d.de_max <= (ext == ".png" ? 1.6 : 1.0 + 1e-3));
    }
    CHECK(compared > 0);
    fs::remove_all(dir);
}
