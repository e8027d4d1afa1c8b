// The rasteriser: exact coverage, the fill rule, depth, perspective-correct interpolation, near-plane
// clipping, determinism across thread counts, culling, framing, bad input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "core/error.hpp"
#include "mesh/mesh.hpp"
#include "raster/raster.hpp"

using namespace shadelab;

namespace {

// Camera at (0, 0, 1) looking down -z with a 90 degree field of view on a square image: the plane z = 0
// spans x, y in [-1, 1], i.e. world x = -1 + 2 px / W. So a world length of 2/W is one pixel.
Camera unit_camera() {
    Camera c;
    c.eye = {0, 0, 1};
    c.target = {0, 0, 0};
    c.up = {0, 1, 0};
    c.fov_y_deg = 90.0;
    c.z_near = 0.01;
    c.z_far = 100.0;
    return c;
}

Mesh rect(double x0, double y0, double x1, double y1, double z) {
    Mesh m;
    m.positions = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
    m.normals.assign(4, glm::dvec3(0, 0, 1));
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

bool unique_pixels(const FragmentBuffer& fb) {
    std::set<int> seen(fb.pixel.begin(), fb.pixel.end());
    return seen.size() == fb.size();
}

RasterOptions square(int n, int threads = 0) {
    RasterOptions o;
    o.width = o.height = n;
    o.threads = threads;
    return o;
}

// The ray through pixel (x, y)'s centre, in world space.
glm::dvec3 pixel_ray(const Camera& c, int W, int H, int x, int y) {
    const double t = std::tan(glm::radians(c.fov_y_deg) / 2);
    const double nx = 2.0 * (x + 0.5) / W - 1.0, ny = 1.0 - 2.0 * (y + 0.5) / H;
    const glm::dvec3 f = glm::normalize(c.target - c.eye), r = glm::normalize(glm::cross(f, c.up)), u = glm::cross(r, f);
    return glm::normalize(f + nx * t * (double(W) / H) * r + ny * t * u);
}

}  // namespace

TEST_CASE("a screen-aligned square covers exactly its area in pixels", "[raster]") {
    const int W = 256;
    const double px = 2.0 / W;
    // Edges on pixel boundaries: columns and rows 64..191.
    FragmentBuffer fb = rasterize(rect(-1 + 64 * px, -1 + 64 * px, -1 + 192 * px, -1 + 192 * px, 0.0), unit_camera(), square(W));
    CHECK(fb.size() == 128u * 128u);
    CHECK(unique_pixels(fb));
    // Edges through pixel centres: the fill rule takes exactly one of each pair of boundary rows/columns.
    fb = rasterize(rect(-1 + 64.5 * px, -1 + 64.5 * px, -1 + 192.5 * px, -1 + 192.5 * px, 0.0), unit_camera(), square(W));
    CHECK(fb.size() == 128u * 128u);
    CHECK(unique_pixels(fb));
}

TEST_CASE("triangles sharing edges shade every pixel exactly once (jittered triangulated grid)", "[raster]") {
    const int W = 200;
    const double px = 2.0 / W;
    std::mt19937_64 g(4);
    for (int trial = 0; trial < 5; ++trial) {
        // A 12 x 9 grid over pixel-aligned bounds [20, 180] x [30, 174]; interior vertices jittered,
        // cells split along a random diagonal; some vertices land exactly on pixel centres.
        const int nx = 12, ny = 9;
        Mesh m;
        for (int j = 0; j <= ny; ++j)
            for (int i = 0; i <= nx; ++i) {
                double sx = 20 + 160.0 * i / nx, sy = 30 + 144.0 * j / ny;
                if (i > 0 && i < nx && j > 0 && j < ny) {
                    sx += double(int(g() % 9) - 4) * 0.5 + ((g() % 3 == 0) ? 0.0 : double(g() % 1000) / 1000.0);
                    sy += double(int(g() % 9) - 4) * 0.5;
                }
                m.positions.push_back({-1 + sx * px, 1 - sy * px, 0.0});
                m.normals.push_back({0, 0, 1});
            }
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const glm::u32 a = glm::u32(j * (nx + 1) + i), b = a + 1, c = a + glm::u32(nx + 1), d = c + 1;
                if (g() % 2) { m.triangles.push_back({a, c, b}); m.triangles.push_back({b, c, d}); }
                else { m.triangles.push_back({a, c, d}); m.triangles.push_back({a, d, b}); }
            }
        for (int threads : {1, 2}) {
            const FragmentBuffer fb = rasterize(m, unit_camera(), square(W, threads));
            INFO("trial " << trial << ", threads " << threads);
            CHECK(unique_pixels(fb));             // no double coverage
            CHECK(fb.size() == 160u * 144u);      // no cracks: the union is the pixel-aligned rectangle
        }
    }
}

