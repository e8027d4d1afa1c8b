// Mesh input: the bundled meshes, every supported format, bad input, normals, icosphere, sampler.
#include <catch2/catch.hpp>

#include <cmath>

#include "core/error.hpp"
#include "mesh/mesh.hpp"
#include "support.hpp"

using namespace shadelab;

namespace {

void check_unit_normals(const Mesh& m) {
    std::size_t bad = 0;
    for (const auto& n : m.normals) bad += std::abs(glm::length(n) - 1.0) < 1e-9 ? 0 : 1;
    INFO(m.source << ": " << bad << " normals not unit length");
    CHECK(bad == 0);
}
}  // namespace

TEST_CASE("the bundled meshes load with their known counts and unit normals", "[mesh]") {
    struct Known { const char* file; std::size_t triangles; };
    for (const Known k : {Known{"spot.obj", 5856}, Known{"teapot.obj", 6320}, Known{"suzanne.obj", 968},
                          Known{"stanford-bunny.obj", 69451}}) {
        MeshLoadReport r;
        const Mesh m = load_mesh(test::kMeshes + "/" + k.file, &r);
        INFO(k.file);
        CHECK(m.triangles.size() == k.triangles);
        CHECK(r.triangles_out == k.triangles);
        CHECK(m.normals.size() == m.positions.size());
        check_unit_normals(m);
    }
    MeshLoadReport bunny;
    load_mesh(test::kMeshes + "/stanford-bunny.obj", &bunny);
    CHECK(bunny.unused_vertices == 1113);   // unreferenced vertices already in the file (SOURCES.md)
    CHECK_FALSE(bunny.notes.empty());
    MeshLoadReport suzanne;
    const Mesh s = load_mesh(test::kMeshes + "/suzanne.obj", &suzanne);
    CHECK(s.positions.size() == 511);       // OpenMesh re-adds one quad with 4 duplicated vertices
    // Those copies carry no file normal (OpenMesh leaves it uninitialised): they must take their
    // original's, the same on every load.
    const Mesh s2 = load_mesh(test::kMeshes + "/suzanne.obj");
    CHECK(s.normals == s2.normals);
    for (std::size_t i = 507; i < 511; ++i) {
        bool matched = false;
        for (std::size_t j = 0; j < 507; ++j)
            if (s.positions[j] == s.positions[i]) matched = matched || s.normals[j] == s.normals[i];
        INFO("duplicated vertex " << i);
        CHECK(matched);
    }
}

TEST_CASE("OFF, PLY and STL load - missing normals are computed area-weighted", "[mesh]") {
    for (const char* f : {"tetra.off", "tetra.ply", "tetra.stl"}) {
        INFO(f);
        MeshLoadReport r;
        const Mesh m = load_mesh(test::kData + "/" + f, &r);
        REQUIRE(m.triangles.size() == 4);
        check_unit_normals(m);
        // The corner at the origin touches the three axis faces (each of area 1/2): the area-weighted
        // normal is -(1, 1, 1)/sqrt(3). STL stores only facet normals, so vertices are computed there too.
        for (std::size_t i = 0; i < m.positions.size(); ++i)
            if (glm::length(m.positions[i]) == 0.0 && !r.normals_from_file) {
                const glm::dvec3 expect = -glm::dvec3(1.0) / std::sqrt(3.0);
                CHECK(glm::length(m.normals[i] - expect) < 1e-12);
            }
        CHECK_FALSE(r.normals_from_file);
    }
}

TEST_CASE("bad mesh input gives one clear error naming the file", "[mesh]") {
    REQUIRE_THROWS_WITH(load_mesh(test::kData + "/does-not-exist.obj"), Catch::Contains("does-not-exist.obj") && Catch::Contains("not found"));
    REQUIRE_THROWS_WITH(load_mesh(test::kData + "/unknown.xyz"), Catch::Contains("unknown.xyz") && Catch::Contains(".obj"));
    REQUIRE_THROWS_WITH(load_mesh(test::kData + "/empty.obj"), Catch::Contains("empty.obj") && Catch::Contains("empty"));
    REQUIRE_THROWS_WITH(load_mesh(test::kData + "/points_only.obj"), Catch::Contains("points_only.obj") && Catch::Contains("no triangles"));
    REQUIRE_THROWS_WITH(load_mesh(test::kData + "/nan.obj"), Catch::Contains("nan.obj") && Catch::Contains("NaN/Inf"));
    REQUIRE_THROWS_AS(load_mesh(test::kData + "/garbage.ply"), Error);
    REQUIRE_THROWS_WITH(load_mesh(test::kData + "/garbage.ply"), Catch::Contains("garbage.ply"));
    REQUIRE_THROWS_WITH(load_mesh(test::kData), Catch::Contains("folder"));
}

TEST_CASE("degenerate triangles are dropped and reported, never silently kept", "[mesh]") {
    MeshLoadReport r;
    const Mesh m = load_mesh(test::kData + "/degenerate.obj", &r);
    CHECK(m.triangles.size() == 2);
    CHECK(r.degenerate_dropped == 1);
    bool noted = false;
    for (const auto& n : r.notes) noted = noted || n.find("degenerate") != std::string::npos;
    CHECK(noted);
    check_unit_normals(m);
}

