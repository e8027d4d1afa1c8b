// Mesh module, second file (tests/test_mesh_loader.cpp has the bundled meshes, the basic formats and bad
// input, degenerate faces, icosphere area and the sampler statistics). Here: hand-computed area-weighted
// normals, partial/zero file normals, repeated-index faces in OBJ and OFF, NaN/Inf in every format,
// binary STL, upper-case extensions, the quad, bounds, icosphere topology, transform against tangents,
// sampler edge cases.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"
#include "mesh/mesh.hpp"
#include "support.hpp"

using namespace shadelab;

namespace {

std::size_t vertex_at(const Mesh& m, const glm::dvec3& p) {
    for (std::size_t i = 0; i < m.positions.size(); ++i)
        if (m.positions[i] == p) return i;
    FAIL("no vertex at (" << p.x << ", " << p.y << ", " << p.z << ") in " << m.source);
    return 0;
}

bool has_note(const MeshLoadReport& r, const std::string& word) {
    for (const auto& n : r.notes)
        if (n.find(word) != std::string::npos) return true;
    return false;
}

std::string notes_of(const MeshLoadReport& r) {
    std::string s;
    for (const auto& n : r.notes) s += "[" + n + "] ";
    return s;
}
}  // namespace

TEST_CASE("mesh: cube without normals gets area-weighted normals (hand computed)", "[mesh]") {
    // Each square face is two triangles of area 1/2 (|cross| = 1). Corner (0,0,0) lies in both triangles of
    // its three faces: the normal is the diagonal. Corner (1,0,0) lies in both triangles of the x = 1 face
    // but in one of the y = 0 and of the z = 0 face: area weighting gives (2, -1, -1)/sqrt(6), where angle
    // weighting would give the diagonal. Corner (1,1,0): both bottom triangles, one back, one right.
    MeshLoadReport r;
    const Mesh m = load_mesh(test::kData + "/cube_no_normals.obj", &r);
    REQUIRE(m.triangles.size() == 12);
    CHECK_FALSE(r.normals_from_file);
    CHECK(r.normals_repaired == 0);
    struct Known { glm::dvec3 p, n; };
    const double s3 = std::sqrt(3.0), s6 = std::sqrt(6.0);
    for (const Known& k : {Known{{0, 0, 0}, glm::dvec3(-1, -1, -1) / s3}, Known{{1, 0, 0}, glm::dvec3(2, -1, -1) / s6},
                           Known{{1, 1, 0}, glm::dvec3(1, 1, -2) / s6}, Known{{1, 1, 1}, glm::dvec3(1, 1, 1) / s3}}) {
        const glm::dvec3 n = m.normals[vertex_at(m, k.p)];
        INFO("vertex (" << k.p.x << ", " << k.p.y << ", " << k.p.z << "): normal (" << n.x << ", " << n.y << ", " << n.z
                        << "), expected (" << k.n.x << ", " << k.n.y << ", " << k.n.z << ")");
        CHECK(glm::length(n - k.n) < 1e-12);
    }
    // Closed, consistently wound: every normal points away from the centre.
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        INFO("vertex " << i);
        CHECK(glm::dot(m.normals[i], m.positions[i] - glm::dvec3(0.5)) > 0.5);
    }
}

TEST_CASE("mesh: valid file normals are kept, zero or missing ones recomputed and counted", "[mesh]") {
    SECTION("only the bottom face's corners name a normal") {
        MeshLoadReport r;
        const Mesh m = load_mesh(test::kData + "/partial_normals.obj", &r);
        INFO(notes_of(r));
        CHECK(r.normals_from_file);
        CHECK(r.normals_repaired == 1);
        CHECK(has_note(r, "recomputed"));
        // Vertices 1..3 keep the file's (0,0,-1) even though the computed normal would differ.
        for (const glm::dvec3 p : {glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0)})
            CHECK(m.normals[vertex_at(m, p)] == glm::dvec3(0, 0, -1));
        // Vertex (0,0,1): faces with cross products (0,-1,0), (-1,0,0), (1,1,1) sum to (0,0,1).
        CHECK(glm::length(m.normals[vertex_at(m, {0, 0, 1})] - glm::dvec3(0, 0, 1)) < 1e-12);
        // The vertex without a file normal must not pick up whatever OpenMesh left in memory.
        const Mesh again = load_mesh(test::kData + "/partial_normals.obj");
        CHECK(again.normals == m.normals);
    }
    SECTION("a zero normal in the file") {
        MeshLoadReport r;
        const Mesh m = load_mesh(test::kData + "/zero_normal.obj", &r);
        INFO(notes_of(r));
        CHECK(r.normals_from_file);
        CHECK(r.normals_repaired == 1);
        CHECK(glm::length(m.normals[vertex_at(m, {0, 0, 0})] - glm::dvec3(-1, -1, -1) / std::sqrt(3.0)) < 1e-12);
        CHECK(m.normals[vertex_at(m, {1, 0, 0})] == glm::dvec3(1, 0, 0));
    }
}

