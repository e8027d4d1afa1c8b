// Per-vertex (Gouraud) evaluation: the barycentrics are right, and the error against per-pixel shading
// shrinks with tessellation.
#include <catch2/catch.hpp>

#include <cmath>
#include <iostream>

#include "mesh/mesh.hpp"
#include "raster/raster.hpp"
#include "shade/gouraud.hpp"
#include "support.hpp"

using namespace shadelab;

TEST_CASE("rasteriser barycentrics reproduce any per-vertex linear field exactly", "[gouraud][raster]") {
    // A vertex value linear in world position, interpolated with the fragment's barycentrics, must give
    // the same linear function of the fragment's position (perspective-correct, through clipping too).
    const Mesh sphere = make_icosphere(3);
    Camera cam = Camera::fit(sphere.bounds(), {0.3, 0.4, 1.0}, 40.0, 1.0);
    cam.eye = glm::dvec3(0.3, 0.2, 1.05);   // close enough that the near plane cuts the sphere,
    cam.fov_y_deg = 150.0;                  // and wide enough to see the cut
    cam.z_near = 0.3;
    RasterOptions o;
    o.width = o.height = 128;
    RasterStats st;
    const FragmentBuffer fb = rasterize(sphere, cam, o, &st);
    REQUIRE(st.triangles_clipped > 0);
    std::vector<float> vp(3 * sphere.positions.size());
    const std::size_t nv = sphere.positions.size();
    for (std::size_t i = 0; i < nv; ++i) {
        const glm::dvec3& p = sphere.positions[i];
        vp[i] = float(2.0 * p.x - p.y + 0.5);
        vp[nv + i] = float(p.z);
        vp[2 * nv + i] = 1.0f;
    }
    const auto f = interpolate_to_fragments(fb, sphere, vp);
    double worst = 0.0;
    const std::size_t n = fb.size();
    for (std::size_t i = 0; i < n; ++i) {
        worst = std::max(worst, std::abs(double(f[i]) - (2.0 * fb.px[i] - fb.py[i] + 0.5)));
        worst = std::max(worst, double(std::abs(f[n + i] - fb.pz[i])));
        worst = std::max(worst, std::abs(double(f[2 * n + i]) - 1.0));
    }
    INFO("worst deviation " << worst);
    CHECK(worst < 2e-6);
}

TEST_CASE("Gouraud Lambert on a sphere converges to per-pixel Lambert with tessellation", "[gouraud]") {
    Runtime& rt = test::runtime();
    Shader shader(rt);
    ShadeSetup setup;
    setup.material.albedo = glm::dvec3(0.8);
    setup.lights = {Light{Light::Type::Directional, {0.2, 0.5, 1.0}, {1, 1, 1}, 1.0, 0.0}};
    double previous = 1e9;
    for (int level : {1, 2, 3, 4, 5}) {
        const Mesh sphere = make_icosphere(level);
        const Camera cam = Camera::fit(sphere.bounds(), {0, 0, 1}, 35.0, 1.0);
        RasterOptions o;
        o.width = o.height = 160;
        const FragmentBuffer fb = rasterize(sphere, cam, o);
        setup.view = glm::dvec4(cam.eye, 1.0);
        const auto per_pixel = shader.shade(fb, setup);
        const auto per_vertex = interpolate_to_fragments(fb, sphere, shade_vertices(shader, sphere, setup));
        double worst = 0.0;
        for (std::size_t i = 0; i < per_pixel.size(); ++i) worst = std::max(worst, double(std::abs(per_pixel[i] - per_vertex[i])));
        std::cout << "gouraud vs per-pixel lambert, icosphere level " << level << ": max abs difference " << worst << "\n";
        INFO("level " << level);
        CHECK(worst < previous);
        previous = worst;
    }
    CHECK(previous < 0.01);
}
