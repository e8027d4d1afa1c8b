// The render path's stages (see pipeline.hpp).
#include "pipeline/pipeline.hpp"

#include <chrono>
#include <limits>
#include <sstream>

#include "core/error.hpp"
#include "core/format.hpp"
#include "raster/big_buffer.hpp"
#include "raster/raster.hpp"
#include "shade/gouraud.hpp"

namespace shadelab::pipeline {

glm::dvec4 shade_view(const Job& job) {
    return glm::length(job.view_direction) > 0.0 ? glm::dvec4(job.view_direction, 0.0) : glm::dvec4(job.camera.eye, 1.0);
}

namespace {

using clock_type = std::chrono::steady_clock;
double ms_since(clock_type::time_point t0) {
    return std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();
}

// Nearest fragment per pixel over all meshes (ties: the earlier mesh), in pixel order; triangle ids and
// barycentrics come along when the rasteriser gave them (per-vertex shading needs them).
void merge_by_depth(std::vector<FragmentBuffer>& parts, Frame& frame) {
    FragmentBuffer& out = frame.fb;
    std::vector<std::uint16_t>& mesh_of = frame.mesh_of;
    if (parts.size() == 1) {
        out = std::move(parts[0]);
        mesh_of.assign(out.size(), 0);
        return;
    }
    const std::size_t npix = std::size_t(parts[0].width) * std::size_t(parts[0].height);
    std::vector<float> best(npix, std::numeric_limits<float>::infinity());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> who(npix, {0xffffffffu, 0});
    for (std::size_t m = 0; m < parts.size(); ++m)
        for (std::size_t i = 0; i < parts[m].size(); ++i) {
            const std::size_t p = std::size_t(parts[m].pixel[i]);
            if (parts[m].depth[i] < best[p]) {
                best[p] = parts[m].depth[i];
                who[p] = {std::uint32_t(m), std::uint32_t(i)};
            }
        }
    out = FragmentBuffer{};
    out.width = parts[0].width;
    out.height = parts[0].height;
    mesh_of.clear();
    for (std::size_t p = 0; p < npix; ++p) {
        if (who[p].first == 0xffffffffu) continue;
        const FragmentBuffer& f = parts[who[p].first];
        const std::size_t i = who[p].second;
        out.push_back(f.px[i], f.py[i], f.pz[i], f.nx[i], f.ny[i], f.nz[i], f.pixel[i], f.depth[i]);
        if (!f.triangle.empty()) {
            out.triangle.push_back(f.triangle[i]);
            out.b1.push_back(f.b1[i]);
            out.b2.push_back(f.b2[i]);
        }
        mesh_of.push_back(std::uint16_t(who[p].first));
    }
}

// The fragments of mesh `mi` (with their triangle ids and barycentrics, for per-vertex shading).
FragmentBuffer fragments_of(const Frame& frame, std::size_t mi, std::vector<std::size_t>& idx) {
    const FragmentBuffer& fb = frame.fb;
    idx.clear();
    for (std::size_t i = 0; i < fb.size(); ++i)
        if (frame.mesh_of[i] == mi) idx.push_back(i);
    FragmentBuffer sub;
    sub.width = fb.width;
    sub.height = fb.height;
    sub.reserve(idx.size());
    for (std::size_t i : idx) {
        sub.push_back(fb.px[i], fb.py[i], fb.pz[i], fb.nx[i], fb.ny[i], fb.nz[i], fb.pixel[i], fb.depth[i]);
        if (!fb.triangle.empty()) {
            sub.triangle.push_back(fb.triangle[i]);
            sub.b1.push_back(fb.b1[i]);
            sub.b2.push_back(fb.b2[i]);
        }
    }
    return sub;
}

std::vector<float> shade_mesh(Shader& shader, const Job& job, const JobMesh& m, const FragmentBuffer& fb,
                              ShadeTiming& st, double& interpolate_ms) {
    ShadeSetup setup;
    setup.material = m.material;
    setup.lights = job.lights;
    setup.ambient = job.ambient;
    setup.view = shade_view(job);
    setup.precision = job.precision;
    if (!job.per_vertex) return shader.shade(fb, setup, &st);
    const auto vertex_planes = shade_vertices(shader, m.mesh, setup, &st);
    const auto t0 = clock_type::now();
    std::vector<float> planes = interpolate_to_fragments(fb, m.mesh, vertex_planes);
    interpolate_ms += ms_since(t0);
    return planes;
}

Image depth_image(const Job& job, const FragmentBuffer& fb) {
    Image d(job.width, job.height, 1);   // 0 = no surface (covered depths are > z_near > 0)
    for (std::size_t i = 0; i < fb.size(); ++i) d.pixels[std::size_t(fb.pixel[i])] = fb.depth[i];
    return d;
}

Image normal_image(const Job& job, const FragmentBuffer& fb) {
    Image nm(job.width, job.height, 4);
    for (std::size_t i = 0; i < fb.size(); ++i) {
        float* px = &nm.pixels[std::size_t(fb.pixel[i]) * 4];
        px[0] = fb.nx[i];
        px[1] = fb.ny[i];
        px[2] = fb.nz[i];
        px[3] = 1.0f;
    }
    return nm;
}

}  // namespace

StageTimes& StageTimes::operator+=(const StageTimes& o) {
    load_ms += o.load_ms;
    raster_ms += o.raster_ms;
    build_ms += o.build_ms;
    kernel_ms += o.kernel_ms;
    interpolate_ms += o.interpolate_ms;
    shade_ms += o.shade_ms;
    resolve_ms += o.resolve_ms;
    write_ms += o.write_ms;
    plan_ms += o.plan_ms;
    return *this;
}

std::string describe(const StageTimes& t) {
    std::string s = "load " + fixed(t.load_ms, 1) + " ms, raster " + fixed(t.raster_ms, 1) + " ms, build " +
                    fixed(t.build_ms, 1) + " ms, kernel " + fixed(t.kernel_ms, 1) + " ms, resolve " +
                    fixed(t.resolve_ms, 1) + " ms, write " + fixed(t.write_ms, 1) + " ms (shade wall " +
                    fixed(t.shade_ms, 1) + " ms";
    if (t.plan_ms > 0.0) s += ", plan " + fixed(t.plan_ms, 1) + " ms";
    return s + ")";
}

std::vector<std::string> JobOutputs::all() const {
    std::vector<std::string> v = colour;
    for (const auto* s : {&depth, &normal})
        if (!s->empty()) v.push_back(*s);
    return v;
}

Frame raster(const Job& job, StageTimes& times) {
    const auto t0 = clock_type::now();
    std::vector<FragmentBuffer> parts;
    for (const auto& m : job.meshes) {
        RasterOptions ro;
        ro.width = job.width;
        ro.height = job.height;
        ro.threads = job.raster_threads;
        ro.cull_backfaces = m.cull_backfaces;
        ro.triangle_ids = job.triangle_ids;
        parts.push_back(rasterize(m.mesh, job.camera, ro));
    }
    Frame frame;
    merge_by_depth(parts, frame);
    times.raster_ms += ms_since(t0);
    return frame;
}

std::vector<float> shade(Shader& shader, const Job& job, const Frame& frame, StageTimes& times) {
    const auto t0 = clock_type::now();
    const std::size_t n = frame.fb.size();
    // One mesh: its shaded planes are the frame's (moved, below). Several: each mesh's planes are scattered into
    // the frame's, zero-filled first. (Zero-filling 3n floats for one mesh too took 40-50 ms of fresh pages at
    // 4096x4096, for planes that were then replaced.)
    std::vector<float> rgb;
    if (job.meshes.size() > 1) size_for_frame(rgb, 3 * n);
    std::vector<std::size_t> idx;
    for (std::size_t mi = 0; mi < job.meshes.size() && n > 0; ++mi) {
        // This mesh's fragments, shaded with its material (one launch per material).
        const bool whole = job.meshes.size() == 1;
        const FragmentBuffer sub = whole ? FragmentBuffer{} : fragments_of(frame, mi, idx);
        if (!whole && idx.empty()) continue;
        ShadeTiming st;
        std::vector<float> part;
        try {
            part = shade_mesh(shader, job, job.meshes[mi], whole ? frame.fb : sub, st, times.interpolate_ms);
        } catch (const Error& e) {
            throw Error("meshes[" + std::to_string(mi) + "] (model '" + job.meshes[mi].material.model + "'): " + e.what());
        }
        times.build_ms += st.build_ms;
        times.kernel_ms += st.kernel_ms;
        if (whole) {
            rgb = std::move(part);
            break;
        }
        const std::size_t m = idx.size();
        for (std::size_t k = 0; k < m; ++k)
            for (std::size_t c = 0; c < 3; ++c) rgb[c * n + idx[k]] = part[c * m + k];
    }
    times.shade_ms += ms_since(t0);
    return rgb;
}

Image compose(const Job& job, const Frame& frame, const std::vector<float>& rgb, StageTimes& times) {
    const auto t0 = clock_type::now();
    Image img = compose_image(frame.fb, rgb, job.background);
    times.resolve_ms += ms_since(t0);
    return img;
}

std::vector<std::pair<std::string, Image>> resolve(const Job& job, const Frame& frame, const std::vector<float>& rgb,
                                                   StageTimes& times) {
    const auto t0 = clock_type::now();
    std::vector<std::pair<std::string, Image>> images;
    const auto& o = job.outputs;
    if (!o.colour.empty()) {
        Image img = compose_image(frame.fb, rgb, job.background);
        for (std::size_t i = 0; i + 1 < o.colour.size(); ++i) images.emplace_back(o.colour[i], img);
        images.emplace_back(o.colour.back(), std::move(img));
    }
    if (!o.depth.empty()) images.emplace_back(o.depth, depth_image(job, frame.fb));
    if (!o.normal.empty()) images.emplace_back(o.normal, normal_image(job, frame.fb));
    times.resolve_ms += ms_since(t0);
    return images;
}

void write(const std::vector<std::pair<std::string, Image>>& images, StageTimes& times) {
    const auto t0 = clock_type::now();
    for (const auto& [path, img] : images) write_image(path, img);
    times.write_ms += ms_since(t0);
}

JobRun run_job(Shader& shader, const Job& job, StageTimes times) {
    JobRun r;
    const Frame frame = raster(job, times);
    r.fragments = frame.fb.size();
    const auto rgb = shade(shader, job, frame, times);
    write(resolve(job, frame, rgb, times), times);
    r.times = times;
    return r;
}

}  // namespace shadelab::pipeline
