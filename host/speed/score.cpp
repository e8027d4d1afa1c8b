#include "speed/score.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <thread>

#include "core/error.hpp"
#include "models/catalogue.hpp"
#include "pipeline/pipeline.hpp"
#include "raster/raster.hpp"
#include "reference/reference.hpp"

namespace shadelab::speed {

ScoreView make_view(const std::string& name, const Mesh& mesh, const glm::dvec3& view_from, int width, int height) {
    if (width < 1 || height < 1) throw Error("chart: image size must be at least 1x1");
    ScoreView v;
    v.name = name;
    v.camera = Camera::fit(mesh.bounds(), view_from, 35.0, double(width) / height);
    // Rasterised by the render path (host/pipeline/), as every command's images are.
    pipeline::Job job;
    job.meshes.push_back(pipeline::JobMesh{mesh, Material{}, false});
    job.camera = v.camera;
    job.width = width;
    job.height = height;
    pipeline::StageTimes times;
    v.fragments = pipeline::raster(job, times).fb;
    v.mesh = std::move(job.meshes.front().mesh);
    if (v.fragments.empty())
        throw Error("chart: the mesh '" + name + "' covers no pixel at " + std::to_string(width) + "x" +
                    std::to_string(height) + ": use a larger --size");
    return v;
}

std::vector<Light> chart_lights(const glm::dvec3& view_from) {
    const glm::dvec3 f = glm::normalize(view_from);
    glm::dvec3 right = glm::cross(glm::dvec3(0, 1, 0), f);
    right = glm::length(right) > 1e-6 ? glm::normalize(right) : glm::dvec3(1, 0, 0);
    const glm::dvec3 up = glm::cross(f, right);
    Light key{Light::Type::Directional, f + 0.9 * up + 0.6 * right, {1.0, 1.0, 1.0}, 1.0, 0.0};
    Light fill{Light::Type::Directional, 0.5 * f - right + 0.2 * up, {1.0, 0.85, 0.7}, 0.4, 0.0};
    return {key, fill};
}

Material chart_material(const std::string& model) {
    const ModelInfo& info = find_model(model);   // throws with the known names
    Material m;
    m.model = info.name;
    m.albedo = glm::dvec3(0.9, 0.5, 0.25);
    m.specular = glm::dvec3(1.0);
    add_demo_children(m, info);
    return resolve_material(m, "chart, model '" + info.name + "'");
}

Scorer::Scorer(Runtime& runtime, std::vector<ScoreView> views, ScoreOptions options)
    : rt_(runtime), shader_(runtime), views_(std::move(views)), opt_(std::move(options)) {
    if (views_.empty()) throw Error("chart: no view to score on (give at least one --mesh)");
    for (const auto& v : views_)
        if (v.fragments.width != views_.front().fragments.width || v.fragments.height != views_.front().fragments.height)
            throw Error("internal: chart views must all have the same image size");
    if (opt_.timing_repeats < 1) throw Error("chart: timing repeats must be at least 1");
    // The timing buffer: every view's fragments, repeated until it holds at least timed_fragments.
    std::size_t per_round = 0;
    for (const auto& v : views_) per_round += v.fragments.size();
    const std::size_t rounds = std::max<std::size_t>(1, (opt_.timed_fragments + per_round - 1) / per_round);
    timing_.reserve(rounds * per_round);
    for (std::size_t r = 0; r < rounds; ++r)
        for (const auto& v : views_) {
            const FragmentBuffer& f = v.fragments;
            for (std::size_t i = 0; i < f.size(); ++i)
                timing_.push_back(f.px[i], f.py[i], f.pz[i], f.nx[i], f.ny[i], f.nz[i], f.pixel[i], f.depth[i]);
        }
}

int Scorer::atlas_width() const { return views_.front().fragments.width * int(views_.size()); }
int Scorer::atlas_height() const { return views_.front().fragments.height; }

Image Scorer::atlas(const std::vector<std::vector<float>>& planes) const {
    Image img(atlas_width(), atlas_height(), 4);
    const int w = views_.front().fragments.width;
    for (std::size_t k = 0; k < views_.size(); ++k) {
        const FragmentBuffer& fb = views_[k].fragments;
        const std::size_t n = fb.size();
        for (std::size_t i = 0; i < n; ++i) {
            const int x = fb.pixel[i] % w + int(k) * w, y = fb.pixel[i] / w;
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = planes[k][std::size_t(c) * n + i];
            img.at(x, y, 3) = 1.0f;
        }
    }
    return img;
}

Image Scorer::kernel_image(const Material& material, Precision precision) {
    std::vector<std::vector<float>> planes;
    for (const auto& v : views_) {
        ShadeSetup s;
        s.material = material;
        s.lights = opt_.lights;
        s.ambient = opt_.ambient;
        s.view = glm::dvec4(v.camera.eye, 1.0);
        s.precision = precision;
        planes.push_back(shader_.shade(v.fragments, s));
    }
    return atlas(planes);
}

const Image& Scorer::reference_image(const Material& material) {
    const Material m = resolve_material(material);
    std::ostringstream key;
    key.precision(17);
    key << m.model << '|' << m.albedo.x << ',' << m.albedo.y << ',' << m.albedo.z << '|' << m.specular.x << ','
        << m.specular.y << ',' << m.specular.z;
    for (const auto& p : m.params) key << '|' << p.first << '=' << p.second;
    for (const auto& c : m.children) key << "|child " << c.model << ' ' << c.albedo.x << ',' << c.albedo.y << ',' << c.albedo.z;
    auto it = reference_cache_.find(key.str());
    if (it != reference_cache_.end()) return it->second;
    std::vector<std::vector<float>> planes;
    for (const auto& v : views_) planes.push_back(ref::shade_fragments(v.fragments, m, opt_.lights, opt_.ambient, v.camera.eye));
    return reference_cache_.emplace(key.str(), atlas(planes)).first->second;
}

double Scorer::time_kernel(const Material& material, Precision precision) {
    ShadeSetup setup;
    setup.material = material;
    setup.lights = opt_.lights;
    setup.ambient = opt_.ambient;
    setup.view = glm::dvec4(views_.front().camera.eye, 1.0);
    setup.precision = precision;
    double best = std::numeric_limits<double>::infinity();
    for (int r = 0; r < opt_.timing_repeats; ++r) {
        ShadeTiming t;
        shader_.shade(timing_, setup, &t);
        best = std::min(best, t.kernel_ms);
    }
    if (!(best > 0.0) || !std::isfinite(best))
        throw Error("chart: the device reported a kernel time of " + std::to_string(best) + " ms for model '" +
                    material.model + "': profiling is not usable on this device");
    return best;
}

Score Scorer::score(const Material& material, Precision precision) {
    Score s;
    s.model = material.model;
    s.precision = precision;
    s.error = compare_images(kernel_image(material, precision), reference_image(material), opt_.rel_floor);   // figures only
    const double best = time_kernel(material, precision);
    s.kernel_ms = best;
    s.timed_fragments = timing_.size();
    s.fragments_per_s = double(timing_.size()) / (best * 1e-3);
    return s;
}

}  // namespace shadelab::speed
