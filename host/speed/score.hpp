// Scoring one model x precision mode: its kernel's speed (fragments per second) and its error against the
// double-precision reference (host/reference) on rendered views of real meshes.
//
// Speed: the kernel's device time (ShadeTiming::kernel_ms, profiling events; best of `timing_repeats` runs)
// over a buffer of at least `timed_fragments` fragments: the views' own fragments repeated. Upload and
// download are not counted.
// Error: the kernel's image against the reference image of the same fragments (ref::shade_point on the
// float fragment positions and normals), compared with compare_images (host/color): CIEDE2000 mean / p99 /
// max over covered pixels, and relative error |kernel - ref| / ref per channel on linear values where the
// reference channel is >= `rel_floor` (absolute, linear; a white Lambert surface facing a unit light is 1).
// The views are placed side by side in one image, so the p99 is over the pixels of all views together.
#pragma once
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "cl/runtime.hpp"
#include "color/image_compare.hpp"
#include "image/image.hpp"
#include "mesh/mesh.hpp"
#include "models/material.hpp"
#include "raster/camera.hpp"
#include "shade/shader.hpp"

namespace shadelab::speed {

// One mesh seen from one camera at the chart's resolution.
struct ScoreView {
    std::string name;          // the mesh's file name, for labels
    Mesh mesh;
    Camera camera;
    FragmentBuffer fragments;  // rasterize(mesh, camera) at the chart's size
};

// Frames `mesh` from direction `view_from` (Camera::fit, 35 deg) and rasterises it at width x height.
ScoreView make_view(const std::string& name, const Mesh& mesh, const glm::dvec3& view_from, int width, int height);

// The chart's lights: a white key light from above the camera's side and a dimmer warm fill from the left
// (both directional, so the scene does not depend on the mesh's scale), relative to `view_from`.
std::vector<Light> chart_lights(const glm::dvec3& view_from);

// The material a model is charted with: its catalogue defaults, albedo (0.9, 0.5, 0.25), specular (1, 1, 1).
// Models that blend children (gradient) get two Lambert children, albedo (0.85, 0.35, 0.2) and
// (0.2, 0.45, 0.85), as on the contact sheet.
Material chart_material(const std::string& model);


struct Score {
    std::string model;
    Precision precision = Precision::Precise;
    double kernel_ms = 0.0;          // best of the timing runs
    std::size_t timed_fragments = 0;
    double fragments_per_s = 0.0;
    DiffFigures error;
};

struct ScoreOptions {
    std::vector<Light> lights;
    glm::dvec3 ambient{0.03};
    std::size_t timed_fragments = std::size_t(1) << 20;
    int timing_repeats = 3;
    double rel_floor = 1e-3;
};


class Scorer {
public:
    Scorer(Runtime& runtime, std::vector<ScoreView> views, ScoreOptions options);

    Score score(const Material& material, Precision precision);

    // Kernel device time over the timing buffer, best of `timing_repeats` runs (ms). score() calls it once;
    // callers may call it again later (another round) and keep the minimum, so that a burst of load from
    // other processes while one model is timed does not decide its place on the chart.
    double time_kernel(const Material& material, Precision precision);

    const std::vector<ScoreView>& views() const { return views_; }
    std::size_t timed_fragments() const { return timing_.size(); }
    int atlas_width() const;
    int atlas_height() const;

    // The views side by side (transparent background), shaded by the kernel or by the reference.
    Image kernel_image(const Material& material, Precision precision);
    const Image& reference_image(const Material& material);   // cached per model name

private:
    Runtime& rt_;
    Shader shader_;
    std::vector<ScoreView> views_;
    ScoreOptions opt_;
    FragmentBuffer timing_;
    std::map<std::string, Image> reference_cache_;
    Image atlas(const std::vector<std::vector<float>>& planes) const;
};

}  // namespace shadelab::speed
