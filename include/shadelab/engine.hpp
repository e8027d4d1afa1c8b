// The OpenCL side: one Engine holds the PoCL context, the program cache and the queue. Create one and reuse it
// (the first use of a model builds its program; later uses are cached).
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "shadelab/types.hpp"

namespace shadelab::api {

struct RenderOptions {
    int width = 512, height = 512;
    Material material;
    std::vector<Light> lights;             // empty: one white directional light from (1, 1, 1)
    Vec3 ambient{0.0, 0.0, 0.0};
    Vec3 view_from{0.0, 0.25, 1.0};        // the camera frames the mesh from this direction
    double fov_deg = 35.0;
    std::array<double, 4> background{0.0, 0.0, 0.0, 0.0};
    bool fast = false;                     // fast precision mode (docs/precision.md)
    bool cull_backfaces = false;
};

class Engine {
public:
    Engine();   // the first CPU device of PoCL (SHADELAB_CL_PLATFORM / SHADELAB_CL_DEVICE choose another)
    ~Engine();
    Engine(const Engine&) = delete;
    Engine& operator=(const Engine&) = delete;

    // The OpenCL device in use, as one line.
    std::string device() const;

    // The folder the OpenCL kernels are read from (beside the installed library, or SHADELAB_KERNELS).
    std::string kernel_dir() const;

    // The material's model at n direction triples: N, L, V hold 3n floats each (xyz interleaved, unit
    // vectors); writes 3n floats of rgb to `out`: the value for a unit white light.
    void shade(const Material& material, const float* N, const float* L, const float* V, std::size_t n, float* out,
               bool fast = false);

    // Loads a mesh file (OBJ, OFF, PLY, STL), rasterises it and shades every pixel: an RGBA image.
    Image render(const std::string& mesh_file, const RenderOptions& options);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace shadelab::api