TEST_CASE("mesh: normals that cancel take an adjacent face's - unused vertices are counted", "[mesh]") {
    // One triangle listed twice with opposite windings: the area-weighted sums are exactly zero.
    MeshLoadReport r;
    const Mesh m = load_mesh(test::kData + "/cancel.obj", &r);
    INFO(notes_of(r));
    REQUIRE(m.triangles.size() == 2);
    CHECK(r.unused_vertices == 1);
    CHECK(has_note(r, "used by no triangle"));
    for (const glm::dvec3 p : {glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0)}) {
        const glm::dvec3 n = m.normals[vertex_at(m, p)];
        INFO("vertex (" << p.x << ", " << p.y << ") normal (" << n.x << ", " << n.y << ", " << n.z << ")");
        CHECK(std::abs(std::abs(n.z) - 1.0) < 1e-12);   // the normal of one of its two faces, +-z
    }
    for (const auto& n : m.normals) CHECK(std::abs(glm::length(n) - 1.0) < 1e-12);
    // Bounds ignore the unused vertex (0,0,1).
    const Bounds b = m.bounds();
    CHECK(b.lo == glm::dvec3(0, 0, 0));
    CHECK(b.hi == glm::dvec3(1, 1, 0));
}

TEST_CASE("mesh: faces naming a vertex twice are dropped and counted (OBJ and OFF)", "[mesh]") {
    // OpenMesh drops the OBJ one silently and logs the OFF one; both must reach the report.
    for (const char* f : {"repeated.obj", "repeated.off"}) {
        MeshLoadReport r;
        const Mesh m = load_mesh(test::kData + "/" + f, &r);
        INFO(f << ": " << notes_of(r));
        CHECK(m.triangles.size() == 4);
        CHECK(r.triangles_out == 4);
        CHECK(r.degenerate_dropped == 1);
        CHECK(has_note(r, "degenerate"));
        CHECK(r.unused_vertices == 0);
    }
}

TEST_CASE("mesh: NaN/Inf coordinates are named in every format, never reported as 'no triangles'", "[mesh]") {
    for (const char* f : {"nan.obj", "nan.off", "inf.ply", "nan_binary.ply", "nan_ascii.stl", "nan_binary.stl"}) {
        INFO(f);
        REQUIRE_THROWS_AS(load_mesh(test::kData + "/" + f), Error);
        REQUIRE_THROWS_WITH(load_mesh(test::kData + "/" + f), Catch::Contains(f) && Catch::Contains("NaN/Inf") &&
                                                            Catch::Contains("fix or remove"));
    }
}

TEST_CASE("mesh: every failure is one line naming the file", "[mesh]") {
    for (const char* f : {"does-not-exist.obj", "unknown.xyz", "empty.obj", "points_only.obj", "garbage.ply", "nan.obj"}) {
        INFO(f);
        try {
            load_mesh(test::kData + "/" + f);
            FAIL("no error for " << f);
        } catch (const Error& e) {
            const std::string msg = e.what();
            INFO(msg);
            CHECK(msg.find(f) != std::string::npos);
            CHECK(msg.find('\n') == std::string::npos);
            CHECK(msg.find(": ") != std::string::npos);   // what went wrong: what to do
        }
    }
    CHECK_THROWS_WITH(load_mesh(test::kData + "/unknown.xyz"),
                      Catch::Contains(".obj") && Catch::Contains(".off") && Catch::Contains(".ply") && Catch::Contains(".stl"));
}

