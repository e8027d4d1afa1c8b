// The fragment buffer: what the rasteriser (or the surface sampler) hands to the shading kernels.
// Structure of arrays, float32, so each field is one contiguous OpenCL buffer and the kernel's loads vectorise.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace shadelab {

struct FragmentBuffer {
    int width = 0;   // image size the pixel indices refer to; 0 for surface samples (no image)
    int height = 0;

    std::vector<float> px, py, pz;   // world-space position
    std::vector<float> nx, ny, nz;   // world-space shading normal, unit length
    std::vector<int32_t> pixel;      // y * width + x (y = 0 is the top row); -1 for surface samples
    std::vector<float> depth;        // view-space distance along the camera axis (positive); 0 for samples

    // Filled by rasterize() only (empty for surface samples and hand-built buffers): the mesh triangle
    // each fragment lies on and its perspective-correct barycentric weights of that triangle's vertices
    // 1 and 2 (vertex 0's is 1 - b1 - b2). Per-vertex (Gouraud) evaluation interpolates with these.
    std::vector<std::int32_t> triangle;
    std::vector<float> b1, b2;

    std::size_t size() const { return px.size(); }
    bool empty() const { return px.empty(); }

    void clear() {
        px.clear(); py.clear(); pz.clear();
        nx.clear(); ny.clear(); nz.clear();
        pixel.clear(); depth.clear();
        triangle.clear(); b1.clear(); b2.clear();
    }
    void reserve(std::size_t n) {
        px.reserve(n); py.reserve(n); pz.reserve(n);
        nx.reserve(n); ny.reserve(n); nz.reserve(n);
        pixel.reserve(n); depth.reserve(n);
    }
    void resize(std::size_t n) {
        px.resize(n); py.resize(n); pz.resize(n);
        nx.resize(n); ny.resize(n); nz.resize(n);
        pixel.resize(n); depth.resize(n);
    }
    void push_back(float x, float y, float z, float n_x, float n_y, float n_z, int32_t pix, float d) {
        px.push_back(x); py.push_back(y); pz.push_back(z);
        nx.push_back(n_x); ny.push_back(n_y); nz.push_back(n_z);
        pixel.push_back(pix); depth.push_back(d);
    }
};

}  // namespace shadelab
