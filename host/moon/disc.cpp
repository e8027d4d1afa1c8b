#include "moon/disc.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "core/error.hpp"
#include "core/format.hpp"
#include "mesh/mesh.hpp"
#include "pipeline/pipeline.hpp"
#include "raster/raster.hpp"
#include "shade/shader.hpp"

namespace shadelab::moon {

namespace {
// A standard normal deviate from two uniform doubles (Box-Muller): the same numbers on every platform for a
// given seed, which std::normal_distribution does not promise.
double gaussian(std::mt19937_64& g) {
    const double u1 = (double(g() >> 11) + 0.5) * (1.0 / 9007199254740992.0);
    const double u2 = double(g() >> 11) * (1.0 / 9007199254740992.0);
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}
}  // namespace

bool sphere_point(const Disc& d, double x, double y, glm::dvec3& N) {
    const double X = (x - d.cx) / d.radius, Y = (d.cy - y) / d.radius;
    const double r2 = X * X + Y * Y;
    if (!(r2 < 1.0)) return false;
    N = {X, Y, std::sqrt(1.0 - r2)};
    return true;
}

double check_disc(const Disc& d, int width, int height, bool allow_partial) {
    if (width < 1 || height < 1) throw Error("the image is empty (" + std::to_string(width) + "x" + std::to_string(height) + ")");
    if (!std::isfinite(d.cx) || !std::isfinite(d.cy)) throw Error("disc centre is not a finite pixel position");
    if (!std::isfinite(d.radius) || d.radius < 2.0)
        throw Error("disc radius " + num(d.radius) + " px is too small: it must be at least 2 pixels");
    if (d.cx < 0.0 || d.cx > width || d.cy < 0.0 || d.cy > height)
        throw Error("disc centre (" + num(d.cx) + ", " + num(d.cy) + ") is outside the " + std::to_string(width) +
                    "x" + std::to_string(height) + " image (pixel (i, j) is centred at (i + 0.5, j + 0.5))");
    const bool whole = d.cx - d.radius >= 0.0 && d.cx + d.radius <= width && d.cy - d.radius >= 0.0 &&
                       d.cy + d.radius <= height;
    if (whole) return 1.0;
    if (!allow_partial)
        throw Error("disc of radius " + num(d.radius) + " px at (" + num(d.cx) + ", " + num(d.cy) +
                    ") extends past the edge of the " + std::to_string(width) + "x" + std::to_string(height) +
                    " image: check the radius, or pass --allow-partial for a cropped disc");
    // Fraction of the disc's pixel centres that fall on the image.
    std::size_t in = 0, all = 0;
    const int step = std::max(1, int(d.radius / 200.0));
    for (int j = int(std::floor(d.cy - d.radius)); j <= int(std::ceil(d.cy + d.radius)); j += step)
        for (int i = int(std::floor(d.cx - d.radius)); i <= int(std::ceil(d.cx + d.radius)); i += step) {
            glm::dvec3 N;
            if (!sphere_point(d, i + 0.5, j + 0.5, N)) continue;
            ++all;
            if (i >= 0 && i < width && j >= 0 && j < height) ++in;
        }
    return all ? double(in) / double(all) : 0.0;
}

FragmentBuffer analytic_disc_fragments(int width, int height, const Disc& d) {
    FragmentBuffer fb;
    fb.width = width;
    fb.height = height;
    const int j0 = std::max(0, int(std::floor(d.cy - d.radius))), j1 = std::min(height - 1, int(std::ceil(d.cy + d.radius)));
    const int i0 = std::max(0, int(std::floor(d.cx - d.radius))), i1 = std::min(width - 1, int(std::ceil(d.cx + d.radius)));
    for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
            glm::dvec3 N;
            if (!sphere_point(d, i + 0.5, j + 0.5, N)) continue;
            // P = N on the unit sphere; depth: distance below the sub-observer point.
            fb.push_back(float(N.x), float(N.y), float(N.z), float(N.x), float(N.y), float(N.z), j * width + i,
                         float(1.0 - N.z));
        }
    return fb;
}