TEST_CASE("depth test keeps the nearer surface whatever the submission order", "[raster]") {
    const Mesh far = rect(-0.5, -0.5, 0.5, 0.5, 0.0), near = rect(-0.2, -0.7, 0.7, 0.2, 0.3);
    for (bool near_first : {true, false}) {
        Mesh both = near_first ? near : far;
        const Mesh& second = near_first ? far : near;
        const glm::u32 off = glm::u32(both.positions.size());
        both.positions.insert(both.positions.end(), second.positions.begin(), second.positions.end());
        both.normals.insert(both.normals.end(), second.normals.begin(), second.normals.end());
        for (auto t : second.triangles) both.triangles.push_back(t + glm::u32vec3(off));
        const FragmentBuffer fb = rasterize(both, unit_camera(), square(128));
        REQUIRE(unique_pixels(fb));
        std::size_t overlap = 0, wrong = 0;
        for (std::size_t i = 0; i < fb.size(); ++i) {
            // In the overlap (projected), the near quad must win.
            const glm::dvec3 d = pixel_ray(unit_camera(), 128, 128, fb.pixel[i] % 128, fb.pixel[i] / 128);
            const glm::dvec3 hit_far = glm::dvec3(0, 0, 1) + d * (-1.0 / d.z);
            const glm::dvec3 hit_near = glm::dvec3(0, 0, 1) + d * (-0.7 / d.z);
            const bool in_far = std::abs(hit_far.x) < 0.5 && std::abs(hit_far.y) < 0.5;
            const bool in_near = hit_near.x > -0.2 && hit_near.x < 0.7 && hit_near.y > -0.7 && hit_near.y < 0.2;
            if (in_far && in_near) {
                ++overlap;
                wrong += std::abs(fb.pz[i] - 0.3f) < 1e-6f ? 0 : 1;
            }
        }
        INFO("near quad first: " << near_first);
        CHECK(overlap > 500);
        CHECK(wrong == 0);
    }
}

TEST_CASE("perspective-correct interpolation: positions on a slanted plane match ray-plane hits", "[raster]") {
    // A quad tilted 60 degrees away from the camera: affine interpolation would be off by a lot.
    Camera cam = unit_camera();
    cam.eye = {0, 0.3, 2.0};
    Mesh m;
    const double c = std::cos(glm::radians(60.0)), s = std::sin(glm::radians(60.0));
    for (auto uv : {glm::dvec2(-1, -1), glm::dvec2(1, -1), glm::dvec2(1, 1), glm::dvec2(-1, 1)})
        m.positions.push_back({uv.x, uv.y * c, -uv.y * s});
    const glm::dvec3 n = glm::normalize(glm::cross(m.positions[1] - m.positions[0], m.positions[2] - m.positions[0]));
    m.normals.assign(4, n);
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    const int W = 160;
    const FragmentBuffer fb = rasterize(m, cam, square(W));
    REQUIRE(fb.size() > 2000);
    double worst = 0.0;
    for (std::size_t i = 0; i < fb.size(); ++i) {
        const glm::dvec3 d = pixel_ray(cam, W, W, fb.pixel[i] % W, fb.pixel[i] / W);
        const double t = glm::dot(m.positions[0] - cam.eye, n) / glm::dot(d, n);
        const glm::dvec3 hit = cam.eye + t * d;
        worst = std::max(worst, glm::length(glm::dvec3(fb.px[i], fb.py[i], fb.pz[i]) - hit));
        CHECK(std::abs(fb.depth[i] - glm::dot(hit - cam.eye, glm::normalize(cam.target - cam.eye))) < 1e-5);
    }
    INFO("worst distance from the ray-plane hit " << worst);
    CHECK(worst < 1e-5);   // float storage of positions ~1e-7; affine interpolation errs by ~1e-2 here
}

TEST_CASE("near-plane clipping keeps only what is in front, with the right coverage", "[raster]") {
    // A floor y = -0.5 running from far in front of the camera to far behind it.
    Camera cam = unit_camera();
    cam.eye = {0, 0, 0};
    cam.target = {0, 0, -1};
    cam.z_near = 0.1;
    cam.z_far = 50.0;
    Mesh floor = rect(-3, -30, 3, 30, 0.0);
    glm::dmat4 rot(1.0);
    rot[1] = glm::dvec4(0, 0, -1, 0);   // y -> -z
    rot[2] = glm::dvec4(0, 1, 0, 0);    // z -> y
    rot[3] = glm::dvec4(0, -0.5, 0, 1);
    floor.transform(rot);
    RasterStats st;
    const int W = 96;
    const FragmentBuffer fb = rasterize(floor, cam, square(W), &st);
    CHECK(st.triangles_clipped > 0);
    REQUIRE(unique_pixels(fb));
    std::size_t expect = 0;
    for (int y = 0; y < W; ++y)
        for (int x = 0; x < W; ++x) {
            const glm::dvec3 d = pixel_ray(cam, W, W, x, y);
            if (d.y >= 0) continue;
            const glm::dvec3 hit = d * (-0.5 / d.y);
            const double depth = -hit.z;
            if (std::abs(hit.x) < 3 && hit.z > -30 && depth > cam.z_near && depth < cam.z_far) ++expect;
        }
    for (std::size_t i = 0; i < fb.size(); ++i) {
        CHECK(fb.depth[i] >= cam.z_near * 0.999);
        CHECK(std::isfinite(fb.px[i]));
    }
    INFO("fragments " << fb.size() << ", analytic " << expect);
    // Pixels whose centre is within rounding of the floor's far edge or sides may go either way.
    CHECK(std::abs(double(fb.size()) - double(expect)) <= 0.01 * double(expect));
}

