// The domain of a fit: the (N, L, V, P) samples on which a model is compared with its target, and how the
// model's values at them combine into the compared outputs.
//
// Default (`hemisphere`, issue 11): N = +z, L and V each uniform in solid angle over the upper hemisphere
// (cos theta uniform in [0, 1], azimuth uniform), every output the shaded value of one sample for a unit light
// (what the kernel returns, per channel). The points are a randomised quasi-random sequence: Halton in bases
// 2, 3, 5, 7 shifted modulo 1 by a random vector drawn from the seed (Cranley & Patterson 1976), so each point
// is uniform on the domain and the set covers it more evenly than independent draws; V's azimuth is L's plus a
// coordinate of its own, so the azimuth difference (all an isotropic model sees) is low-discrepancy too.
// Measured: minnaert_1941 fitted to oren_nayar sigma 0.4, k over seeds 1-4 spread by 2e-4 at 65536 samples
// (the default) and 7e-4 at 16384 (tests/test_fit.cpp holds 1e-3 over three seeds).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "models/material.hpp"

namespace shadelab::fit {

struct Domain {
    std::string name;          // "hemisphere", "hemisphere, phase 30 deg", ...
    std::string description;   // one line: sample count, distribution, seed
    std::size_t seed = 0;
    std::vector<glm::dvec3> N, L, V, P;
    std::size_t size() const { return N.size(); }

    // Scene domains: the compared outputs are the rendered colours of fragments, each the sum over its
    // `per_group` samples (one per light) of weight (light colour x intensity x attenuation, per channel) times
    // the model's value, plus ambient x albedo; three outputs (r, g, b) per fragment, fragment after fragment.
    // Empty `weight`: every output is one sample's value (the hemisphere).
    std::vector<glm::dvec3> weight;
    std::size_t per_group = 1;
    glm::dvec3 ambient{0.0};
    bool grouped() const { return !weight.empty(); }
    std::size_t outputs() const { return grouped() ? 3 * (size() / per_group) : size(); }
    // Outputs from the model's grey values at every sample (size() of them) and its grey albedo.
    std::vector<double> combine(const double* values, double albedo) const;
    // The first `samples` samples (whole groups) as a domain of their own.
    Domain prefix(std::size_t samples) const;
};

// Appends one rendered fragment to a scene-like domain: a sample per light (N unit, V = normalize(eye - P), L
// and the weight colour x intensity x attenuation from ref::light_incident), as the shading kernel sees it.
void add_fragment(Domain& d, const glm::dvec3& P, const glm::dvec3& N, const glm::dvec3& eye,
                  const std::vector<Light>& lights);

struct HemisphereOptions {
    std::size_t samples = 65536;
    std::uint64_t seed = 1;
    bool has_phase = false;   // only pairs with angle(L, V) = phase_deg
    double phase_deg = 0.0;
    bool at_normal = false;   // V = N (the view-on-normal slice); L as above
    double min_cos = 0.0;     // keep only NoL >= min_cos and NoV >= min_cos (0: the whole hemisphere)
};

// Throws shadelab::Error on a sample count outside [64, 4194304], a phase outside [0, 180] or a min_cos
// outside [0, 1).
Domain hemisphere_domain(const HemisphereOptions& o);

// The samples of `d` with NoL >= c and NoV >= c (the limb check); `kept` gets their indices in `d`.
Domain grazing_cut(const Domain& d, double c, std::vector<std::size_t>* kept = nullptr);

// The fragments a scene file produces (its meshes, camera, size and lights, nearest surface per pixel as the
// batch renderer composes them), in an order shuffled by `seed` (so that any prefix covers the whole image),
// one sample per fragment and light. Throws shadelab::Error naming the file when it has no light or no
// fragment.
Domain scene_domain(const std::string& scene_file, std::uint64_t seed = 1);

// A disc image (moon fit's geometry: centre and radius in pixels, phase and position angle of the sun): one
// sample per disc pixel with alpha > 0 (moon::disc_pixels: N the unit sphere under the pixel centre, L to the
// sun, V = +z), and `values` the pixel intensities (the mean of the colour channels), the fit's target.
struct DiscImageOptions {
    std::string image;
    double cx = -1.0, cy = -1.0, radius = -1.0;   // < 0: the image centre, 0.45 of the smaller side
    double phase_deg = 0.0, pa_deg = 0.0;
};
Domain disc_image_domain(const DiscImageOptions& o, std::vector<double>& values);

// An image the batch renderer wrote with its AOVs (docs/batch.md, `outputs`): the linear colour EXR
// (outputs.exr) is the target, three outputs (r, g, b) per pixel covered in it and in the AOVs; the geometry
// comes from the normal AOV (outputs.normal: world-space N, alpha = coverage) and the depth AOV (outputs.depth:
// view-space depth along the camera axis), which with the scene's camera gives the position P on the pixel
// centre's ray; V = normalize(eye - P); the scene's lights (one sample per pixel and light, weighted by colour x
// intensity x attenuation at P) and ambient. The scene file says camera, size, lights and ambient: the AOVs
// hold no camera. Empty `normal` / `depth`: the scene's own outputs.normal / outputs.depth, resolved against
// the colour image's folder (where `shadelab batch -o DIR` put them). Throws shadelab::Error with one line
// naming the file for a missing AOV, an image that is not one (wrong channel count, non-unit normals, negative
// depth), sizes that differ from each other or from the scene's, a non-finite pixel, or fewer than 64 pixels.
struct AovImageOptions {
    std::string image;    // linear colour EXR
    std::string scene;    // the scene file it was rendered from
    std::string normal;   // normal AOV (empty: the scene's outputs.normal next to the image)
    std::string depth;    // depth AOV (empty: the scene's outputs.depth next to the image)
};
Domain aov_image_domain(const AovImageOptions& o, std::vector<double>& values);

// Angles of sample i for reports, degrees: theta_i = angle(N, L), theta_r = angle(N, V), phase = angle(L, V),
// dphi = azimuth difference of L and V about N (0 when either is along N).
struct SampleAngles {
    double theta_i = 0, theta_r = 0, phase = 0, dphi = 0, NoL = 0, NoV = 0;
};
SampleAngles angles_of(const Domain& d, std::size_t i);

}  // namespace shadelab::fit