TEST_CASE("mesh: binary STL and upper-case extensions load - report counts", "[mesh]") {
    for (const char* f : {"tetra_binary.stl", "upper_case.OFF", "tetra.off"}) {
        MeshLoadReport r;
        const Mesh m = load_mesh(test::kData + "/" + f, &r);
        INFO(f << ": " << notes_of(r));
        CHECK(m.positions.size() == 4);   // STL corners are merged by position
        CHECK(m.triangles.size() == 4);
        CHECK(r.vertices_in == 4);
        CHECK(r.faces_in == 4);
        CHECK(r.triangles_out == 4);
        CHECK(r.degenerate_dropped == 0);
        CHECK(r.notes.empty());
        CHECK(m.source == test::kData + "/" + f);
        CHECK(glm::length(m.normals[vertex_at(m, {0, 0, 0})] - glm::dvec3(-1, -1, -1) / std::sqrt(3.0)) < 1e-12);
        const Bounds b = m.bounds();
        CHECK(b.lo == glm::dvec3(0.0));
        CHECK(b.hi == glm::dvec3(1.0));
        CHECK(b.centre() == glm::dvec3(0.5));
        CHECK(std::abs(b.radius() - 0.5 * std::sqrt(3.0)) < 1e-15);
    }
}

TEST_CASE("mesh: suzanne's complex edges become notes - its duplicated vertices are reported", "[mesh]") {
    MeshLoadReport r;
    const Mesh m = load_mesh(test::kMeshes + "/suzanne.obj", &r);
    INFO(notes_of(r));
    CHECK(m.positions.size() == 511);
    CHECK(r.vertices_in == 511);
    CHECK(m.triangles.size() == 968);
    CHECK(r.normals_from_file);
    CHECK(r.normals_repaired == 0);
    CHECK(has_note(r, "complex"));
    CHECK(has_note(r, "duplicated"));
}

TEST_CASE("mesh: make_quad is two CCW triangles seen from +z with +z normals", "[mesh]") {
    const double half = 1.5;
    const Mesh q = make_quad(half);
    REQUIRE(q.triangles.size() == 2);
    REQUIRE(q.positions.size() == 4);
    double area = 0.0;
    for (const auto& t : q.triangles) {
        const glm::dvec3 c = glm::cross(q.positions[t[1]] - q.positions[t[0]], q.positions[t[2]] - q.positions[t[0]]);
        CHECK(c.z > 0.0);
        CHECK(c.x == 0.0);
        CHECK(c.y == 0.0);
        area += 0.5 * c.z;
    }
    CHECK(area == Approx(4.0 * half * half).epsilon(1e-15));
    for (const auto& n : q.normals) CHECK(n == glm::dvec3(0, 0, 1));
    const Bounds b = q.bounds();
    CHECK(b.lo == glm::dvec3(-half, -half, 0));
    CHECK(b.hi == glm::dvec3(half, half, 0));
}

TEST_CASE("mesh: icosphere is a closed genus-0 surface with uniform edges at level 0", "[mesh]") {
    for (int k = 0; k <= 4; ++k) {
        const Mesh m = make_icosphere(k, 1.0);
        INFO("level " << k);
        const std::size_t f = 20u << (2 * k), v = 10u * (std::size_t(1) << (2 * k)) + 2, e = 30u << (2 * k);
        CHECK(m.triangles.size() == f);
        CHECK(m.positions.size() == v);   // V - E + F = 2 with E = 3F/2: no duplicated midpoints
        CHECK(long(v) - long(e) + long(f) == 2);
        CHECK(m.normals.size() == v);
        CHECK(m.source.find(std::to_string(k)) != std::string::npos);
    }
    const Mesh ico = make_icosphere(0, 2.0);
    const double edge = 2.0 / std::sin(2.0 * M_PI / 5.0);   // circumradius R = a sin(2 pi / 5)
    for (const auto& t : ico.triangles)
        for (int k = 0; k < 3; ++k)
            CHECK(glm::length(ico.positions[t[k]] - ico.positions[t[(k + 1) % 3]]) == Approx(edge).epsilon(1e-12));
    CHECK_THROWS_WITH(make_icosphere(12), Catch::Contains("12"));
}

