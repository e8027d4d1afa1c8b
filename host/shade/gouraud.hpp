// Per-vertex (Gouraud 1971) evaluation: shade the mesh's vertices with the kernel, then interpolate the
// colours to the fragments with the rasteriser's perspective-correct barycentrics. Cheaper than per-pixel
// when vertices are fewer than fragments; wrong where the shading varies faster than the tessellation
// (highlights, terminators): its error is measured, not assumed (tests/test_gouraud.cpp, the planner).
#pragma once
#include <vector>

#include "core/fragment_buffer.hpp"
#include "mesh/mesh.hpp"
#include "shade/shader.hpp"

namespace shadelab {

// Shades every vertex of `mesh` (same planes layout as Shader::shade: r..., g..., b...).
std::vector<float> shade_vertices(Shader& shader, const Mesh& mesh, const ShadeSetup& setup, ShadeTiming* timing = nullptr);

// Interpolates per-vertex planes (3 x n_vertices) to the fragments of `fb`, which must come from
// rasterize() of the same mesh (it carries triangle ids and barycentrics). Returns 3 x n_fragments planes.
std::vector<float> interpolate_to_fragments(const FragmentBuffer& fb, const Mesh& mesh, const std::vector<float>& vertex_planes);

}  // namespace shadelab
