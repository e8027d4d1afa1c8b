// Rendered moon discs: a unit sphere lit by a distant sun, seen by a distant observer, shaded by any model
// of the catalogue with the OpenCL kernels.
//
// Two ways to get the surface (docs/moon.md, "Rendering"):
//  - analytic normals (mesh_level < 0): for every pixel whose centre (X, Y) (in disc radii, y up) lies
//    strictly inside the disc, the orthographic ray hits the unit sphere at P = (X, Y, sqrt(1 - X^2 - Y^2));
//    the normal is N = P. Exact geometry, so the rendered value differs from the model only by float rounding.
//  - an icosphere (mesh_level >= 0): make_icosphere(level) rasterised by the perspective rasteriser from a
//    camera kDistantEye radii away with a field of view so narrow that the disc has the requested radius.
//    The view is then orthographic to within 1/(2 kDistantEye) of a radius in position; the shading itself
//    uses the orthographic view direction (ShadeSetup.view with w = 0), as for the analytic disc. What
//    remains is the mesh's own error: its facets lie inside the sphere, so each pixel sees a point of a
//    facet whose interpolated normal differs from the sphere's normal under that pixel by about h tan(e)
//    (h <= a^2 / 6 the facet's radial gap, a its edge angle), and the silhouette is a polygon inside the circle.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "cl/runtime.hpp"
#include "core/fragment_buffer.hpp"
#include "image/image.hpp"
#include "models/material.hpp"
#include "moon/photometry.hpp"

namespace shadelab::moon {

// Distance of the camera for mesh discs, in sphere radii (see above).
constexpr double kDistantEye = 1.0e4;

// A disc on an image, in pixel units: x to the right, y down, pixel (i, j) centred at (i + 0.5, j + 0.5).
struct Disc {
    double cx = 128.0, cy = 128.0;
    double radius = 120.0;
};

// The point of the unit sphere under pixel centre (x, y) of the image (disc radii, world axes: x right, y up,
// z to the observer); false when the pixel centre is not strictly inside the disc.
bool sphere_point(const Disc& d, double x, double y, glm::dvec3& N);

// Checks a disc against an image of width x height: the radius must be finite and >= 2 px, the centre inside
// the image, and (unless allow_partial) the whole disc inside the image. Throws one clear line otherwise.
// Returns the fraction of the disc's area that falls on the image (1 when whole).
double check_disc(const Disc& d, int width, int height, bool allow_partial);

struct DiscRenderOptions {
    int width = 256, height = 256;
    Disc disc;                      // radius <= 0: 0.45 * min(width, height), centred
    Material material;              // any catalogue model; albedo grey for a moon
    SunGeometry sun;
    int mesh_level = -1;            // < 0: analytic normals; >= 0: icosphere subdivision level (<= 8)
    double limb_mask_mu = 0.0;      // pixels with mu < this are left as background (alpha 0); 0 = none
    double noise_sigma = 0.0;       // Gaussian noise added to the disc's pixels (I/F units), 0 = none
    std::uint64_t noise_seed = 1;
    glm::dvec4 background{0.0, 0.0, 0.0, 0.0};
};

struct DiscRenderReport {
    std::size_t pixels = 0;         // shaded pixels on the disc
    std::size_t masked = 0;         // pixels dropped by limb_mask_mu
    std::size_t limb_pixels = 0;    // pixels with mu < 0.01, where Minnaert k < 1 is steep (mu^(k-1))
    std::size_t guard_pixels = 0;   // pixels with mu < 1e-3: inside the Minnaert kernels' limb guard
    double min_mu = 1.0;            // smallest mu of a shaded pixel centre (sphere geometry)
    double max_value = 0.0;         // largest shaded value (after the kernel's own guards)
    std::size_t triangles = 0;      // mesh discs: triangles rasterised
    std::string method;             // "analytic normals" or "icosphere(level), camera at ... radii"
    double build_ms = 0.0, kernel_ms = 0.0;
};

// The fragments of a disc with exact sphere normals (N = P, the unit sphere at the origin).
FragmentBuffer analytic_disc_fragments(int width, int height, const Disc& d);

// The fragments of a rasterised icosphere; positions are on the mesh (inside the unit sphere).
FragmentBuffer mesh_disc_fragments(int width, int height, const Disc& d, int level, std::size_t* triangles = nullptr);

// Renders the disc: RGBA linear float, alpha 1 on shaded pixels. The shading is Shader::shade with one white
// directional light of intensity 1 towards sun.L, orthographic view V = +z: a pixel's value is the model's
// value (I/F for unit solar flux) at that pixel. Never returns NaN/Inf (the kernels write non-finite results
// as 0, and the renderer checks).
Image render_disc(Runtime& rt, const DiscRenderOptions& options, DiscRenderReport* report = nullptr,
                  FragmentBuffer* fragments_out = nullptr);

// The same disc drawn from a closed-form law (photometry.hpp: Minnaert, Lommel-Seeliger, Lunar-Lambert, ...)
// evaluated in double at each pixel centre, without the kernels: for laws that are not in the catalogue, and as
// a cross-check of the kernels. o.material is ignored; noise, mask and background apply as above.
Image render_law_disc(const DiscRenderOptions& options, const PhotometricModel& law, DiscRenderReport* report = nullptr);

}  // namespace shadelab::moon
