#include "fit/domain.hpp"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <cmath>
#include <random>
#include <sstream>

#include "core/error.hpp"
#include "core/format.hpp"
#include "reference/reference.hpp"
#include "image/image.hpp"
#include "mesh/mesh.hpp"
#include "moon/fit.hpp"
#include "raster/raster.hpp"
#include "scene/scene.hpp"

namespace shadelab::fit {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The radical inverse of i in `base` (van der Corput): the i-th Halton coordinate.
double radical_inverse(std::uint64_t i, unsigned base) {
    double inv = 1.0 / base, f = inv, r = 0.0;
    while (i > 0) {
        r += f * double(i % base);
        i /= base;
        f *= inv;
    }
    return r;
}

// Point i of the Halton sequence in bases 2, 3, 5, 7, shifted by `shift` modulo 1 (Cranley-Patterson).
struct Qmc {
    double shift[4];
    explicit Qmc(std::uint64_t seed) {
        std::mt19937_64 rng(seed);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        for (double& s : shift) s = u(rng);
    }
    double at(std::uint64_t i, int dim) const {
        static const unsigned bases[4] = {2, 3, 5, 7};
        const double x = radical_inverse(i + 1, bases[dim]) + shift[dim];   // i + 1: skip the all-zero point
        return x - std::floor(x);
    }
};

// Uniform in solid angle over the upper hemisphere about +z: cos theta = u1, azimuth 2 pi u2.
glm::dvec3 hemisphere_dir(double u1, double u2) {
    const double c = u1, s = std::sqrt(std::max(0.0, 1.0 - c * c)), phi = 2.0 * kPi * u2;
    return {s * std::cos(phi), s * std::sin(phi), c};
}

// A unit vector at angle g from the unit vector a, at azimuth 2 pi u about it.
glm::dvec3 at_angle_from(const glm::dvec3& a, double g, double u) {
    const glm::dvec3 helper = std::abs(a.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
    const glm::dvec3 t = glm::normalize(glm::cross(helper, a)), b = glm::cross(a, t);
    const double phi = 2.0 * kPi * u;
    return glm::normalize(std::cos(g) * a + std::sin(g) * (std::cos(phi) * t + std::sin(phi) * b));
}

}  // namespace

Domain hemisphere_domain(const HemisphereOptions& o) {
    if (o.samples < 64 || o.samples > (std::size_t(1) << 22))
        throw Error("--samples " + std::to_string(o.samples) + " is out of range: use 64 to 4194304");
    if (o.has_phase && !(o.phase_deg >= 0.0 && o.phase_deg <= 180.0))
        throw Error("--phase " + num(o.phase_deg) + " is out of range: give the angle between L and V in [0, 180] degrees");
    if (!(o.min_cos >= 0.0 && o.min_cos < 1.0))
        throw Error("--min-cos " + num(o.min_cos) + " is out of range: use [0, 1)");
    if (o.has_phase && o.at_normal && o.phase_deg > 90.0)
        throw Error("--phase " + num(o.phase_deg) + " with --at-normal puts the light below the horizon: use a phase <= 90");
    Domain d;
    d.seed = o.seed;
    const Qmc q(o.seed);
    const double g = o.phase_deg * kPi / 180.0;
    const glm::dvec3 Nz(0, 0, 1);
    // Draws until `samples` pairs fall inside the domain (rejection keeps the restricted pairs uniform).
    const std::uint64_t limit = 4000 * std::uint64_t(o.samples) + 100000;
    for (std::uint64_t i = 0; d.size() < o.samples; ++i) {
        if (i > limit)
            throw Error("the fit domain is (almost) empty: fewer than " + std::to_string(o.samples) + " of " +
                        std::to_string(limit) + " draws fall inside it; relax --phase / --min-cos");
        glm::dvec3 L, V;
        if (o.at_normal) {
            V = Nz;
            L = o.has_phase ? at_angle_from(Nz, g, q.at(i, 1)) : hemisphere_dir(q.at(i, 0), q.at(i, 1));
        } else if (o.has_phase) {
            L = hemisphere_dir(q.at(i, 0), q.at(i, 3));
            V = at_angle_from(L, g, q.at(i, 2));
        } else {
            // V's azimuth is L's plus a uniform offset (so still uniform and independent of L's): the offset, the
            // one azimuth an isotropic model sees, takes a low-discrepancy coordinate of its own.
            const double phi_l = q.at(i, 3);
            L = hemisphere_dir(q.at(i, 0), phi_l);
            const double phi_v = phi_l + q.at(i, 2);
            V = hemisphere_dir(q.at(i, 1), phi_v - std::floor(phi_v));
        }
        if (V.z < 0.0 || L.z < 0.0) continue;   // a phase pair with V below the horizon
        if (L.z < o.min_cos || V.z < o.min_cos) continue;
        d.N.push_back(Nz);
        d.L.push_back(L);
        d.V.push_back(V);
        d.P.push_back(glm::dvec3(0.0));
    }
    std::ostringstream name, desc;
    name << "hemisphere";
    if (o.at_normal) name << ", view on the normal";
    if (o.has_phase) name << ", phase " << o.phase_deg << " deg";
    if (o.min_cos > 0.0) name << ", NoL, NoV >= " << o.min_cos;
    d.name = name.str();
    desc << o.samples << " samples: N = +z, ";
    if (o.at_normal) desc << "V = N, L uniform in solid angle over the upper hemisphere";
    else desc << "L and V each uniform in solid angle over the upper hemisphere";
    if (o.has_phase) desc << (o.at_normal ? " at angle " : ", restricted to angle(L, V) = ") << o.phase_deg << " deg";
    if (o.min_cos > 0.0) desc << ", NoL and NoV >= " << o.min_cos;
    desc << " (randomised Halton points, seed " << o.seed << ")";
    d.description = desc.str();
    return d;
}

Domain grazing_cut(const Domain& d, double c, std::vector<std::size_t>* kept) {
    Domain out;
    out.seed = d.seed;
    out.name = d.name + ", NoL, NoV >= " + num(c);
    if (kept) kept->clear();
    for (std::size_t i = 0; i < d.size(); ++i) {
        if (glm::dot(d.N[i], d.L[i]) < c || glm::dot(d.N[i], d.V[i]) < c) continue;
        out.N.push_back(d.N[i]);
        out.L.push_back(d.L[i]);
        out.V.push_back(d.V[i]);
        out.P.push_back(d.P[i]);
        if (kept) kept->push_back(i);
    }
    out.description = std::to_string(out.size()) + " of the " + std::to_string(d.size()) + " samples with NoL, NoV >= " + num(c);
    return out;
}

std::vector<double> Domain::combine(const double* v, double albedo) const {
    if (!grouped()) return std::vector<double>(v, v + size());
    const std::size_t F = size() / per_group;
    std::vector<double> out(3 * F);
    for (std::size_t f = 0; f < F; ++f)
        for (int c = 0; c < 3; ++c) {
            double sum = ambient[c] * albedo;
            for (std::size_t k = 0; k < per_group; ++k) sum += weight[f * per_group + k][c] * v[f * per_group + k];
            out[3 * f + c] = sum;
        }
    return out;
}

Domain Domain::prefix(std::size_t samples) const {
    Domain c;
    c.name = name;
    c.seed = seed;
    c.per_group = per_group;
    c.ambient = ambient;
    const std::size_t n = std::min(size(), samples / per_group * per_group);
    c.description = "the first " + std::to_string(n) + " of " + description;
    c.N.assign(N.begin(), N.begin() + n);
    c.L.assign(L.begin(), L.begin() + n);
    c.V.assign(V.begin(), V.begin() + n);
    c.P.assign(P.begin(), P.begin() + n);
    if (grouped()) c.weight.assign(weight.begin(), weight.begin() + n);
    return c;
}

void add_fragment(Domain& d, const glm::dvec3& P, const glm::dvec3& N, const glm::dvec3& eye,
                  const std::vector<Light>& lights) {
    const glm::dvec3 V = glm::normalize(eye - P);
    for (const Light& li : lights) {
        glm::dvec3 L;
        const double atten = ref::light_incident(li, P, L);
        d.N.push_back(N);
        d.L.push_back(L);
        d.V.push_back(V);
        d.P.push_back(P);
        d.weight.push_back(li.colour * li.intensity * atten);
    }
}

Domain scene_domain(const std::string& file, std::uint64_t seed) {
    const Scene s = load_scene(file);
    if (s.lights.empty()) throw Error("scene '" + file + "' has no light: a fit over it needs at least one");
    const SceneGeometry g = load_scene_geometry(s, [](const std::string& p) { return load_mesh(p); });
    // Nearest fragment per pixel over all meshes (ties: the earlier mesh), as the batch renderer composes them.
    const std::size_t npix = std::size_t(s.width) * std::size_t(s.height);
    std::vector<FragmentBuffer> parts;
    for (std::size_t m = 0; m < g.meshes.size(); ++m) {
        RasterOptions ro;
        ro.width = s.width;
        ro.height = s.height;
        ro.cull_backfaces = s.meshes[m].cull_backfaces;
        parts.push_back(rasterize(g.meshes[m], g.camera, ro));
    }
    std::vector<float> best(npix, std::numeric_limits<float>::infinity());
    std::vector<std::pair<std::size_t, std::size_t>> who(npix, {SIZE_MAX, 0});
    for (std::size_t m = 0; m < parts.size(); ++m)
        for (std::size_t i = 0; i < parts[m].size(); ++i) {
            const std::size_t p = std::size_t(parts[m].pixel[i]);
            if (parts[m].depth[i] < best[p]) best[p] = parts[m].depth[i], who[p] = {m, i};
        }
    std::vector<std::pair<std::size_t, std::size_t>> frags;
    for (const auto& w : who)
        if (w.first != SIZE_MAX) frags.push_back(w);
    if (frags.empty()) throw Error("scene '" + file + "': its meshes cover no pixel from its camera: nothing to fit over");
    std::mt19937_64 rng(seed);
    std::shuffle(frags.begin(), frags.end(), rng);
    Domain d;
    d.seed = seed;
    d.per_group = s.lights.size();
    d.ambient = s.ambient;
    const glm::dvec3 eye = g.camera.eye;
    for (const auto& [m, i] : frags) {
        const FragmentBuffer& f = parts[m];
        const glm::dvec3 P(f.px[i], f.py[i], f.pz[i]);
        glm::dvec3 N(f.nx[i], f.ny[i], f.nz[i]);
        N = glm::length(N) > 0 ? glm::normalize(N) : glm::dvec3(0, 0, 1);
        add_fragment(d, P, N, eye, s.lights);
    }
    d.name = "scene " + file;
    d.description = std::to_string(frags.size()) + " fragments of scene '" + file + "' (" + std::to_string(s.width) +
                    "x" + std::to_string(s.height) + ", " + std::to_string(g.meshes.size()) + " meshes, " +
                    std::to_string(s.lights.size()) + " lights), rendered colours compared per channel";
    return d;
}

Domain disc_image_domain(const DiscImageOptions& o, std::vector<double>& values) {
    const Image img = read_image(o.image);
    moon::Disc disc;
    disc.cx = o.cx >= 0.0 ? o.cx : 0.5 * img.width;
    disc.cy = o.cy >= 0.0 ? o.cy : 0.5 * img.height;
    disc.radius = o.radius > 0.0 ? o.radius : 0.45 * std::min(img.width, img.height);
    const moon::SunGeometry sun = moon::sun_geometry(o.phase_deg, o.pa_deg);
    const auto pixels = moon::disc_pixels(img, disc, sun);
    Domain d;
    values.clear();
    for (const auto& p : pixels) {
        glm::dvec3 N;
        if (!moon::sphere_point(disc, p.x + 0.5, p.y + 0.5, N)) continue;
        d.N.push_back(N);
        d.L.push_back(sun.L);
        d.V.push_back(sun.V);
        d.P.push_back(N);
        values.push_back(p.I);
    }
    if (d.size() < 64)
        throw Error("image '" + o.image + "': only " + std::to_string(d.size()) +
                    " usable disc pixels: check --centre and --radius (a fit needs at least 64)");
    std::ostringstream name;
    name << "disc image " << o.image;
    d.name = name.str();
    std::ostringstream desc;
    desc << d.size() << " disc pixels of '" << o.image << "' (centre " << disc.cx << "," << disc.cy << ", radius "
         << disc.radius << " px, phase " << o.phase_deg << " deg, position angle " << o.pa_deg
         << " deg): N the unit sphere under each pixel, V = +z, the pixel values the target";
    d.description = desc.str();
    return d;
}

namespace {

// An AOV image read and checked: the path, what it is for messages, and its pixels.
Image read_aov(const std::string& path, const std::string& what, const std::string& how) {
    if (path.empty() || !std::filesystem::exists(path))
        throw Error("fit --over: the " + what + " '" + path + "' does not exist: " + how);
    return read_image(path);
}

void check_same_size(const Image& a, const std::string& pa, const Image& b, const std::string& pb) {
    if (a.width != b.width || a.height != b.height)
        throw Error("fit --over: '" + pb + "' is " + std::to_string(b.width) + "x" + std::to_string(b.height) + " but '" +
                    pa + "' is " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                    ": give the AOVs of the same render");
}

std::string at_pixel(const std::string& path, int x, int y) {
    return "'" + path + "' pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
}

// The point at view-space depth `depth` on the ray through the centre of pixel (x, y), as the rasteriser
// places fragments: NDC x = 2 (x + 0.5) / W - 1, y = 1 - 2 (y + 0.5) / H (row 0 the top), the view-space
// direction (x tan(fov/2) aspect, y tan(fov/2), -1) has unit length along the camera axis.
glm::dvec3 point_at_depth(const Camera& cam, int W, int H, int x, int y, double depth) {
    const double t = std::tan(0.5 * cam.fov_y_deg * kPi / 180.0), aspect = double(W) / double(H);
    const double nx = 2.0 * (double(x) + 0.5) / double(W) - 1.0, ny = 1.0 - 2.0 * (double(y) + 0.5) / double(H);
    const glm::dmat3 to_world = glm::inverse(glm::dmat3(cam.view()));
    return cam.eye + depth * (to_world * glm::dvec3(nx * t * aspect, ny * t, -1.0));
}

}  // namespace

Domain aov_image_domain(const AovImageOptions& o, std::vector<double>& values) {
    SceneLoadOptions lo;
    lo.out_dir = std::filesystem::path(o.image).parent_path().string();
    if (lo.out_dir.empty()) lo.out_dir = ".";
    const Scene s = load_scene(o.scene, lo);
    if (s.lights.empty()) throw Error("scene '" + o.scene + "' has no light: a fit over its render needs at least one");
    const std::string normal_path = o.normal.empty() ? s.outputs.normal : o.normal;
    const std::string depth_path = o.depth.empty() ? s.outputs.depth : o.depth;
    const std::string render_hint = " (shadelab batch " + o.scene + " -o DIR writes it when the scene's outputs name ";
    if (normal_path.empty())
        throw Error("fit --over " + o.image + ": scene '" + o.scene + "' writes no normal AOV (outputs.normal): add one "
                    "and render again, or give --normal FILE");
    if (depth_path.empty())
        throw Error("fit --over " + o.image + ": scene '" + o.scene + "' writes no depth AOV (outputs.depth): add one "
                    "and render again, or give --depth FILE");
    const Image colour = read_aov(o.image, "image", "give the linear colour EXR the batch wrote (outputs.exr)");
    const Image normal = read_aov(normal_path, "normal AOV", "give --normal FILE" + render_hint + "\"normal\")");
    const Image depth = read_aov(depth_path, "depth AOV", "give --depth FILE" + render_hint + "\"depth\")");
    if (colour.channels < 3)
        throw Error("fit --over: '" + o.image + "' has " + std::to_string(colour.channels) +
                    " channel(s): a colour render (r, g, b) is the target, the AOVs go to --normal and --depth");
    if (normal.channels != 4)
        throw Error("fit --over: '" + normal_path + "' has " + std::to_string(normal.channels) +
                    " channel(s), not a normal AOV (the batch writes x, y, z and coverage alpha)");
    if (depth.channels != 1)
        throw Error("fit --over: '" + depth_path + "' has " + std::to_string(depth.channels) +
                    " channels, not a depth AOV (the batch writes one: view-space depth, 0 where no surface)");
    check_same_size(colour, o.image, normal, normal_path);
    check_same_size(colour, o.image, depth, depth_path);
    if (colour.width != s.width || colour.height != s.height)
        throw Error("fit --over: '" + o.image + "' is " + std::to_string(colour.width) + "x" + std::to_string(colour.height) +
                    " but scene '" + o.scene + "' renders " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                    ": give the scene the image was rendered from");
    // The camera: the scene's, over its meshes' bounds (a framed camera needs them).
    const SceneGeometry g = load_scene_geometry(s, [](const std::string& p) { return load_mesh(p); });
    const Camera& cam = g.camera;
    Domain d;
    d.per_group = s.lights.size();
    d.ambient = s.ambient;
    values.clear();
    for (int y = 0; y < colour.height; ++y)
        for (int x = 0; x < colour.width; ++x) {
            const float z = depth.at(x, y, 0);
            const glm::dvec3 n(normal.at(x, y, 0), normal.at(x, y, 1), normal.at(x, y, 2));
            if (!std::isfinite(z) || z < 0.0f)
                throw Error("fit --over: " + at_pixel(depth_path, x, y) + " has depth " + num(z) +
                            ": a depth AOV holds distances >= 0 (0 where no surface)");
            if (!(normal.at(x, y, 3) > 0.5f) || z == 0.0f) continue;   // no surface here
            const double len = glm::length(n);
            if (!(std::abs(len - 1.0) <= 1e-3))
                throw Error("fit --over: " + at_pixel(normal_path, x, y) + " holds a normal of length " + num(len) +
                            ": not a normal AOV (the batch writes unit world-space normals)");
            glm::dvec3 rgb;
            for (int c = 0; c < 3; ++c) {
                rgb[c] = colour.at(x, y, c);
                if (!std::isfinite(rgb[c]))
                    throw Error("fit --over: " + at_pixel(o.image, x, y) + " is not finite: a render to fit holds finite colours");
            }
            add_fragment(d, point_at_depth(cam, colour.width, colour.height, x, y, z), n / len, cam.eye, s.lights);
            for (int c = 0; c < 3; ++c) values.push_back(rgb[c]);
        }
    const std::size_t pixels = values.size() / 3;
    if (pixels < 64)
        throw Error("fit --over: '" + normal_path + "' covers only " + std::to_string(pixels) +
                    " pixels (a fit needs at least 64): give the AOVs of a render that shows the meshes");
    d.name = "image " + o.image;
    std::ostringstream desc;
    desc << pixels << " pixels of '" << o.image << "' (" << colour.width << "x" << colour.height << "), N from '"
         << normal_path << "', P from the depth in '" << depth_path << "' on each pixel's ray, camera and "
         << s.lights.size() << " light(s) of scene '" << o.scene << "': the rendered colours the target, per channel";
    d.description = desc.str();
    return d;
}

SampleAngles angles_of(const Domain& d, std::size_t i) {
    const glm::dvec3 N = glm::normalize(d.N[i]), L = glm::normalize(d.L[i]), V = glm::normalize(d.V[i]);
    auto deg = [](double c) { return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / kPi; };
    SampleAngles a;
    a.NoL = glm::dot(N, L);
    a.NoV = glm::dot(N, V);
    a.theta_i = deg(a.NoL);
    a.theta_r = deg(a.NoV);
    a.phase = deg(glm::dot(L, V));
    const glm::dvec3 Lt = L - a.NoL * N, Vt = V - a.NoV * N;
    const double ll = glm::length(Lt), lv = glm::length(Vt);
    a.dphi = (ll > 1e-9 && lv > 1e-9) ? deg(glm::dot(Lt, Vt) / (ll * lv)) : 0.0;
    return a;
}

}  // namespace shadelab::fit