TEST_CASE("mesh: transform keeps normals unit and perpendicular to transformed tangents", "[mesh]") {
    Mesh m = make_icosphere(2, 1.0);
    const Mesh before = m;
    glm::dmat4 t = glm::translate(glm::dmat4(1.0), glm::dvec3(1, -2, 3));
    t = glm::rotate(t, 0.7, glm::normalize(glm::dvec3(1, 2, 3)));
    t = glm::scale(t, glm::dvec3(3.0, 0.5, 1.7));   // non-uniform: plain m * n would not stay perpendicular
    m.transform(t);
    const glm::dmat3 l(t);
    std::size_t bad_unit = 0, bad_perp = 0, bad_pos = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        const glm::dvec3 n0 = before.normals[i];
        // Two tangents of the sphere at the vertex, mapped as positions' differentials are.
        const glm::dvec3 a = std::abs(n0.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        const glm::dvec3 t1 = glm::normalize(glm::cross(n0, a)), t2 = glm::cross(n0, t1);
        const glm::dvec3 n = m.normals[i];
        bad_unit += std::abs(glm::length(n) - 1.0) < 1e-12 ? 0 : 1;
        for (const glm::dvec3& tg : {l * t1, l * t2}) {
            const double c = std::abs(glm::dot(n, glm::normalize(tg)));
            worst = std::max(worst, c);
            bad_perp += c < 1e-12 ? 0 : 1;
        }
        bad_pos += glm::length(m.positions[i] - glm::dvec3(t * glm::dvec4(before.positions[i], 1.0))) < 1e-12 ? 0 : 1;
        // Still outward: the ellipsoid's normal has a positive component along the centred position.
        CHECK(glm::dot(n, m.positions[i] - glm::dvec3(1, -2, 3)) > 0.0);
    }
    INFO("worst |cos(normal, tangent)| " << worst);
    CHECK(bad_unit == 0);
    CHECK(bad_perp == 0);
    CHECK(bad_pos == 0);
}

TEST_CASE("mesh: sampler edge cases and uniformity on a quad", "[mesh]") {
    const Mesh q = make_quad(1.0);
    const std::size_t n = 40000;
    const FragmentBuffer s = sample_surface(q, n, 11);
    REQUIRE(s.size() == n);
    CHECK(s.width == 0);
    CHECK(s.height == 0);
    CHECK(s.triangle.empty());
    // Uniform on [-1, 1]^2: mean 0 with sigma 1/sqrt(3 n) per axis; a quarter of the points per quadrant.
    double mx = 0.0, my = 0.0;
    std::size_t q1 = 0, outside = 0, bad = 0;
    for (std::size_t i = 0; i < n; ++i) {
        mx += s.px[i] / double(n);
        my += s.py[i] / double(n);
        q1 += (s.px[i] > 0.0f && s.py[i] > 0.0f) ? 1 : 0;
        outside += (std::abs(s.px[i]) > 1.0f || std::abs(s.py[i]) > 1.0f || s.pz[i] != 0.0f) ? 1 : 0;
        bad += (s.nx[i] != 0.0f || s.ny[i] != 0.0f || s.nz[i] != 1.0f || s.pixel[i] != -1 || s.depth[i] != 0.0f) ? 1 : 0;
    }
    const double sigma = 1.0 / std::sqrt(3.0 * double(n));
    INFO("mean (" << mx << ", " << my << "), sigma " << sigma << ", first quadrant " << q1 << " of " << n);
    CHECK(std::abs(mx) < 4.0 * sigma);
    CHECK(std::abs(my) < 4.0 * sigma);
    CHECK(std::abs(double(q1) / double(n) - 0.25) < 4.0 * std::sqrt(0.25 * 0.75 / double(n)));
    CHECK(outside == 0);
    CHECK(bad == 0);

    // A prefix property: the first k samples do not depend on how many are asked for.
    const FragmentBuffer few = sample_surface(q, 100, 11);
    for (std::size_t i = 0; i < few.size(); ++i) {
        INFO("sample " << i);
        CHECK(few.px[i] == s.px[i]);
        CHECK(few.py[i] == s.py[i]);
    }

    CHECK(sample_surface(q, 0, 1).empty());

    // A hand-built mesh without per-vertex normals samples with its face normal.
    Mesh bare;
    bare.positions = {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}};   // normal -x
    bare.triangles = {{0, 1, 2}};
    const FragmentBuffer b = sample_surface(bare, 50, 2);
    for (std::size_t i = 0; i < b.size(); ++i) CHECK(b.nx[i] == -1.0f);

    Mesh none;
    none.source = "nothing";
    CHECK_THROWS_WITH(sample_surface(none, 10), Catch::Contains("nothing"));
    Mesh flat;
    flat.source = "flat";
    flat.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    flat.normals.assign(3, glm::dvec3(0, 0, 1));
    flat.triangles = {{0, 1, 2}};
    CHECK_THROWS_AS(sample_surface(flat, 10), Error);
    Mesh broken = flat;
    broken.triangles = {{0, 1, 7}};
    CHECK_THROWS_AS(sample_surface(broken, 10), Error);
}
