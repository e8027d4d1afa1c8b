// The planner's catalogue search (host/plan/substitute.hpp, issue 11): each material gets its own fitted
// substitute where one is cheaper, and every chosen configuration is within the tolerance of the requested
// model's double reference - recomputed here with the test's own composition.
#include <catch2/catch.hpp>

#include <iostream>
#include <limits>

#include "color/image_compare.hpp"
#include "image/image.hpp"
#include "mesh/mesh.hpp"
#include "plan/substitute.hpp"
#include "plan/planner.hpp"
#include "raster/raster.hpp"
#include "reference/reference.hpp"
#include "support.hpp"

using namespace shadelab;

namespace {

// Two icospheres side by side, each with its own material.
PlanInput two_spheres(const Material& a, const Material& b) {
    PlanInput in;
    for (int s = 0; s < 2; ++s) {
        PlanItem it;
        it.mesh = make_icosphere(4);
        glm::dmat4 T(1.0);
        T[3] = glm::dvec4(s == 0 ? -1.1 : 1.1, 0.0, 0.0, 1.0);
        it.mesh.transform(T);
        it.material = resolve_material(s == 0 ? a : b);
        in.items.push_back(it);
    }
    Bounds bb = in.items[0].mesh.bounds();
    bb.lo = glm::min(bb.lo, in.items[1].mesh.bounds().lo);
    bb.hi = glm::max(bb.hi, in.items[1].mesh.bounds().hi);
    in.camera = Camera::fit(bb, {0.0, 0.3, 1.0}, 35.0, 2.0);
    in.width = 256;
    in.height = 128;
    in.lights = {Light{Light::Type::Directional, {0.3, 0.8, 0.6}, {1, 1, 1}, 1.0, 0.0},
                 Light{Light::Type::Point, {-3.0, 2.0, 3.0}, {0.6, 0.7, 1.0}, 12.0, 0.0}};
    in.ambient = glm::dvec3(0.02);
    return in;
}

Material mat(const std::string& model, std::map<std::string, double> params, glm::dvec3 albedo) {
    Material m;
    m.model = model;
    m.params = std::move(params);
    m.albedo = albedo;
    return m;
}

// The scene with `materials` rendered by the kernels, against the requested materials' double reference,
// composed nearest-first here; the max Delta E 2000.
double recomputed_de_max(const PlanInput& in, const std::vector<Material>& materials,
                          Precision precision = Precision::Precise) {
    const int w = in.width, h = in.height;
    Image a(w, h, 4), b(w, h, 4);
    std::vector<float> z(std::size_t(w) * h, std::numeric_limits<float>::infinity());
    Shader shader(test::runtime());
    for (std::size_t k = 0; k < in.items.size(); ++k) {
        RasterOptions ro;
        ro.width = w;
        ro.height = h;
        const FragmentBuffer fb = rasterize(in.items[k].mesh, in.camera, ro);
        ShadeSetup s;
        s.material = materials[k];
        s.lights = in.lights;
        s.ambient = in.ambient;
        s.view = glm::dvec4(in.camera.eye, 1.0);
        s.precision = precision;
        const auto kv = shader.shade(fb, s);
        const auto rv = ref::shade_fragments(fb, in.items[k].material, in.lights, in.ambient, in.camera.eye);
        const std::size_t n = fb.size();
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t p = std::size_t(fb.pixel[i]);
            if (!(fb.depth[i] < z[p])) continue;
            z[p] = fb.depth[i];
            for (int c = 0; c < 3; ++c) {
                a.pixels[p * 4 + c] = kv[std::size_t(c) * n + i];
                b.pixels[p * 4 + c] = rv[std::size_t(c) * n + i];
            }
            a.pixels[p * 4 + 3] = b.pixels[p * 4 + 3] = 1.0f;
        }
    }
    return compare_images(a, b).de_max;
}

}  // namespace

