// The render path's stages (see pipeline.hpp).
#include "pipeline/pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <sstream>

#include "core/error.hpp"
#include "core/format.hpp"
#include "raster/big_buffer.hpp"
#include "raster/parallel.hpp"
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
//
// Each part is in pixel order, as the rasteriser emits it (checked), so the parts are merged as sorted lists: the
// image is cut into one range of pixels a thread, each range walked in blocks of kMergeBlock pixels with a cursor
// a part, and a block's nearest fragments found in a small array of the block's own (in cache). Two passes: the
// first counts each range's winners, which gives every range its place in the output; the second writes them.
// (It replaced arrays of the whole image's depth and winners, 12 bytes a pixel, and push_back into the output:
// 150-200 ms of a 3-mesh scene at 4096x2048 on one thread.)
constexpr std::size_t kMergeBlock = std::size_t(1) << 14;
constexpr std::uint32_t kNoPart = 0xffffffffu;

// Fragment i of `from` as fragment k of `to` (whose arrays hold k; the triangle ids and barycentrics with `ids`).
void copy_fragment(FragmentBuffer& to, std::size_t k, const FragmentBuffer& from, std::size_t i, bool ids) {
    to.px[k] = from.px[i];
    to.py[k] = from.py[i];
    to.pz[k] = from.pz[i];
    to.nx[k] = from.nx[i];
    to.ny[k] = from.ny[i];
    to.nz[k] = from.nz[i];
    to.pixel[k] = from.pixel[i];
    to.depth[k] = from.depth[i];
    if (ids) {
        to.triangle[k] = from.triangle[i];
        to.b1[k] = from.b1[i];
        to.b2[k] = from.b2[i];
    }
}

// Calls winner(m, i) for the nearest fragment (part m, index i) of every covered pixel in [p0, p1), in pixel
// order; `at` starts at each part's first fragment at or after p0 and ends past p1's.
template <class Winner>
void merge_range(const std::vector<FragmentBuffer>& parts, std::size_t p0, std::size_t p1, std::vector<std::size_t>& at,
                 const Winner& winner) {
    std::vector<float> best(kMergeBlock);
    std::vector<std::uint32_t> part(kMergeBlock), index(kMergeBlock);
    for (std::size_t b0 = p0; b0 < p1; b0 += kMergeBlock) {
        const std::size_t b1 = std::min(p1, b0 + kMergeBlock), n = b1 - b0;
        std::fill(best.begin(), best.begin() + std::ptrdiff_t(n), std::numeric_limits<float>::infinity());
        std::fill(part.begin(), part.begin() + std::ptrdiff_t(n), kNoPart);
        for (std::size_t m = 0; m < parts.size(); ++m) {
            const FragmentBuffer& f = parts[m];
            std::size_t i = at[m];
            for (; i < f.size() && std::size_t(f.pixel[i]) < b1; ++i) {
                const std::size_t q = std::size_t(f.pixel[i]) - b0;
                if (f.depth[i] < best[q]) {
                    best[q] = f.depth[i];
                    part[q] = std::uint32_t(m);
                    index[q] = std::uint32_t(i);
                }
            }
            at[m] = i;
        }
        for (std::size_t q = 0; q < n; ++q)
            if (part[q] != kNoPart) winner(part[q], index[q]);
    }
}

// Every part's pixel indices inside the image and non-decreasing (the rasteriser's order); the merge needs it.
void require_pixel_order(const std::vector<FragmentBuffer>& parts, std::size_t npix) {
    for (std::size_t m = 0; m < parts.size(); ++m) {
        const std::vector<std::int32_t>& p = parts[m].pixel;
        for (std::size_t i = 0; i < p.size(); ++i)
            if (p[i] < 0 || std::size_t(p[i]) >= npix || (i > 0 && p[i] < p[i - 1]))
                throw Error("internal: mesh " + std::to_string(m) + "'s fragment " + std::to_string(i) +
                            " is not in pixel order inside the image (pixel " + std::to_string(p[i]) + ")");
    }
}

