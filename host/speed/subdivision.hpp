// Error against tessellation and against where the model is evaluated (per pixel, or per vertex and
// interpolated: host/shade/gouraud.hpp), for the analytic sphere and for a real mesh.
//
//  - Sphere: make_icosphere(level), rendered by the kernel, against the *exact* sphere: every pixel's ray
//    is intersected with the unit sphere in double and shaded by ref::shade_point with N = P. Per-pixel
//    error therefore includes the facets' geometric error (position on the flat facet, interpolated normal).
//  - Real mesh: Loop subdivision (OpenMesh's LoopT) of the mesh `level` times, against the double reference
//    on the fragments of the mesh subdivided `reference_level` times (the finest surface computed, standing
//    in for the limit surface). Normals of every level, 0 included, are OpenMesh's update_normals().
// Pixels covered in only one of the two images (the silhouette moves with the tessellation) are not
// compared; their count is reported.
#pragma once
#include <string>
#include <vector>

#include "cl/runtime.hpp"
#include "mesh/mesh.hpp"
#include "speed/score.hpp"

namespace shadelab::speed {

// The mesh Loop-subdivided (Loop 1987, OpenMesh::Subdivider::Uniform::LoopT) `times` times, with vertex
// normals recomputed by OpenMesh. times = 0 returns the mesh with those recomputed normals.
Mesh loop_subdivide(const Mesh& mesh, int times);

struct SubdivisionRow {
    std::string surface;       // "icosphere" or the mesh's file name
    std::string reference;     // what the error is measured against: "exact sphere" or "Loop level N"
    int level = 0;
    std::size_t triangles = 0, vertices = 0;
    std::string model;
    bool per_vertex = false;
    DiffFigures error;
};

struct SubdivisionOptions {
    int width = 256, height = 256;
    glm::dvec3 view_from{0.0, 0.25, 1.0};
    std::vector<Light> lights;
    glm::dvec3 ambient{0.03};
    double rel_floor = 1e-3;
};

// Rows for each model x level x {per pixel, per vertex}, precise kernels.
std::vector<SubdivisionRow> sphere_subdivision(Runtime& rt, const std::vector<std::string>& models,
                                               const std::vector<int>& levels, const SubdivisionOptions& o);
std::vector<SubdivisionRow> mesh_subdivision(Runtime& rt, const std::string& name, const Mesh& mesh,
                                             const std::vector<std::string>& models, const std::vector<int>& levels,
                                             int reference_level, const SubdivisionOptions& o);

}  // namespace shadelab::speed