TEST_CASE("planner catalogue search: two materials get their own substitutes, each within the tolerance",
          "[plan][modelfit]") {
    // Minnaert at k = 1 is Lambert (a far cheaper kernel); Oren-Nayar sigma 0.5 is not Lambert at Delta E <= 1,
    // but its trig-free form (and other fitted cheaper models) are candidates.
    const PlanInput in = two_spheres(mat("minnaert_1941", {{"k", 1.0}}, {0.7, 0.5, 0.3}),
                                     mat("oren_nayar", {{"sigma", 0.5}}, {0.3, 0.5, 0.7}));
    PlanOptions o;
    o.tolerance = 1.0;
    const SubstitutionPlan p = plan_substitutions(test::runtime(), in, o);
    std::cout << format_substitutions(p, o);
    REQUIRE(p.items.size() == 2);
    CHECK(p.within);
    // Whether a fitted model becomes a substitute is decided by timing: it must shade its mesh 5% faster at full
    // resolution, and here a mesh shades in about 0.01 ms, mostly the launch, so that reruns came out either way
    // (Oren-Nayar kept in some; at 1024 x 512, tried instead, even Minnaert k = 1 was kept once, against Lambert).
    // What the search guarantees is checked whatever the timing said: a substitute was fitted, is
    // within the tolerance, measured at least 1 / 0.95 times faster, and (below) within the tolerance when
    // recomputed here, alone and with the other.
    for (const auto& it : p.items) {
        CHECK(it.error <= o.tolerance);
        if (it.chosen.model == it.requested.model) continue;
        CHECK(it.tried >= 1);
        CHECK(it.model_speedup > 1.0 / 0.95);
    }
    std::vector<Material> chosen;
    for (const auto& it : p.items) chosen.push_back(it.chosen);
    const double de = recomputed_de_max(in, chosen);
    CHECK(de <= o.tolerance);
    CHECK(std::abs(de - p.error) <= 0.05 + 0.05 * p.error);   // the planner's verification (at its reduced size)
    // Each substitution alone is within the tolerance too.
    for (std::size_t k = 0; k < 2; ++k) {
        std::vector<Material> one{in.items[0].material, in.items[1].material};
        one[k] = p.items[k].chosen;
        CHECK(recomputed_de_max(in, one) <= o.tolerance);
    }
}

TEST_CASE("make_plan with the catalogue: per-mesh substitutes are chosen, combined with precision, and applied",
          "[plan][modelfit]") {
    const PlanInput in = two_spheres(mat("minnaert_1941", {{"k", 1.0}}, {0.7, 0.5, 0.3}),
                                     mat("oren_nayar", {{"sigma", 0.5}}, {0.3, 0.5, 0.7}));
    PlanOptions o;
    o.tolerance = 1.0;
    o.catalogue = true;
    o.allow_per_vertex = false;   // the recomputation below shades per pixel, as the batch renderer does
    const Plan p = make_plan(test::runtime(), in, o);
    std::cout << format_plan(p, o);
    REQUIRE(p.catalogue_searched);
    REQUIRE(p.materials.size() == 2);
    // Which substitutes the search keeps, and which configuration is cheapest, are measured (the test above says
    // why that is noise at this size; a clean-clone CI run chose the requested models in fast mode, 1.31x, over
    // the substitutes, 1.35x): so the choice is checked against the planner's rule on the times it measured (the
    // cheapest within the tolerance, unless the one before it is not 5% dearer), and the chosen configuration's
    // models against the materials the plan applies.
    CHECK(p.chosen.within);
    CHECK(p.chosen.speedup >= 1.0);
    for (const auto& c : p.candidates)
        if (c.within) CHECK(c.time_ms >= 0.95 * p.chosen.time_ms);
    for (std::size_t k = 0; k < 2; ++k) {
        const std::string expected = p.chosen.config.catalogue           ? p.catalogue.items[k].chosen.model
                                     : p.chosen.config.simplify_to_lambert ? std::string("lambert")
                                                                           : in.items[k].material.model;
        CHECK(p.materials[k].model == expected);
    }
    CHECK(p.planning_ms > 0.0);
    // Every verified candidate that uses the catalogue is within the tolerance when recomputed here at full size
    // (its precision applied), not only the chosen one.
    int recomputed = 0;
    for (const auto& c : p.candidates) {
        if (!c.config.catalogue || !c.within) continue;
        const double de = recomputed_de_max(in, p.materials.size() == 2 && c.config.label() == p.chosen.config.label()
                                                    ? p.materials
                                                    : std::vector<Material>{p.catalogue.items[0].chosen,
                                                                            p.catalogue.items[1].chosen},
                                            c.config.precision);
        INFO(c.config.label() << ": planner " << c.error << ", recomputed " << de);
        CHECK(de <= o.tolerance);
        ++recomputed;
    }
    bool any_substitute = false;
    for (const auto& it : p.catalogue.items) any_substitute = any_substitute || it.chosen.model != it.requested.model;
    if (any_substitute) CHECK(recomputed >= 1);
    // Without the catalogue the old planner's choice is reachable: no catalogue candidate at all.
    PlanOptions old = o;
    old.catalogue = false;
    const Plan q = make_plan(test::runtime(), in, old);
    CHECK_FALSE(q.catalogue_searched);
    for (const auto& c : q.candidates) CHECK_FALSE(c.config.catalogue);
    CHECK(q.materials[1].model == "oren_nayar");   // Lambert is not within 1 of Oren-Nayar sigma 0.5 here
}
