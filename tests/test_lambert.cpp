// Lambert: the kernel against the double reference over the whole sphere, and end to end on a sphere.
#include <catch2/catch.hpp>

#include <cmath>
#include <iostream>

#include "cl/runtime.hpp"
#include "mesh/mesh.hpp"
#include "models/catalogue.hpp"
#include "raster/raster.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"
#include "sweep.hpp"

using namespace shadelab;

namespace {
Runtime& runtime() {
    static Runtime rt;
    return rt;
}
}  // namespace

TEST_CASE("lambert kernel matches the double reference over the whole sphere", "[lambert][kernel]") {
    const auto sweep = test::make_sweep(120000);
    Material m;
    m.model = "lambert";
    m.albedo = {0.9, 0.5, 0.25};
    m = resolve_material(m);
    Shader shader(runtime());
    const auto out = shader.eval_directions(m, sweep.N, sweep.L, sweep.V, sweep.P);
    std::vector<glm::dvec3> ref(sweep.size());
    for (std::size_t i = 0; i < sweep.size(); ++i)
        ref[i] = ref::eval_material(sweep.dN[i], sweep.dL[i], sweep.dV[i], sweep.dP[i], m);
    const auto e = test::compare(out, ref, 1e-3);
    std::cout << "lambert: " << e.count << " triples, max abs err " << e.max_abs << ", max rel err " << e.max_rel
              << " (|ref| >= 1e-3), non-finite " << e.non_finite << "\n";
    INFO("worst triple " << e.worst << " (" << sweep.kind[e.worst] << ")");
    CHECK(e.non_finite == 0);
    CHECK(e.max_abs < 1e-6);
    CHECK(e.max_rel < 2e-6);
}

TEST_CASE("lambert is zero for light below the horizon and albedo at normal incidence", "[lambert][kernel]") {
    Material m;
    m.albedo = {0.2, 0.4, 0.6};
    m = resolve_material(m);
    Shader shader(runtime());
    // N = +z; L = +z (head-on), L = -z (behind), L at 60 deg (cos = 0.5).
    const float s60 = float(std::sqrt(3.0) / 2.0);
    std::vector<float> N = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    std::vector<float> L = {0, 0, 1, 0, 0, -1, s60, 0, 0.5f};
    std::vector<float> V = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    std::vector<float> P(9, 0.0f);
    const auto out = shader.eval_directions(m, N, L, V, P);
    CHECK(out[0] == Approx(0.2).epsilon(1e-6));
    CHECK(out[2] == Approx(0.6).epsilon(1e-6));
    CHECK(out[3] == 0.0f);
    CHECK(out[5] == 0.0f);
    CHECK(out[6] == Approx(0.1).epsilon(1e-6));
}

// End to end: a Lambert sphere under one directional light. Every covered pixel must equal
// albedo * E * max(0, N.L) for the analytic normal at that point (normalize(P) on a unit sphere). The
// mesh's interpolated normal differs from the analytic one by an angle that shrinks about 4x per
// subdivision level; the tolerance is measured per level and the trend is asserted.
TEST_CASE("lambert sphere end to end matches the closed form, error shrinks with tessellation",
          "[lambert][e2e]") {
    const glm::dvec3 albedo{0.7, 0.5, 0.3};
    const double E = 2.0;
    const glm::dvec3 Ldir = glm::normalize(glm::dvec3(0.3, 0.8, 0.5));
    Material m;
    m.albedo = albedo;
    ShadeSetup setup;
    setup.material = m;
    setup.lights = {Light{Light::Type::Directional, Ldir, {1, 1, 1}, E, 0.0}};
    Shader shader(runtime());
    double previous = 1e9;
    for (int level : {2, 3, 4, 5}) {
        const Mesh sphere = make_icosphere(level);
        Camera cam = Camera::fit(sphere.bounds(), {0.2, 0.3, 1.0}, 35.0, 1.0);
        RasterOptions ro;
        ro.width = ro.height = 256;
        const FragmentBuffer fb = rasterize(sphere, cam, ro);
        REQUIRE(fb.size() > 10000);
        setup.view = glm::dvec4(cam.eye, 1.0);
        const auto rgb = shader.shade(fb, setup);
        double max_err = 0.0;
        const std::size_t n = fb.size();
        for (std::size_t i = 0; i < n; ++i) {
            const glm::dvec3 P{fb.px[i], fb.py[i], fb.pz[i]};
            const glm::dvec3 Nexact = glm::normalize(P);
            const double expect_g = albedo.y * E * std::max(0.0, glm::dot(Nexact, Ldir));
            REQUIRE(std::isfinite(rgb[n + i]));
            max_err = std::max(max_err, std::abs(double(rgb[n + i]) - expect_g));
        }
        std::cout << "lambert sphere, icosphere level " << level << ": " << n << " pixels, max abs error "
                  << max_err << " (of peak " << albedo.y * E << ")\n";
        INFO("level " << level << " max error " << max_err << " previous " << previous);
        CHECK(max_err < previous);   // finer mesh, smaller error
        previous = max_err;
        // Bound from the interpolated-normal angle: roughly (edge angle)^2 scaled by the peak value.
        const double edge = 1.1071487 / std::pow(2.0, level);   // icosahedron edge angle / 2^level
        CHECK(max_err < albedo.y * E * edge * edge);
    }
    CHECK(previous < 2e-3 * albedo.y * E * 10);
}