namespace {
// The job a disc is: one sphere (the icosphere, or no mesh for the analytic normals), the sun, an orthographic
// view from the observer.
pipeline::Job disc_job(int width, int height, const Disc& d) {
    pipeline::Job job;
    job.width = width;
    job.height = height;
    // The camera looks along -z at the point of the z = 0 plane that must appear at the image centre, so the
    // sphere's centre lands on (cx, cy). Pixels per world unit on that plane: R (the disc radius in pixels).
    const double D = kDistantEye;
    Camera& cam = job.camera;
    const double tx = (0.5 * width - d.cx) / d.radius, ty = (d.cy - 0.5 * height) / d.radius;
    cam.target = {tx, ty, 0.0};
    cam.eye = {tx, ty, D};
    cam.up = {0.0, 1.0, 0.0};
    cam.fov_y_deg = 2.0 * std::atan(0.5 * height / (d.radius * D)) / kDeg;
    cam.z_near = D - 2.0;
    cam.z_far = D + 2.0;
    job.meshes.emplace_back();
    return job;
}
}  // namespace

FragmentBuffer mesh_disc_fragments(int width, int height, const Disc& d, int level, std::size_t* triangles) {
    if (level < 0 || level > 8) throw Error("icosphere level " + std::to_string(level) + " must be in [0, 8]");
    pipeline::Job job = disc_job(width, height, d);
    job.meshes.front().mesh = make_icosphere(level);
    if (triangles) *triangles = job.meshes.front().mesh.triangles.size();
    pipeline::StageTimes times;
    return pipeline::raster(job, times).fb;
}

namespace {
Disc checked_disc(const DiscRenderOptions& o) {
    if (o.width < 8 || o.height < 8 || o.width > 16384 || o.height > 16384)
        throw Error("disc image size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                    " must be between 8x8 and 16384x16384");
    Disc d = o.disc;
    if (!(d.radius > 0.0)) d = Disc{0.5 * o.width, 0.5 * o.height, 0.45 * std::min(o.width, o.height)};
    check_disc(d, o.width, o.height, true);
    if (!std::isfinite(o.limb_mask_mu) || o.limb_mask_mu < 0.0 || o.limb_mask_mu >= 1.0)
        throw Error("limb mask mu " + num(o.limb_mask_mu) + " must be in [0, 1)");
    if (!std::isfinite(o.noise_sigma) || o.noise_sigma < 0.0)
        throw Error("noise sigma " + num(o.noise_sigma) + " must be finite and >= 0");
    return d;
}

// Noise and statistics on the shaded planes (r, g, b of n fragments), shared by both renderers.
void finish(const DiscRenderOptions& o, const std::vector<double>& mu, std::vector<float>& rgb, DiscRenderReport& rep,
            const std::string& what) {
    const std::size_t n = mu.size();
    if (o.noise_sigma > 0.0) {
        std::mt19937_64 g(o.noise_seed);
        for (std::size_t i = 0; i < n; ++i) {
            const double e = o.noise_sigma * gaussian(g);   // the same noise in r, g, b: a grey detector
            for (int c = 0; c < 3; ++c) rgb[std::size_t(c) * n + i] = float(double(rgb[std::size_t(c) * n + i]) + e);
        }
    }
    rep.pixels = n;
    for (std::size_t i = 0; i < n; ++i) {
        rep.min_mu = std::min(rep.min_mu, mu[i]);
        if (mu[i] < 0.01) ++rep.limb_pixels;
        if (mu[i] < 1e-3) ++rep.guard_pixels;
        for (int c = 0; c < 3; ++c) {
            const float v = rgb[std::size_t(c) * n + i];
            if (!std::isfinite(v)) throw Error("internal: " + what + " returned a non-finite value");
            rep.max_value = std::max(rep.max_value, double(v));
        }
    }
}
}  // namespace

Image render_law_disc(const DiscRenderOptions& o, const PhotometricModel& law, DiscRenderReport* report) {
    const Disc d = checked_disc(o);
    DiscRenderReport rep;
    rep.method = "closed form " + law.describe() + " in double at pixel centres (no kernel)";
    FragmentBuffer fb = analytic_disc_fragments(o.width, o.height, d);
    FragmentBuffer kept;
    kept.width = fb.width;
    kept.height = fb.height;
    std::vector<double> mu;
    std::vector<double> value;
    for (std::size_t i = 0; i < fb.size(); ++i) {
        glm::dvec3 N;
        sphere_point(d, fb.pixel[i] % o.width + 0.5, fb.pixel[i] / o.width + 0.5, N);
        if (N.z < o.limb_mask_mu) { ++rep.masked; continue; }
        kept.push_back(fb.px[i], fb.py[i], fb.pz[i], fb.nx[i], fb.ny[i], fb.nz[i], fb.pixel[i], fb.depth[i]);
        mu.push_back(N.z);
        value.push_back(law.value(N, o.sun));
    }
    if (kept.empty()) throw Error("no pixel of the disc is left to draw");
    const std::size_t n = kept.size();
    std::vector<float> rgb(3 * n);
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) rgb[std::size_t(c) * n + i] = float(value[i]);
    finish(o, mu, rgb, rep, "the law " + law.describe());
    if (report) *report = rep;
    return compose_image(kept, rgb, o.background);
}