void merge_by_depth(std::vector<FragmentBuffer>& parts, Frame& frame) {
    FragmentBuffer& out = frame.fb;
    std::vector<std::uint16_t>& mesh_of = frame.mesh_of;
    if (parts.size() == 1) {
        out = std::move(parts[0]);
        mesh_of.assign(out.size(), 0);
        return;
    }
    const std::size_t npix = std::size_t(parts[0].width) * std::size_t(parts[0].height);
    require_pixel_order(parts, npix);
    // (a part with no fragments has no ids either: the job asked for them or not, for every mesh)
    const bool ids =
        std::any_of(parts.begin(), parts.end(), [](const FragmentBuffer& f) { return !f.triangle.empty(); });
    const int threads = thread_count(0, npix / (4 * kMergeBlock));
    // each range's cursors where it starts, and its winners' count (pass 1) then first output index
    std::vector<std::vector<std::size_t>> start(std::size_t(threads), std::vector<std::size_t>(parts.size()));
    std::vector<std::size_t> first(std::size_t(threads) + 1, 0);
    run_parallel(threads, [&](int t) {
        const std::size_t p0 = split(npix, threads, t), p1 = split(npix, threads, t + 1);
        std::vector<std::size_t>& at = start[std::size_t(t)];
        for (std::size_t m = 0; m < parts.size(); ++m) {
            const std::vector<std::int32_t>& p = parts[m].pixel;
            at[m] = std::size_t(std::lower_bound(p.begin(), p.end(), std::int32_t(p0)) - p.begin());
        }
        std::vector<std::size_t> walk = at;
        std::size_t count = 0;
        merge_range(parts, p0, p1, walk, [&](std::uint32_t, std::uint32_t) { ++count; });
        first[std::size_t(t) + 1] = count;
    });
    for (int t = 0; t < threads; ++t) first[std::size_t(t) + 1] += first[std::size_t(t)];
    const std::size_t total = first.back();
    out = FragmentBuffer{};
    out.width = parts[0].width;
    out.height = parts[0].height;
    size_fragments(out, total, ids, threads);
    size_for_frame(mesh_of, total);
    run_parallel(threads, [&](int t) {
        const std::size_t p0 = split(npix, threads, t), p1 = split(npix, threads, t + 1);
        std::size_t k = first[std::size_t(t)];
        merge_range(parts, p0, p1, start[std::size_t(t)], [&](std::uint32_t m, std::uint32_t i) {
            copy_fragment(out, k, parts[m], i, ids);
            mesh_of[k++] = std::uint16_t(m);
        });
    });
}

// Where each mesh's fragments lie in the frame, so that a mesh's fragments are gathered and its shaded planes
// scattered back on several threads, with no list of indices: the frame's fragments cut into `threads`
// contiguous chunks (split()), first[t][m] = the index, among mesh m's own fragments, of its first one in chunk t,
// and count[m] = all of mesh m's. (Replaced one thread's walk that pushed every index into a list, then copied and
// scattered through it: 85-100 ms of a 3-mesh scene's shade stage at 4096x2048 around 4-5 ms of kernels.)
struct MeshChunks {
    int threads = 1;
    std::vector<std::vector<std::size_t>> first;
    std::vector<std::size_t> count;
};

MeshChunks chunk_by_mesh(const Frame& frame, std::size_t meshes) {
    const std::vector<std::uint16_t>& mesh_of = frame.mesh_of;
    const std::size_t n = mesh_of.size();
    MeshChunks c;
    c.threads = thread_count(0, n / kMergeBlock);
    c.first.assign(std::size_t(c.threads), std::vector<std::size_t>(meshes, 0));
    run_parallel(c.threads, [&](int t) {
        std::vector<std::size_t>& here = c.first[std::size_t(t)];
        for (std::size_t i = split(n, c.threads, t), end = split(n, c.threads, t + 1); i < end; ++i) {
            if (mesh_of[i] >= meshes)
                throw Error("internal: fragment " + std::to_string(i) + " names mesh " + std::to_string(mesh_of[i]) +
                            " of " + std::to_string(meshes));
            ++here[mesh_of[i]];
        }
    });
    c.count.assign(meshes, 0);
    for (std::vector<std::size_t>& here : c.first)
        for (std::size_t m = 0; m < meshes; ++m) {
            const std::size_t in_chunk = here[m];
            here[m] = c.count[m];
            c.count[m] += in_chunk;
        }
    return c;
}

// fn(i, k) for every fragment i of the frame that is mesh mi's, k its index among the mesh's own (in order), on
// the chunks' threads (each chunk's i and k are its own).
template <class Fn>
void for_mesh_fragments(const Frame& frame, const MeshChunks& c, std::size_t mi, const Fn& fn) {
    const std::size_t n = frame.mesh_of.size();
    run_parallel(c.threads, [&](int t) {
        std::size_t k = c.first[std::size_t(t)][mi];
        for (std::size_t i = split(n, c.threads, t), end = split(n, c.threads, t + 1); i < end; ++i)
            if (frame.mesh_of[i] == mi) fn(i, k++);
    });
}

// The fragments of mesh `mi` into `sub` (its memory reused from the mesh before when large enough), with their
// triangle ids and barycentrics (for per-vertex shading).
void fragments_of(const Frame& frame, const MeshChunks& c, std::size_t mi, FragmentBuffer& sub) {
    const FragmentBuffer& fb = frame.fb;
    const bool ids = !fb.triangle.empty();
    sub.width = fb.width;
    sub.height = fb.height;
    size_fragments(sub, c.count[mi], ids, c.threads);
    for_mesh_fragments(frame, c, mi, [&](std::size_t i, std::size_t k) { copy_fragment(sub, k, fb, i, ids); });
}