TEST_CASE("results are bit-identical for any thread count", "[raster]") {
    const Mesh bunny = load_mesh(SHADELAB_MESH_DIR "/stanford-bunny.obj");
    const Camera cam = Camera::fit(bunny.bounds(), {0.3, 0.2, 1.0}, 35.0, 1.0);
    const FragmentBuffer a = rasterize(bunny, cam, square(256, 1));
    REQUIRE(a.size() > 10000);
    for (int t : {2, 3, 7}) {
        const FragmentBuffer b = rasterize(bunny, cam, square(256, t));
        INFO("threads " << t);
        CHECK(a.pixel == b.pixel);
        CHECK(a.px == b.px);
        CHECK(a.py == b.py);
        CHECK(a.pz == b.pz);
        CHECK(a.nx == b.nx);
        CHECK(a.ny == b.ny);
        CHECK(a.nz == b.nz);
        CHECK(a.depth == b.depth);
    }
    CHECK(std::is_sorted(a.pixel.begin(), a.pixel.end()));
}

TEST_CASE("back-face culling on a closed convex mesh drops nothing visible", "[raster]") {
    const Mesh sphere = make_icosphere(3);
    const Camera cam = Camera::fit(sphere.bounds(), {1, 0.5, 0.8}, 40.0, 1.0);
    RasterOptions o = square(128);
    RasterStats st;
    const FragmentBuffer all = rasterize(sphere, cam, o);
    o.cull_backfaces = true;
    const FragmentBuffer front = rasterize(sphere, cam, o, &st);
    CHECK(st.triangles_culled > 0);
    CHECK(front.size() == all.size());
    CHECK(front.pixel == all.pixel);
    std::size_t facing_away = 0;
    for (std::size_t i = 0; i < front.size(); ++i) {
        const glm::dvec3 p{front.px[i], front.py[i], front.pz[i]};
        // On a sphere the normal is p; a front-facing facet's points may see the eye at up to the facet's
        // angular size (0.14 rad at level 3) beyond the tangent plane, never more.
        facing_away += glm::dot(glm::normalize(p), glm::normalize(cam.eye - p)) < -0.15 ? 1 : 0;
    }
    CHECK(facing_away == 0);
}

TEST_CASE("Camera::fit frames the whole bounds", "[raster]") {
    const Mesh teapot = load_mesh(SHADELAB_MESH_DIR "/teapot.obj");
    for (double aspect : {1.0, 16.0 / 9.0, 0.5}) {
        const Camera cam = Camera::fit(teapot.bounds(), {0.4, 0.6, 1.0}, 30.0, aspect);
        const glm::dmat4 vp = cam.projection(aspect) * cam.view();
        const Bounds b = teapot.bounds();
        for (int k = 0; k < 8; ++k) {
            const glm::dvec3 corner{k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z};
            const glm::dvec4 c = vp * glm::dvec4(corner, 1.0);
            INFO("aspect " << aspect << " corner " << k);
            CHECK(c.w > 0);
            CHECK(std::abs(c.x / c.w) <= 1.0);
            CHECK(std::abs(c.y / c.w) <= 1.0);
            CHECK(c.z / c.w >= -1.0);
            CHECK(c.z / c.w <= 1.0);
        }
    }
}

TEST_CASE("bad raster input is one clear error", "[raster]") {
    const Mesh q = make_quad();
    RasterOptions o = square(64);
    o.width = 0;
    REQUIRE_THROWS_WITH(rasterize(q, unit_camera(), o), Catch::Contains("image size") && Catch::Contains("[1, 16384]"));
    Camera c = unit_camera();
    c.fov_y_deg = 0.0;
    REQUIRE_THROWS_WITH(rasterize(q, c, square(64)), Catch::Contains("field of view"));
    c = unit_camera();
    c.target = c.eye;
    REQUIRE_THROWS_WITH(rasterize(q, c, square(64)), Catch::Contains("same point"));
    c = unit_camera();
    c.eye.x = std::nan("");
    REQUIRE_THROWS_WITH(rasterize(q, c, square(64)), Catch::Contains("finite"));
}
