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
#include "support.hpp"

using namespace shadelab;

TEST_CASE("lambert kernel matches the double reference over the whole sphere", "[lambert][kernel]") {
    // Float rounding of NoL (~6e-8 absolute) bounds the absolute error everywhere; relative error is
    // tight only where NoL is not small (0.05: the rounding is then < 2e-6 of the value).
    std::cout << "lambert kernel vs double reference: within 2e-7 everywhere, 2e-6 relative where NoL >= 0.05\n";
    const auto e = test::check_kernel_against_reference(test::material("lambert"), [](const test::Compared& v) {
        return v.NoL() >= 0.05 ? std::min(2e-7, 2e-6 * std::abs(v.r)) : 2e-7;
    });
    test::expect_within(e, test::sweep().size());
}

TEST_CASE("lambert is zero for light below the horizon and albedo at normal incidence", "[lambert][kernel]") {
    Material m;
    m.albedo = {0.2, 0.4, 0.6};
    m = resolve_material(m);
    Shader shader(test::runtime());
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
// albedo * E * max(0, N.L) for the analytic normal: where the pixel's ray (eye through the fragment)
// meets the exact unit sphere. The mesh's interpolated normal and its flat facets both differ from that,
// by amounts that shrink about 4x per subdivision level; the bound per level is stated and the trend asserted.
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
    Shader shader(test::runtime());
    double previous = 1e9;
    for (int level : {2, 3, 4, 5, 6}) {
        const Mesh sphere = make_icosphere(level);
        Camera cam = Camera::fit(sphere.bounds(), {0.2, 0.3, 1.0}, 35.0, 1.0);
        RasterOptions ro;
        ro.width = ro.height = 256;
        const FragmentBuffer fb = rasterize(sphere, cam, ro);
        REQUIRE(fb.size() > 10000);
        setup.view = glm::dvec4(cam.eye, 1.0);
        const auto rgb = shader.shade(fb, setup);
        double max_err = 0.0, max_err_interior = 0.0;
        std::size_t compared = 0;
        const std::size_t n = fb.size();
        for (std::size_t i = 0; i < n; ++i) {
            REQUIRE(std::isfinite(rgb[n + i]));
            // Ray from the eye through the fragment, intersected with the unit sphere (nearest root).
            const glm::dvec3 P{fb.px[i], fb.py[i], fb.pz[i]};
            const glm::dvec3 d = glm::normalize(P - cam.eye);
            const double b = glm::dot(cam.eye, d), c = glm::dot(cam.eye, cam.eye) - 1.0;
            const double disc = b * b - c;
            if (disc <= 0.0) continue;   // facets lie inside the sphere, so a rim pixel's ray may miss it
            const glm::dvec3 Nexact = glm::normalize(cam.eye + (-b - std::sqrt(disc)) * d);
            const double expect_g = albedo.y * E * std::max(0.0, glm::dot(Nexact, Ldir));
            const double err = std::abs(double(rgb[n + i]) - expect_g);
            max_err = std::max(max_err, err);
            if (-glm::dot(Nexact, d) > 0.3) max_err_interior = std::max(max_err_interior, err);
            ++compared;
        }
        // Where the pixel's ray meets the flat facet and where it meets the true sphere differ by the
        // facet's sagitta (about edge^2 / 8 radially), which moves the seen point along the surface by
        // up to sagitta / tan(view angle): small facing the camera, large at the silhouette. Bounds, in
        // units of the peak value: edge^2 where the true NoV > 0.3, and 6 edge^2 everywhere (measured
        // ratios at levels 2-6: 2.1-5.4, growing as the rim's grazing pixels dominate).
        const double edge = 1.1071487 / std::pow(2.0, level);   // icosahedron edge angle / 2^level
        const double peak = albedo.y * E;
        std::cout << "lambert sphere, icosphere level " << level << ": " << compared << " of " << n
                  << " pixels, max abs error " << max_err << " (" << max_err / (peak * edge * edge)
                  << " edge^2), where NoV > 0.3: " << max_err_interior << " ("
                  << max_err_interior / (peak * edge * edge) << " edge^2)\n";
        INFO("level " << level << " max error " << max_err << " previous " << previous);
        CHECK(compared > n * 9 / 10);
        CHECK(max_err < previous);   // finer mesh, smaller error
        CHECK(max_err_interior < peak * edge * edge);
        CHECK(max_err < 6.0 * peak * edge * edge);
        previous = max_err;
    }
}