// Mesh m's fragments shaded into `planes` (its memory reused when large enough: the meshes of one frame share it).
void shade_mesh(Shader& shader, const Job& job, const JobMesh& m, const FragmentBuffer& fb, std::vector<float>& planes,
                ShadeTiming& st, double& interpolate_ms) {
    ShadeSetup setup;
    setup.material = m.material;
    setup.lights = job.lights;
    setup.ambient = job.ambient;
    setup.view = shade_view(job);
    setup.precision = job.precision;
    if (!job.per_vertex) {
        shader.shade_into(fb, setup, planes, &st);
        return;
    }
    const auto vertex_planes = shade_vertices(shader, m.mesh, setup, &st);
    const auto t0 = clock_type::now();
    planes = interpolate_to_fragments(fb, m.mesh, vertex_planes);
    interpolate_ms += ms_since(t0);
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
    // One mesh: its shaded planes are the frame's (moved, below). Several: each mesh's fragments are gathered,
    // shaded, and its planes scattered into the frame's (every fragment is one mesh's, so every value is written).
    // (Zero-filling 3n floats for one mesh too took 40-50 ms of fresh pages at 4096x4096, for planes that were
    // then replaced.)
    const bool whole = job.meshes.size() == 1;
    std::vector<float> rgb;
    MeshChunks chunks;
    if (!whole && n > 0) {
        size_for_frame(rgb, 3 * n);
        chunks = chunk_by_mesh(frame, job.meshes.size());
    }
    FragmentBuffer sub;   // this mesh's fragments, and their shaded planes: both reused from mesh to mesh
    std::vector<float> part;
    for (std::size_t mi = 0; mi < job.meshes.size() && n > 0; ++mi) {
        // This mesh's fragments, shaded with its material (one launch per material).
        if (!whole) {
            if (chunks.count[mi] == 0) continue;
            fragments_of(frame, chunks, mi, sub);
        }
        ShadeTiming st;
        try {
            shade_mesh(shader, job, job.meshes[mi], whole ? frame.fb : sub, part, st, times.interpolate_ms);
        } catch (const Error& e) {
            throw Error("meshes[" + std::to_string(mi) + "] (model '" + job.meshes[mi].material.model + "'): " + e.what());
        }
        times.build_ms += st.build_ms;
        times.kernel_ms += st.kernel_ms;
        if (whole) {
            rgb = std::move(part);
            break;
        }
        const std::size_t m = chunks.count[mi];
        for_mesh_fragments(frame, chunks, mi, [&](std::size_t i, std::size_t k) {
            for (std::size_t c = 0; c < 3; ++c) rgb[c * n + i] = part[c * m + k];
        });
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

namespace {

// The depth and normal images the job's outputs ask for, after `images`.
void add_aov_images(const Job& job, const Frame& frame, std::vector<OutputImage>& images) {
    const auto& o = job.outputs;
    if (!o.depth.empty()) images.push_back(OutputImage{o.depth, depth_image(job, frame.fb), {}});
    if (!o.normal.empty()) images.push_back(OutputImage{o.normal, normal_image(job, frame.fb), {}});
}

}  // namespace

std::vector<OutputImage> resolve(const Job& job, const Frame& frame, const std::vector<float>& rgb, StageTimes& times) {
    const auto t0 = clock_type::now();
    std::vector<OutputImage> images;
    const auto& o = job.outputs;
    const bool coded = !o.colour.empty() && std::all_of(o.colour.begin(), o.colour.end(), [](const std::string& p) {
        return encoding_for(p) == Encoding::Srgb8;
    });
    if (coded) {
        // 8-bit outputs only: composed and coded at once (a 4096 x 4096 float image is 256 MB of fresh pages, its
        // coding another pass; the coded image is 64 MB).
        Srgb8Image img;
        compose_image_srgb8_into(frame.fb, rgb, job.background, o.colour.front(), img);
        for (std::size_t i = 0; i + 1 < o.colour.size(); ++i) images.push_back(OutputImage{o.colour[i], {}, img});
        images.push_back(OutputImage{o.colour.back(), {}, std::move(img)});
    } else if (!o.colour.empty()) {
        Image img = compose_image(frame.fb, rgb, job.background);
        for (std::size_t i = 0; i + 1 < o.colour.size(); ++i) images.push_back(OutputImage{o.colour[i], img, {}});
        images.push_back(OutputImage{o.colour.back(), std::move(img), {}});
    }
    add_aov_images(job, frame, images);
    times.resolve_ms += ms_since(t0);
    return images;
}

void resolve_and_write(const Job& job, const Frame& frame, const std::vector<float>& rgb, StageTimes& times) {
    const auto& o = job.outputs;
    const bool folded = !o.colour.empty() && std::all_of(o.colour.begin(), o.colour.end(), [&](const std::string& p) {
        return png_composed_in_pieces(p, frame.fb.width, frame.fb.height);
    });
    if (!folded) return write(resolve(job, frame, rgb, times), times);
    const auto t0 = clock_type::now();
    std::vector<OutputImage> aovs;
    add_aov_images(job, frame, aovs);
    times.resolve_ms += ms_since(t0);
    const auto t1 = clock_type::now();
    for (const std::string& path : o.colour) write_image_composed(path, frame.fb, rgb, job.background);
    times.write_ms += ms_since(t1);
    write(aovs, times);
}

void write(const std::vector<OutputImage>& images, StageTimes& times) {
    const auto t0 = clock_type::now();
    for (const OutputImage& img : images) {
        if (!img.srgb8.bytes.empty())
            write_image(img.path, img.srgb8);
        else
            write_image(img.path, img.linear);
    }
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
