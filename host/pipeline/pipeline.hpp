// The one render path: meshes in world space -> raster -> shade -> resolve -> write.
//
//   raster   each mesh rasterised with the job's camera, the fragments merged by depth (nearest per pixel,
//            ties: the earlier mesh)
//   shade    each mesh's fragments with its material, per pixel or per vertex (Gouraud), one launch per mesh
//   resolve  the colour planes composed over the background into images, plus the AOVs (depth, normal)
//   write    every image written atomically (write_image)
//
// `render`, `batch` (one Job per scene), `contact`, the planner's renders (host/plan/plan_job.hpp plans a Job),
// `moon render` and `chart` describe what they want as a Job and run these stages; each stage adds its time to StageTimes (load is the caller's: parsing a
// scene, loading meshes). Batch runs the stages of neighbouring jobs on different threads; run_job chains them.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "core/fragment_buffer.hpp"
#include "image/image.hpp"
#include "mesh/mesh.hpp"
#include "models/material.hpp"
#include "cl/runtime.hpp"
#include "raster/camera.hpp"
#include "shade/shader.hpp"

namespace shadelab::pipeline {

// Milliseconds spent in each stage (summed over the meshes of a job, or over jobs).
struct StageTimes {
    double load_ms = 0.0;      // the caller's: scene parsing, mesh loading and transforming
    double raster_ms = 0.0;
    double build_ms = 0.0;     // program builds inside shading (0 when every program was cached)
    double kernel_ms = 0.0;    // device time of the shading kernels (profiling events)
    double interpolate_ms = 0.0;   // per vertex: interpolating the vertex colours to the fragments (host)
    double shade_ms = 0.0;     // wall time of shading: build + upload + kernel + download (+ interpolation)
    double resolve_ms = 0.0;   // composing the images and AOVs (a PNG composed in its write counts in write_ms)
    double write_ms = 0.0;
    double plan_ms = 0.0;      // --tolerance: planning (apart from the stages)
    StageTimes& operator+=(const StageTimes& o);
};
// "load 1.2 ms, raster 3.4 ms, build 0 ms, kernel 5.6 ms, resolve 0.7 ms, write 8.9 ms" (plus "plan .. ms"
// when a plan was made, and "(shade wall 6.1 ms)").
std::string describe(const StageTimes& t);

struct JobMesh {
    Mesh mesh;                 // world space
    Material material;         // resolved
    bool cull_backfaces = false;
};

// Where the images of a job go (empty: not written).
struct JobOutputs {
    std::vector<std::string> colour;   // colour + coverage alpha, any format write_image takes (.png sRGB, .exr ...)
    std::string depth;                 // linear float, one channel: view-space depth, 0 where no surface
    std::string normal;                // linear float RGBA: world-space normal xyz, alpha = coverage
    std::vector<std::string> all() const;
};

// One render: everything the stages need, however the command described it.
struct Job {
    std::vector<JobMesh> meshes;
    Camera camera;
    int width = 512, height = 512;
    std::vector<Light> lights;
    glm::dvec3 ambient{0.0};
    glm::dvec4 background{0.0, 0.0, 0.0, 0.0};
    Precision precision = Precision::Precise;
    bool per_vertex = false;           // shade the vertices and interpolate (Gouraud) instead of per pixel
    // raster() fills the fragments' triangle ids and barycentrics (RasterOptions::triangle_ids), which per-vertex
    // shading needs; a caller that knows the frame will be shaded per pixel only sets it false.
    bool triangle_ids = true;
    // Orthographic views (the moon disc): the direction to the viewer, the same for every fragment, when its
    // length is > 0; else the viewer is at the camera's eye.
    glm::dvec3 view_direction{0.0};
    JobOutputs outputs;
    int raster_threads = 0;            // 0: all hardware threads
};

// The job's view as ShadeSetup::view takes it: the direction to the viewer (w = 0) for an orthographic job, else
// the camera's eye (w = 1).
glm::dvec4 shade_view(const Job& job);

// The fragments of a job: nearest per pixel over all meshes, and which mesh each came from.
struct Frame {
    FragmentBuffer fb;
    std::vector<std::uint16_t> mesh_of;
};

Frame raster(const Job& job, StageTimes& times);
// Three planes of n floats (all red, all green, all blue) for the n fragments of `frame`. Errors name the mesh.
std::vector<float> shade(Shader& shader, const Job& job, const Frame& frame, StageTimes& times);
// The colour image: the planes composed over the job's background (coverage alpha).
Image compose(const Job& job, const Frame& frame, const std::vector<float>& rgb, StageTimes& times);
// One image to write: linear floats, or, when every colour output is an 8-bit format, the colour image coded
// (srgb8 non-empty), which costs a quarter of the float image's memory.
struct OutputImage {
    std::string path;
    Image linear;
    Srgb8Image srgb8;
};
// The images the job's outputs ask for, in output order (colour outputs, then depth, then normal).
std::vector<OutputImage> resolve(const Job& job, const Frame& frame, const std::vector<float>& rgb, StageTimes& times);
void write(const std::vector<OutputImage>& images, StageTimes& times);
// write(resolve(...)), except that colour outputs which are all PNGs deflated in pieces (png_composed_in_pieces)
// are composed inside their write (write_image_composed): no colour image is held, and the composing counts in
// write_ms, not resolve_ms. For a process that writes its images at once (render); batch keeps resolve and write
// apart, to write one job's images while it shades the next.
void resolve_and_write(const Job& job, const Frame& frame, const std::vector<float>& rgb, StageTimes& times);

// The four stages in a row; returns the number of fragments.
struct JobRun {
    std::size_t fragments = 0;
    StageTimes times;
};
JobRun run_job(Shader& shader, const Job& job, StageTimes times = {});

}  // namespace shadelab::pipeline
