// Host rasteriser: mesh + camera -> fragment buffer (one fragment per covered pixel, front-most surface).
//
// Rules:
//  - pixel centres at (x + 0.5, y + 0.5); y = 0 is the top row of the image;
//  - top-left fill rule, so a pixel on an edge shared by two triangles is covered by exactly one of them;
//  - depth test (nearest wins; ties broken by the lower triangle index, so results are deterministic);
//  - near-plane clipping in clip space (triangles crossing the near plane are clipped, not dropped);
//  - perspective-correct interpolation of world position and normal (normal re-normalised);
//  - both sides of a triangle are rasterised unless cull_backfaces is set; the interpolated normal is
//    flipped to face the camera only if flip_normals_to_viewer is set (default off: shading sees the
//    mesh's own normals).
// Output fragments are ordered by pixel index, so runs are deterministic whatever the thread count.
// Work: set-up and binning in chunks of 4096 triangles; rasterisation in 128 x 64 pixel tiles (the visibility
// buffer of a tile stays in cache); emission in bands of 16-64 rows; threads take the next piece of each stage
// from a shared counter. Every pixel's result is computed the same way whatever the split: bit-identical for any
// thread count.
#pragma once
#include <cstddef>

#include "core/fragment_buffer.hpp"
#include "mesh/mesh.hpp"
#include "raster/camera.hpp"

namespace shadelab {

struct RasterOptions {
    int width = 512;
    int height = 512;
    int threads = 0;                   // 0 = all hardware threads
    bool cull_backfaces = false;
    bool flip_normals_to_viewer = false;
    // Also fill the fragments' triangle, b1 and b2 (the mesh triangle and its barycentric weights: per-vertex
    // shading interpolates with them). False leaves those three arrays empty: 12 of a fragment's 44 bytes
    // that a per-pixel frame never reads are not written. Every other array is the same either way.
    bool triangle_ids = true;
};

struct RasterStats {
    std::size_t triangles_in = 0;
    std::size_t triangles_culled = 0;  // back-facing (when culling) or fully outside the frustum
    std::size_t triangles_clipped = 0; // crossed the near plane and were clipped
    std::size_t fragments = 0;
    // Wall time of the stages (ms): validation, clip and set-up; binning and rasterising the visibility
    // buffer; emitting the fragments (interpolation).
    double setup_ms = 0, raster_ms = 0, emit_ms = 0;
};

FragmentBuffer rasterize(const Mesh& mesh, const Camera& camera, const RasterOptions& options,
                         RasterStats* stats = nullptr);
// The same fragments into `out`, reusing its arrays' memory when they are large enough (a renderer drawing
// frame after frame keeps one buffer and pays no fresh-page faults); whatever `out` held is replaced.
void rasterize_into(const Mesh& mesh, const Camera& camera, const RasterOptions& options, FragmentBuffer& out,
                    RasterStats* stats = nullptr);

}  // namespace shadelab