Image render_disc(Runtime& rt, const DiscRenderOptions& o, DiscRenderReport* report, FragmentBuffer* fragments_out) {
    const Disc d = checked_disc(o);

    DiscRenderReport rep;
    FragmentBuffer fb;
    if (o.mesh_level < 0) {
        fb = analytic_disc_fragments(o.width, o.height, d);
        rep.method = "analytic sphere normals (orthographic rays through pixel centres)";
    } else {
        fb = mesh_disc_fragments(o.width, o.height, d, o.mesh_level, &rep.triangles);
        rep.method = "icosphere(" + std::to_string(o.mesh_level) + "), " + std::to_string(rep.triangles) +
                     " triangles, camera " + num(kDistantEye) + " radii away (near-orthographic)";
    }
    if (fb.empty()) throw Error("the disc covers no pixel of the " + std::to_string(o.width) + "x" + std::to_string(o.height) + " image");

    // The sphere's own mu at each pixel centre: what the limb statistics and the mask use.
    std::vector<double> mu(fb.size(), 0.0);
    for (std::size_t i = 0; i < fb.size(); ++i) {
        const int px = fb.pixel[i] % o.width, py = fb.pixel[i] / o.width;
        glm::dvec3 N;
        mu[i] = sphere_point(d, px + 0.5, py + 0.5, N) ? N.z : 0.0;
    }
    if (o.limb_mask_mu > 0.0) {
        FragmentBuffer kept;
        kept.width = fb.width;
        kept.height = fb.height;
        std::vector<double> kept_mu;
        for (std::size_t i = 0; i < fb.size(); ++i) {
            if (mu[i] < o.limb_mask_mu) { ++rep.masked; continue; }
            kept.push_back(fb.px[i], fb.py[i], fb.pz[i], fb.nx[i], fb.ny[i], fb.nz[i], fb.pixel[i], fb.depth[i]);
            kept_mu.push_back(mu[i]);
        }
        fb = std::move(kept);
        mu = std::move(kept_mu);
        if (fb.empty()) throw Error("the limb mask mu >= " + num(o.limb_mask_mu) + " leaves no pixel of the disc");
    }

    pipeline::Job job = disc_job(o.width, o.height, d);
    job.meshes.front().material = o.material;
    job.lights = {Light{Light::Type::Directional, o.sun.L, {1.0, 1.0, 1.0}, 1.0, 0.0}};
    job.ambient = glm::dvec3(0.0);
    job.view_direction = o.sun.V;   // orthographic: the same direction to the viewer everywhere
    job.background = o.background;
    pipeline::Frame frame;
    frame.fb = std::move(fb);
    frame.mesh_of.assign(frame.fb.size(), 0);
    Shader shader(rt);
    pipeline::StageTimes times;
    std::vector<float> rgb = pipeline::shade(shader, job, frame, times);
    rep.build_ms = times.build_ms;
    rep.kernel_ms = times.kernel_ms;

    finish(o, mu, rgb, rep, "the kernel of model '" + o.material.model + "'");
    if (report) *report = rep;
    Image img = pipeline::compose(job, frame, rgb, times);
    fb = std::move(frame.fb);
    if (fragments_out) *fragments_out = std::move(fb);
    return img;
}

}  // namespace shadelab::moon
