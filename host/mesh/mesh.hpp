// Meshes: loaded with OpenMesh (OBJ, OFF, PLY, STL), validated, normals ensured, flattened for the rasteriser.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/fragment_buffer.hpp"

namespace shadelab {

struct Bounds {
    glm::dvec3 lo{0.0}, hi{0.0};
    glm::dvec3 centre() const { return 0.5 * (lo + hi); }
    double radius() const { return 0.5 * glm::length(hi - lo); }  // bounding-sphere radius of the box
};

// A triangle mesh as the rasteriser wants it: shared vertices, unit per-vertex normals, index triples.
struct Mesh {
    std::vector<glm::dvec3> positions;
    std::vector<glm::dvec3> normals;       // one unit normal per vertex
    std::vector<glm::u32vec3> triangles;   // counter-clockwise seen from outside
    std::string source;                    // file it came from, or a description ("icosphere(4)")

    Bounds bounds() const;                 // over vertices used by triangles
    void transform(const glm::dmat4& m);   // positions by m, normals by its inverse transpose
};

// What the loader found and what it repaired, so nothing is changed silently.
struct MeshLoadReport {
    std::size_t vertices_in = 0;
    std::size_t faces_in = 0;              // faces as OpenMesh loaded them (polygons fan-triangulated)
    std::size_t triangles_out = 0;
    std::size_t degenerate_dropped = 0;    // zero-area or repeated-index triangles removed
    std::size_t unused_vertices = 0;       // vertices no triangle references (kept, ignored)
    bool normals_from_file = false;        // false: computed, area-weighted
    std::size_t normals_repaired = 0;      // file normals that were zero/NaN and were recomputed
    std::vector<std::string> notes;        // one line per repair, for the user
};

// Which mesh cache a load uses (host/mesh/mesh_cache.hpp), and what it did.
struct MeshCacheUse {
    std::string setting;        // "" = SHADELAB_MESH_CACHE, then the XDG default; "off" = none; else a folder
    // What happened (set by load_mesh):
    bool hit = false;           // the mesh and report came from the cache entry
    bool rejected = false;      // an entry was there but unusable (why): loaded from the file instead
    std::string why;
    bool written = false;       // an entry was written after loading from the file
};

// Loads OBJ, OFF, PLY or STL. Throws shadelab::Error with one clear line when the file is missing,
// unreadable, empty (no triangles left), or has NaN/Inf coordinates. Degenerate faces are dropped and
// reported. Vertex normals come from the file when present and valid, else are computed area-weighted.
// Through the mesh cache (`cache`, or the environment's when null): a file whose bytes were loaded before
// gives the same Mesh, bit for bit, and the same report, from the cache entry.
Mesh load_mesh(const std::string& path, MeshLoadReport* report = nullptr, MeshCacheUse* cache = nullptr);

// The same without the cache: always OpenMesh, the checks and the repairs.
Mesh load_mesh_uncached(const std::string& path, MeshLoadReport* report = nullptr);

// Unit-radius icosphere centred at the origin, built with OpenMesh, `subdivisions` times 4-to-1 refined
// (0 = icosahedron, 20 triangles; each level x4). Vertex normals are the exact sphere normals.
Mesh make_icosphere(int subdivisions, double radius = 1.0);

// A two-triangle quad in the plane z = 0 spanning [-half, half]^2, normal +z (known-answer scenes).
Mesh make_quad(double half_size = 1.0);

// Area-uniform random points on the surface with interpolated unit normals (no camera, no image):
// pixel = -1 and depth = 0 in the returned buffer. Deterministic for a given seed.
FragmentBuffer sample_surface(const Mesh& mesh, std::size_t count, std::uint64_t seed = 1);

}  // namespace shadelab