TEST_CASE("icosphere: counts, radius, outward winding, area converging to 4 pi r^2", "[mesh]") {
    double previous_err = 1e9;
    for (int k = 0; k <= 5; ++k) {
        const double r = 2.5;
        const Mesh m = make_icosphere(k, r);
        INFO("level " << k);
        CHECK(m.triangles.size() == 20u * (1u << (2 * k)));
        double area = 0.0;
        std::size_t inward = 0, off_sphere = 0, bad_normal = 0;
        for (std::size_t i = 0; i < m.positions.size(); ++i) {
            off_sphere += std::abs(glm::length(m.positions[i]) - r) < 1e-12 ? 0 : 1;
            bad_normal += glm::length(m.normals[i] - m.positions[i] / r) < 1e-12 ? 0 : 1;
        }
        for (const auto& t : m.triangles) {
            const glm::dvec3 c = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
            area += 0.5 * glm::length(c);
            inward += glm::dot(c, m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]) > 0 ? 0 : 1;
        }
        CHECK(off_sphere == 0);
        CHECK(bad_normal == 0);
        CHECK(inward == 0);
        const double err = std::abs(area - 4.0 * M_PI * r * r) / (4.0 * M_PI * r * r);
        CHECK(err < previous_err);
        previous_err = err;
        if (k == 5) CHECK(err < 0.01);
    }
    CHECK_THROWS_AS(make_icosphere(-1), Error);
    CHECK_THROWS_AS(make_icosphere(10), Error);
    CHECK_THROWS_AS(make_icosphere(2, 0.0), Error);
}

TEST_CASE("surface sampler: area-uniform, on the surface, deterministic per seed", "[mesh]") {
    const Mesh sphere = make_icosphere(4);
    const std::size_t n = 200000;
    const FragmentBuffer s = sample_surface(sphere, n, 7);
    REQUIRE(s.size() == n);
    glm::dvec3 mean(0.0);
    std::size_t bad = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 p{s.px[i], s.py[i], s.pz[i]}, nn{s.nx[i], s.ny[i], s.nz[i]};
        mean += p / double(n);
        // Level 4 chords sit at most ~1 - cos(edge/2) ~ 1.2e-3 inside the unit sphere.
        bad += (glm::length(p) > 1.0 + 1e-6 || glm::length(p) < 0.998 || std::abs(glm::length(nn) - 1.0) > 1e-5) ? 1 : 0;
        CHECK(s.pixel[i] == -1);
    }
    CHECK(bad == 0);
    for (int c = 0; c < 3; ++c) CHECK(std::abs(mean[c]) < 3.0 * 0.58 / std::sqrt(double(n)) * 2.0);

    // Two triangles of areas 1 and 3: a quarter of the samples on the first.
    Mesh two;
    two.positions = {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}, {10, 0, 0}, {16, 0, 0}, {10, 1, 0}};
    two.normals.assign(6, glm::dvec3(0, 0, 1));
    two.triangles = {{0, 1, 2}, {3, 4, 5}};
    const FragmentBuffer t = sample_surface(two, 100000, 3);
    std::size_t first = 0;
    for (std::size_t i = 0; i < t.size(); ++i) first += t.px[i] < 5.0f ? 1 : 0;
    const double frac = double(first) / double(t.size());
    const double sigma = std::sqrt(0.25 * 0.75 / double(t.size()));
    INFO("fraction on the small triangle " << frac);
    CHECK(std::abs(frac - 0.25) < 4.0 * sigma);

    const FragmentBuffer again = sample_surface(sphere, 1000, 7), other = sample_surface(sphere, 1000, 8);
    const FragmentBuffer first_k = sample_surface(sphere, 1000, 7);
    CHECK(again.px == first_k.px);
    CHECK(again.nz == first_k.nz);
    CHECK(again.px != other.px);
}

TEST_CASE("Mesh::transform keeps normals unit and perpendicular under non-uniform scale", "[mesh]") {
    Mesh m = make_icosphere(2);
    const Mesh before = m;
    glm::dmat4 t(1.0);
    t[0][0] = 3.0;   // scale x by 3
    t[1][1] = 0.5;
    t[3] = glm::dvec4(1, 2, 3, 1);
    m.transform(t);
    for (const auto& tri : m.triangles) {
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 edge = m.positions[tri[(k + 1) % 3]] - m.positions[tri[k]];
            const glm::dvec3 n = m.normals[tri[k]];
            CHECK(std::abs(glm::length(n) - 1.0) < 1e-12);
            // Vertex normals are exact sphere normals, so the ellipsoid's true normal at the vertex is
            // perpendicular to its tangent plane; edges are chords, so check against the face normal's sign.
            const glm::dvec3 fn = glm::cross(m.positions[tri[1]] - m.positions[tri[0]], m.positions[tri[2]] - m.positions[tri[0]]);
            CHECK(glm::dot(fn, n) > 0.0);
            (void)edge;
        }
    }
    CHECK(m.positions[0] == glm::dvec3(t * glm::dvec4(before.positions[0], 1.0)));
}
