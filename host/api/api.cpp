// The public API (include/shadelab/): thin translations between its plain types and the internal ones. Every
// internal shadelab::Error leaves as shadelab::api::Error with the same one-line message.
#include <cmath>
#include <utility>

#include "shadelab/shadelab.hpp"

#include "cl/runtime.hpp"
#include "color/image_compare.hpp"
#include "core/error.hpp"
#include "image/image.hpp"
#include "mesh/mesh.hpp"
#include "models/catalogue.hpp"
#include "moon/fit.hpp"
#include "raster/raster.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"

#ifndef SHADELAB_VERSION
#define SHADELAB_VERSION "0.0.0"
#endif

namespace shadelab::api {

namespace {

template <class F>
auto guarded(F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const shadelab::Error& e) {
        throw Error(e.what());
    }
}

glm::dvec3 to_glm(const Vec3& v) { return {v[0], v[1], v[2]}; }
Vec3 from_glm(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

shadelab::Material to_internal(const Material& m) {
    shadelab::Material out;
    out.model = m.model;
    out.params = m.params;
    out.albedo = to_glm(m.albedo);
    out.specular = to_glm(m.specular);
    const shadelab::ModelInfo& info = find_model(m.model);
    add_demo_children(out, info);   // a blending model (gradient) gets the demonstration children
    return resolve_material(out, "material");
}

shadelab::Light to_internal(const Light& l) {
    shadelab::Light out;
    out.type = l.point ? shadelab::Light::Type::Point : shadelab::Light::Type::Directional;
    out.vec = to_glm(l.vec);
    out.colour = to_glm(l.colour);
    out.intensity = l.intensity;
    out.range = l.range;
    return out;
}

shadelab::Image to_internal(const Image& img) {
    if (img.width < 1 || img.height < 1 || img.channels < 1 || img.channels > 4 ||
        img.pixels.size() != std::size_t(img.width) * img.height * img.channels)
        throw shadelab::Error("image: expected width x height x (1 to 4) floats, got " + std::to_string(img.width) +
                              "x" + std::to_string(img.height) + "x" + std::to_string(img.channels) + " with " +
                              std::to_string(img.pixels.size()) + " values");
    shadelab::Image out(img.width, img.height, img.channels);
    out.pixels = img.pixels;
    return out;
}

Image from_internal(shadelab::Image&& img) {
    Image out;
    out.width = img.width;
    out.height = img.height;
    out.channels = img.channels;
    out.pixels = std::move(img.pixels);
    return out;
}

}  // namespace

std::string version() { return SHADELAB_VERSION; }

std::vector<std::string> models() {
    std::vector<std::string> out;
    for (const auto& m : model_catalogue()) out.push_back(m.name);
    return out;
}

api::ModelInfo model_info(const std::string& name) {
    return guarded([&] {
        const shadelab::ModelInfo& m = find_model(name);
        api::ModelInfo out{m.name, m.family, m.summary, m.source, {}};
        for (const auto& p : m.params) out.params.push_back(ParamInfo{p.name, p.def, p.lo, p.hi, p.integer, p.doc});
        return out;
    });
}

Vec3 reference(const Material& material, const Vec3& N, const Vec3& L, const Vec3& V, const Vec3& P) {
    return guarded([&] {
        return from_glm(ref::eval_material(to_glm(N), to_glm(L), to_glm(V), to_glm(P), to_internal(material)));
    });
}

struct Engine::Impl {
    Runtime rt;
};

Engine::Engine() : impl_(guarded([] { return std::make_unique<Impl>(); })) {}
Engine::~Engine() = default;

std::string Engine::device() const { return impl_->rt.device_description(); }
std::string Engine::kernel_dir() const { return impl_->rt.kernel_dir(); }

void Engine::shade(const Material& material, const float* N, const float* L, const float* V, std::size_t n,
                   float* out, bool fast) {
    guarded([&] {
        if (n == 0) return 0;
        if (!N || !L || !V || !out) throw shadelab::Error("shade: N, L, V and out must not be null");
        for (std::size_t i = 0; i < 3 * n; ++i)
            if (!std::isfinite(N[i]) || !std::isfinite(L[i]) || !std::isfinite(V[i]))
                throw shadelab::Error("shade: direction triple " + std::to_string(i / 3) +
                                      " holds NaN or Inf: give finite unit vectors");
        Shader shader(impl_->rt);
        // the caller's arrays in place, the results straight into `out`; positions are zeros
        shader.eval_directions_into(to_internal(material), N, L, V, nullptr, n, out,
                                    fast ? Precision::Fast : Precision::Precise);
        return 0;
    });
}

Image Engine::render(const std::string& mesh_file, const RenderOptions& o) {
    return guarded([&] {
        if (o.width < 1 || o.height < 1 || o.width > 16384 || o.height > 16384)
            throw shadelab::Error("render: width and height must be in [1, 16384]");
        const shadelab::Mesh mesh = load_mesh(mesh_file);
        const Camera cam = Camera::fit(mesh.bounds(), to_glm(o.view_from), o.fov_deg, double(o.width) / o.height);
        RasterOptions ro;
        ro.width = o.width;
        ro.height = o.height;
        ro.cull_backfaces = o.cull_backfaces;
        const FragmentBuffer fb = rasterize(mesh, cam, ro);
        ShadeSetup setup;
        setup.material = to_internal(o.material);
        for (const auto& l : o.lights) setup.lights.push_back(to_internal(l));
        if (setup.lights.empty()) setup.lights.push_back(shadelab::Light{});
        if (o.lights.empty()) setup.lights.back().vec = {1.0, 1.0, 1.0};
        setup.ambient = to_glm(o.ambient);
        setup.view = glm::dvec4(cam.eye, 1.0);
        setup.precision = o.fast ? Precision::Fast : Precision::Precise;
        Shader shader(impl_->rt);
        const auto rgb = shader.shade(fb, setup);
        const glm::dvec4 bg{o.background[0], o.background[1], o.background[2], o.background[3]};
        return from_internal(compose_image(fb, rgb, bg));
    });
}

Comparison compare(const Image& a, const Image& b) {
    return guarded([&] {
        for (const Image* img : {&a, &b})
            for (std::size_t i = 0; i < img->pixels.size(); ++i)
                if (!std::isfinite(img->pixels[i])) {
                    const std::size_t px = i / std::size_t(img->channels);
                    throw shadelab::Error(std::string(img == &a ? "first" : "second") + " image: pixel (" +
                                          std::to_string(px % std::size_t(img->width)) + ", " +
                                          std::to_string(px / std::size_t(img->width)) +
                                          ") is NaN or Inf: compare finite images");
                }
        if (a.channels < 3 || b.channels < 3) throw shadelab::Error("compare: images need 3 (RGB) or 4 (RGBA) channels");
        const shadelab::Image ia = to_internal(a), ib = to_internal(b);
        if (ia.width != ib.width || ia.height != ib.height)
            throw shadelab::Error("compare: the images differ in size (" + std::to_string(ia.width) + "x" +
                                  std::to_string(ia.height) + " and " + std::to_string(ib.width) + "x" +
                                  std::to_string(ib.height) + ")");
        const ImageDiff d = compare_images(ia, ib);
        return Comparison{d.pixels, d.coverage_mismatch, d.de_mean, d.de_p99, d.de_max, d.rel_max, d.rel_p99};
    });
}

MinnaertResult fit_minnaert(const Image& image, const DiscGeometry& g, const std::string& method) {
    return guarded([&] {
        const shadelab::Image img = to_internal(image);
        moon::Disc disc;
        disc.cx = g.cx;
        disc.cy = g.cy;
        disc.radius = g.radius;
        if (!(g.radius > 0) || !std::isfinite(g.radius) || !std::isfinite(g.cx) || !std::isfinite(g.cy))
            throw shadelab::Error("disc geometry: centre must be finite and radius > 0 pixels");
        const moon::SunGeometry sun = moon::sun_geometry(g.phase_deg, g.pa_deg);
        moon::FitOptions fo;
        fo.method = moon::parse_fit_method(method);
        const auto pixels = moon::disc_pixels(img, disc, sun);
        const moon::MinnaertFit f = moon::fit_minnaert(pixels, sun, fo);
        return MinnaertResult{f.k, f.se_k, f.B0, f.se_B0, f.rms_rel, f.used, f.warnings};
    });
}

}  // namespace shadelab::api
