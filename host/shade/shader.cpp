#include "shade/shader.hpp"
#include "shade/shade_program.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "consts/scene.h"   // DeviceLight, DeviceView, shared with kernels/shade.cl
#include "core/error.hpp"
#include "models/catalogue.hpp"
#include "raster/big_buffer.hpp"

namespace shadelab {

namespace {

std::vector<DeviceLight> pack_lights(const std::vector<Light>& lights) {
    std::vector<DeviceLight> out;
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const Light& l = lights[i];
        const std::string which = "light " + std::to_string(i + 1);
        for (int c = 0; c < 3; ++c) {
            if (!std::isfinite(l.vec[c])) throw Error(which + " has a non-finite position/direction");
            if (!std::isfinite(l.colour[c]) || l.colour[c] < 0) throw Error(which + " colour must be finite and >= 0");
        }
        if (!std::isfinite(l.intensity) || l.intensity < 0) throw Error(which + " intensity must be finite and >= 0");
        if (!std::isfinite(l.range) || l.range < 0) throw Error(which + " range must be finite and >= 0 (0 = unbounded)");
        DeviceLight g{};
        glm::dvec3 v = l.vec;
        if (l.type == Light::Type::Directional) {
            const double len = glm::length(v);
            if (!(len > 0)) throw Error(which + " is directional with a zero direction vector: give a direction");
            v /= len;
        }
        for (int c = 0; c < 3; ++c) {
            g.pos_or_dir[c] = float(v[c]);
            g.radiance[c] = float(l.colour[c] * l.intensity);
        }
        g.type = l.type == Light::Type::Directional ? 0.0f : 1.0f;
        g.range = float(l.range);
        out.push_back(g);
    }
    if (out.empty()) out.push_back(DeviceLight{});   // a __constant buffer cannot be empty; never read
    return out;
}

std::size_t round_up(std::size_t n, std::size_t m) { return (n + m - 1) / m * m; }

// The environment switch `name`: nothing when it is unset or empty, false for value `a`, true for value `b`; any
// other value throws shadelab::Error, one line naming it, the two values and `what` they choose.
std::optional<bool> env_switch(const char* name, const char* a, const char* b, const char* what) {
    const char* env = std::getenv(name);
    if (!env || !*env) return std::nullopt;
    const std::string v = env;
    if (v != a && v != b)
        throw Error(std::string(name) + " is '" + v + "': use " + a + " or " + b + " (" + what + "), or unset it");
    return v == b;
}

// The material's table buffer (kernels/shade.cl's `tab`, the last argument of every kernel there): one float,
// never read, for a model without tables.
cl::Buffer table_buffer(cl::Context& ctx, const Material& resolved) {
    std::vector<float> tab = pack_table(resolved);
    return cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, tab.size() * sizeof(float), tab.data());
}

// The view as the kernels take it: an orthographic direction (w = 0) made unit; every component finite.
glm::dvec4 checked_view(const glm::dvec4& v) {
    for (int c = 0; c < 4; ++c)
        if (!std::isfinite(v[c])) throw Error("view position/direction is not finite");
    if (v.w != 0.0) return v;
    const double len = glm::length(glm::dvec3(v));
    if (!(len > 0)) throw Error("orthographic view direction is zero: give a direction to the viewer");
    return glm::dvec4(glm::dvec3(v) / len, 0.0);
}

double ms_between(const cl::Event& e) {
    const auto t0 = e.getProfilingInfo<CL_PROFILING_COMMAND_START>();
    const auto t1 = e.getProfilingInfo<CL_PROFILING_COMMAND_END>();
    return double(t1 - t0) * 1e-6;
}

// A read-only buffer over `count` floats at p, in place: PoCL's CPU device reads host memory given with
// CL_MEM_USE_HOST_PTR directly (whatever its alignment), so no copy is made. The kernel never writes it.
cl::Buffer in_place(cl::Context& ctx, const float* p, std::size_t count) {
    return cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, count * sizeof(float), const_cast<float*>(p));
}

// A read-only buffer of `padded` floats: v's first `head` floats and its floats from `from` on (together fewer
// than `padded`), then zeros that shade (0, 0, 0) fragments, never read back. Only the launch's rest needs it.
cl::Buffer padded_copy(cl::Context& ctx, const std::vector<float>& v, std::size_t head, std::size_t from,
                       std::size_t padded) {
    std::vector<float> h(padded, 0.0f);
    std::copy_n(v.begin(), head, h.begin());
    std::copy(v.begin() + std::ptrdiff_t(from), v.end(), h.begin() + std::ptrdiff_t(head));
    return cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, padded * sizeof(float), h.data());
}

// The knot count a table model's program is built for: the material's, rounded up to 4, 8, 16 or the most the
// family allows (the kernel scans that many segment starts, so a short table does not pay for the longest; one
// program per bucket).
std::size_t table_knots_bucket(const ModelInfo& info, const Material& m) {
    std::size_t knots = 2, most = 2;
    for (const auto& t : info.tables)
        if (t.knots) {
            auto it = m.tables.find(t.name);
            knots = it == m.tables.end() ? t.def.size() : it->second.size();
            most = t.max_length;
        }
    for (std::size_t b : {std::size_t(4), std::size_t(8), std::size_t(16)})
        if (knots <= b && b < most) return b;
    return most;
}

// A program request as one string: what tells the single-model programs apart (Runtime::build's key).
std::string request_key(const ProgramRequest& r) {
    std::string key = r.main_file;
    for (const auto& d : r.defines) key += " -D" + d;
    return key + " " + r.extra_options;
}

// A model whose shade kernel can share a program with others' (kernels/shade_many.cl): no table (SL_TABLE
// changes every kernel of a program), no children (their headers and evals are program-wide defines).
bool shareable(const Material& m) {
    const ModelInfo& info = find_model(m.model);
    return !has_tables(info) && info.children == 0 && m.children.empty();
}

// kernels/shade_many.cl's request for `models` (distinct, shareable, within its slots), given the single-model
// request of one of them: the same defines and options without the model's header and eval, then each model
// file once as SL_HEADER_i and each model's eval as SL_EVAL_i; `dispatch`: one kernel for them all (SL_DISPATCH).
ProgramRequest many_program(const std::vector<const ModelInfo*>& models, const ProgramRequest& single, bool dispatch) {
    ProgramRequest r{"shade_many.cl", {}, single.extra_options};
    if (dispatch) r.defines.push_back("SL_DISPATCH=1");
    for (const std::string& d : single.defines)
        if (d.rfind("SL_MODEL_HEADER=", 0) != 0 && d.rfind("SL_EVAL=", 0) != 0) r.defines.push_back(d);
    std::vector<std::string> headers;
    for (std::size_t i = 0; i < models.size(); ++i) {
        if (std::find(headers.begin(), headers.end(), models[i]->header) == headers.end()) {
            r.defines.push_back("SL_HEADER_" + std::to_string(headers.size()) + "=<" + models[i]->header + ">");
            headers.push_back(models[i]->header);
        }
        r.defines.push_back("SL_EVAL_" + std::to_string(i) + "=" + models[i]->eval);
    }
    return r;
}

}  // namespace

std::size_t Shader::prepare_many(const std::vector<Material>& materials, const std::vector<Light>& lights,
                                 Precision precision, bool dispatch, bool perspective) {
    struct Todo {
        std::string key;   // request_key of the model's own program
        ProgramRequest single;
        const ModelInfo* info;
    };
    std::vector<Todo> todo;
    std::set<std::string> seen;
    for (const Material& given : materials) {
        const Material m = resolve_material(given);
        if (!shareable(m)) continue;
        ProgramRequest single = shade_program(m, lights, precision, rt_.vector_width(), perspective);
        std::string key = request_key(single);
        if (many_.count(key) || !seen.insert(key).second) continue;
        todo.push_back({std::move(key), std::move(single), &find_model(m.model)});
    }
    // A program's models share its fragments a work-item (SL_MAX_LANES or SL_MODEL_LANES, SL_CHAINS): the models of
    // one lanes and chains go together.
    const std::size_t width = rt_.vector_width();
    const auto kind = [width](const Todo& t) {
        return std::make_pair(lanes_for(*t.info, width), chains_for(*t.info, width));
    };
    std::stable_sort(todo.begin(), todo.end(), [&](const Todo& a, const Todo& b) { return kind(a) < kind(b); });
    std::map<std::string, SharedKernel> added;
    for (std::size_t b = 0; b < todo.size();) {   // programs of up to kManyModels models and kManyHeaders files
        std::vector<const ModelInfo*> models;
        std::set<std::string> headers;
        std::size_t e = b;
        for (; e < todo.size() && models.size() < kManyModels; ++e) {
            if (kind(todo[e]) != kind(todo[b])) break;
            headers.insert(todo[e].info->header);
            if (headers.size() > kManyHeaders) break;
            models.push_back(todo[e].info);
        }
        const ProgramRequest req = many_program(models, todo[b].single, dispatch);
        const cl::Program prog = rt_.build(req.main_file, req.defines, req.extra_options);
        for (std::size_t i = b; i < e; ++i)
            added[todo[i].key] = dispatch ? SharedKernel{prog, "shade_fragments_any", int(i - b)}
                                          : SharedKernel{prog, "shade_fragments_" + todo[i].info->eval, -1};
        b = e;
    }
    many_.insert(added.begin(), added.end());
    return added.size();
}

cl::Kernel Shader::shade_kernel(const ProgramRequest& single) {
    const auto it = many_.find(request_key(single));
    if (it != many_.end()) {
        cl::Kernel k(it->second.program, it->second.kernel.c_str());
        // The dispatching kernel's model is its last argument (kernels/shade_many.cl, SL_SHADE_EXTRA_ARGS).
        if (it->second.model >= 0) k.setArg(k.getInfo<CL_KERNEL_NUM_ARGS>() - 1, cl_uint(it->second.model));
        return k;
    }
    return cl::Kernel(rt_.build(single.main_file, single.defines, single.extra_options), "shade_fragments");
}

const char* precision_name(Precision p) { return p == Precision::Fast ? "fast" : "precise"; }

Precision parse_precision(const std::string& name) {
    if (name == "precise") return Precision::Precise;
    if (name == "fast") return Precision::Fast;
    throw Error("precision mode '" + name + "' is unknown: use 'precise' or 'fast'");
}

std::string Shader::options_for(Precision precision) {
    return precision == Precision::Fast ? "-cl-mad-enable" : "";
}

std::vector<std::string> Shader::defines_for(const Material& m, int num_lights, Precision precision) {
    const ModelInfo& info = find_model(m.model);
    std::vector<std::string> d{"SL_MODEL_HEADER=<" + info.header + ">", "SL_EVAL=" + info.eval,
                               "SL_NUM_LIGHTS=" + std::to_string(num_lights)};
    if (precision == Precision::Fast) d.push_back("SL_FAST=1");
    if (has_tables(info)) {   // its eval takes the table buffer (kernels/shade.cl), scanned up to SL_TABLE_KNOTS
        d.push_back("SL_TABLE=1");
        d.push_back("SL_TABLE_KNOTS=" + std::to_string(table_knots_bucket(info, m)));
    }
    for (std::size_t c = 0; c < m.children.size(); ++c) {
        const ModelInfo& ci = find_model(m.children[c].model);
        d.push_back("SL_CHILD" + std::to_string(c) + "_HEADER=<" + ci.header + ">");
        d.push_back("SL_CHILD" + std::to_string(c) + "_EVAL=" + ci.eval);
    }
    return d;
}

std::string light_kinds(const std::vector<Light>& lights) {
    std::string kinds;
    for (const Light& l : lights) kinds += l.type == Light::Type::Directional ? 'd' : (l.range > 0.0 ? 'r' : 'p');
    return kinds;
}

bool light_kinds_in_programs() {
    return env_switch("SHADELAB_LIGHT_KINDS", "0", "1", "each light's kind read at run time or built into the program")
        .value_or(true);
}

std::vector<std::string> light_defines(const std::vector<Light>& lights) {
    // more than the masks hold (a scene has at most 64), or SHADELAB_LIGHT_KINDS=0: the kinds read at run time
    if (lights.size() > 64 || !light_kinds_in_programs()) return {};
    std::uint64_t point = 0, ranged = 0;
    const std::string kinds = light_kinds(lights);
    for (std::size_t l = 0; l < kinds.size(); ++l) {
        if (kinds[l] != 'd') point |= std::uint64_t(1) << l;
        if (kinds[l] == 'r') ranged |= std::uint64_t(1) << l;
    }
    auto mask = [](std::uint64_t m) {   // an unsigned long literal of OpenCL C (64 bits)
        char text[32];
        std::snprintf(text, sizeof text, "0x%llxul", static_cast<unsigned long long>(m));
        return std::string(text);
    };
    return {"SL_POINT_LIGHTS=" + mask(point), "SL_RANGED_LIGHTS=" + mask(ranged)};
}

bool is_perspective(const glm::dvec4& view) { return view.w != 0.0; }

ProgramRequest shade_program(const Material& mat, const std::vector<Light>& lights, Precision precision,
                              std::size_t device_width, bool perspective) {
    std::vector<std::string> defines = Shader::defines_for(mat, int(lights.size()), precision);
    // Each light's kind: the kernel computes no point-light arithmetic for a directional light and no window for a
    // point light without a range, which the vectorised work-item loop would otherwise compute for every fragment
    // and light (kernels/shade_parts.cl, light_incident_v3).
    for (std::string& d : light_defines(lights)) defines.push_back(std::move(d));
    // The view's kind: the vectorised loop does not choose per fragment (kernels/shade_parts.cl, view_dir_v3).
    defines.push_back(perspective ? "SL_PERSPECTIVE=1" : "SL_PERSPECTIVE=0");
    const ModelInfo& info = find_model(mat.model);
    if (info.normals_only)   // Shader::lanes_for
        defines.push_back("SL_MAX_LANES=" + std::to_string(Shader::kNormalsOnlyLanes));
    else if (const std::size_t lanes = Shader::lanes_for(info, device_width); lanes != device_width)
        defines.push_back("SL_MODEL_LANES=" + std::to_string(lanes));
    if (const std::size_t chains = Shader::chains_for(info, device_width); chains > 1)   // Shader::frags_per_item
        defines.push_back("SL_CHAINS=" + std::to_string(chains));
    return {"shade.cl", defines, Shader::options_for(precision)};
}

std::size_t Shader::lanes_for(bool normals_only, std::size_t device_width) {
    return normals_only ? std::min(device_width, kNormalsOnlyLanes) : device_width;
}

std::size_t Shader::lanes_for(const ModelInfo& info, std::size_t device_width) {
    if (info.normals_only) return lanes_for(true, device_width);
    const auto wide = env_switch("SHADELAB_WIDE_LANES", "0", "1", "sixteen lanes a shading work-item on an 8-lane device");
    return device_width == 8 && wide.value_or(info.lanes_avx2 == int(kWideLanes)) ? kWideLanes : device_width;
}

std::size_t Shader::chains_for(const ModelInfo& info, std::size_t device_width) {
    const auto two = env_switch("SHADELAB_CHAINS", "1", "2", "chains a shading work-item runs");
    return two.value_or((device_width >= 16 ? info.chains : info.chains_avx2) > 1) ? 2 : 1;
}

bool Shader::streams_output(std::size_t n) {
    return env_switch("SHADELAB_STREAM_STORES", "0", "1", "plain or streaming stores of the shaded planes")
        .value_or(3 * n * sizeof(float) >= kStreamOutputBytes);
}

bool Shader::streams_output(const ModelInfo& info, std::size_t n) {
    // the size rule and the variable as above; a plain-store model streams only when the variable says 1
    return info.plain_stores ? streams_output(0) : streams_output(n);
}

bool Shader::streams_output(const ModelInfo& info, std::size_t n, std::size_t per_item) {
    // a work-item's block of a plane short of a whole 64-byte line: plain stores unless the variable says 1, or the
    // model reads N and L only (at memory speed, where plain stores' write-allocate read cost more than half lines)
    const bool whole_lines = per_item * sizeof(float) % kLineBytes == 0;
    return whole_lines || info.normals_only ? streams_output(info, n) : streams_output(info, 0);
}

std::size_t Shader::frags_per_item(const ModelInfo& info, std::size_t device_width) {
    return frags_of(lanes_for(info, device_width), chains_for(info, device_width));
}

namespace {

// The per-launch arguments of a shade kernel (kernels/shade_fragments.cl: the six input planes, the output and
// its plane stride); the others are the same for every launch of a frame.
struct LaunchBuffers {
    cl::Buffer in[6];
    cl::Buffer out;
    std::size_t stride = 0;
    cl_uint stream = 0;   // the planes written with streaming stores (kernels/common.cl, SL_STREAM_PLANE)
    std::size_t count = 0;   // fragments the input buffers hold (kernels/shade_fragments.cl, `count`)
};

// The kernel's `stream` mask for output planes that start at `plane0` and `stride` floats apart, when the launch
// streams (Shader::streams_output): a plane's bit is set where it starts on a 64-byte line. Every work-item's
// block then starts on a boundary of the vector it is stored in (a block is SL_FRAGS_PER_ITEM floats from the
// plane's start, a multiple of that vector's 8 or 16 floats: kernels/common.cl, sl_store_block).
cl_uint streamed_planes(const float* plane0, std::size_t stride, bool stream) {
    cl_uint mask = 0;
    for (std::size_t c = 0; stream && c < 3; ++c)
        if (reinterpret_cast<std::uintptr_t>(plane0 + c * stride) % Shader::kLineBytes == 0) mask |= cl_uint(1) << c;
    return mask;
}

// The six planes of `fb`, in the kernel's argument order.
std::array<const std::vector<float>*, 6> planes_of(const FragmentBuffer& fb) {
    return {&fb.px, &fb.py, &fb.pz, &fb.nx, &fb.ny, &fb.nz};
}

// The body's inputs: `body` fragments of each plane from `first` on, in place (zero-copy).
LaunchBuffers body_planes(cl::Context& ctx, const FragmentBuffer& fb, std::size_t first, std::size_t body) {
    LaunchBuffers b;
    for (int c = 0; c < 6; ++c) b.in[c] = in_place(ctx, planes_of(fb)[std::size_t(c)]->data() + first, body);
    return b;
}

// The rest's inputs: each plane's first `head` fragments and those from `from` on, copied and padded to
// `padded` fragments (whole work-groups).
LaunchBuffers rest_planes(cl::Context& ctx, const FragmentBuffer& fb, std::size_t head, std::size_t from,
                          std::size_t padded) {
    LaunchBuffers b;
    for (int c = 0; c < 6; ++c) b.in[c] = padded_copy(ctx, *planes_of(fb)[std::size_t(c)], head, from, padded);
    return b;
}

// The body's launch: `body` fragments from `head` on, read in place, their results written in place into `out`
// (three planes of fb.size() floats), streamed where `stream` and a plane's start allow (streamed_planes).
LaunchBuffers body_launch(cl::Context& ctx, const FragmentBuffer& fb, std::size_t head, std::size_t body,
                          std::vector<float>& out, bool stream) {
    LaunchBuffers b = body_planes(ctx, fb, head, body);
    b.out = cl::Buffer(ctx, CL_MEM_WRITE_ONLY | CL_MEM_USE_HOST_PTR, (out.size() - head) * sizeof(float),
                       out.data() + head);
    b.stride = fb.size();
    b.stream = streamed_planes(out.data() + head, fb.size(), stream);
    b.count = body;
    return b;
}

// The rest launch: the first `head` fragments and those from `from` on, padded to whole work-groups (the
// planes of `rest_out`, three of rest_out.size() / 3 floats, which receives their results).
LaunchBuffers rest_launch(cl::Context& ctx, const FragmentBuffer& fb, std::size_t head, std::size_t from,
                          std::vector<float>& rest_out) {
    const std::size_t padded = rest_out.size() / 3;
    LaunchBuffers b = rest_planes(ctx, fb, head, from, padded);
    b.out = cl::Buffer(ctx, CL_MEM_WRITE_ONLY | CL_MEM_USE_HOST_PTR, rest_out.size() * sizeof(float),
                       rest_out.data());
    b.stride = padded;
    b.count = padded;
    return b;
}

// Enqueues one launch of `launched` fragments' work-items (a multiple of the work-group's `local` fragments
// unless `local` is kLocalAuto; at least b.count), `per_item` fragments a work-item (the program's
// SL_FRAGS_PER_ITEM: kernels/common.cl).
cl::Event enqueue_launch(cl::CommandQueue& q, cl::Kernel& k, const LaunchBuffers& b, std::size_t launched,
                         std::size_t local, std::size_t per_item) {
    for (cl_uint c = 0; c < 6; ++c) k.setArg(c, b.in[c]);
    k.setArg(6, b.out);
    k.setArg(7, cl_uint(b.stride));
    k.setArg(13, b.stream);
    k.setArg(14, cl_uint(b.count));
    cl::Event ev;
    const cl::NDRange groups = local == Shader::kLocalAuto ? cl::NullRange : cl::NDRange(local / per_item);
    q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(launched / per_item), groups, nullptr, &ev);
    return ev;
}

// Sets the arguments that a frame's launches share (kernels/shade_fragments.cl: view, material constants, lights,
// ambient, tables) and returns the buffers behind them, which must outlive the launches.
std::array<cl::Buffer, 3> set_frame_args(cl::Context& ctx, cl::Kernel& k, const std::vector<ModelConsts>& consts,
                                         const std::vector<DeviceLight>& lights, const glm::dvec4& view,
                                         const glm::dvec3& ambient, const Material& mat) {
    std::array<cl::Buffer, 3> b{
        cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, consts.size() * sizeof(ModelConsts),
                   const_cast<ModelConsts*>(consts.data())),
        cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, lights.size() * sizeof(DeviceLight),
                   const_cast<DeviceLight*>(lights.data())),
        table_buffer(ctx, mat)};
    const DeviceView dview{{float(view.x), float(view.y), float(view.z)}, float(view.w)};
    k.setArg(8, sizeof dview, &dview);
    k.setArg(9, b[0]);
    k.setArg(10, b[1]);
    k.setArg(11, cl_float4{{float(ambient.x), float(ambient.y), float(ambient.z), 0.0f}});
    k.setArg(12, b[2]);
    return b;
}

// The output buffers' read maps, which make the kernels' writes visible at the host pointers (on a CPU device a
// mapping is the host memory itself: no copy). They are enqueued behind the launches without blocking, so that
// the frame waits once for launches and maps together: each blocking call is a round trip to the device's
// threads, which costs as much as a small frame's kernel.
struct ReadMap {
    const cl::Buffer* buf = nullptr;
    float* host = nullptr;
    std::size_t floats = 0;
    void* mapped = nullptr;
};

void enqueue_read_map(cl::CommandQueue& q, ReadMap& m) {
    m.mapped = q.enqueueMapBuffer(*m.buf, CL_FALSE, CL_MAP_READ, 0, m.floats * sizeof(float));
}

// After the queue has finished: the mapped results at the host pointer (a copy only where the device mapped
// elsewhere), and the unmap enqueued.
void finish_read_map(cl::CommandQueue& q, const ReadMap& m) {
    if (m.mapped != m.host) std::memcpy(m.host, m.mapped, m.floats * sizeof(float));
    q.enqueueUnmapMemObject(*m.buf, m.mapped);
}

// Fragments from p (a plane of n floats) to the first that starts a 64-byte line: 0 to 15 (0 when p is not even
// float-aligned, or when there are not that many fragments).
std::size_t fragments_to_line(const float* p, std::size_t n) {
    const std::uintptr_t a = reinterpret_cast<std::uintptr_t>(p);
    if (a % sizeof(float) != 0) return 0;
    const std::size_t line = Shader::kLineBytes, h = std::size_t((line - a % line) % line) / sizeof(float);
    return h < n ? h : 0;
}

// The rest launch's results (planes of `rest_n`: the `head` fragments, then the tail) into their places in `out`
// (planes of n = out.size() / 3), around the body's `body` fragments.
void place_rest(const std::vector<float>& rest_out, std::size_t rest_n, std::size_t head, std::size_t body,
                std::vector<float>& out) {
    const std::size_t n = out.size() / 3, tail = n - head - body;
    for (std::size_t c = 0; c < 3; ++c) {
        const auto from = rest_out.begin() + std::ptrdiff_t(c * rest_n);
        std::copy_n(from, head, out.begin() + std::ptrdiff_t(c * n));
        std::copy_n(from + std::ptrdiff_t(head), tail, out.begin() + std::ptrdiff_t(c * n + head + body));
    }
}

}  // namespace

// The kernel has no bounds check, so each launch covers a whole number of work-groups; its work-items past the
// fragments it is given shade the last block of them again (kernels/shade_fragments.cl, `count`). The body reads
// the fragment planes and writes `out` in place, with no copy either way, to the last fragment; the fragments
// before it (the head, when streamed: Shader::streams_output) go through small padded copies in a second launch,
// and so does everything when there are fewer fragments than a work-item shades.
std::vector<float> Shader::shade(const FragmentBuffer& fb, const ShadeSetup& setup, ShadeTiming* timing) {
    std::vector<float> out;
    shade_into(fb, setup, out, timing);
    return out;
}

void Shader::shade_into(const FragmentBuffer& fb, const ShadeSetup& setup, std::vector<float>& out,
                        ShadeTiming* timing) {
    const Material mat = resolve_material(setup.material);
    const std::size_t n = fb.size();
    if (n == 0) {
        out.clear();
        return;
    }
    if (n > 0xffffffffu) throw Error("fragment buffer too large for one launch (" + std::to_string(n) + ")");
    const auto consts = pack_material(mat);
    const auto lights = pack_lights(setup.lights);
    const glm::dvec4 view = checked_view(setup.view);

    using clock = std::chrono::steady_clock;
    const std::size_t local = setup.local_size == 0 ? kLocalSize : setup.local_size;
    const std::size_t group = local == kLocalAuto ? kLocalSize : local;
    // fragments a work-item: the program's SL_FRAGS_PER_ITEM (kernels/common.cl)
    const ModelInfo& info = find_model(mat.model);
    const std::size_t per_item = frags_per_item(info, rt_.vector_width());
    if (group % per_item != 0)
        throw Error("work-group size " + std::to_string(group) + " is not a multiple of the " +
                    std::to_string(per_item) + " fragments a work-item shades on this device: use a multiple of " +
                    std::to_string(per_item) + " (or SHADELAB_VECTOR_WIDTH)");
    // Fresh `out` pages are touched here (zero-filled, huge pages advised: a 4096x4096 frame's 44 MB took ~26 ms
    // of 4 KB page faults), not first-touched page by page inside the kernel's time; `out`'s own memory is
    // reused when it is large enough (a renderer's next frame: the zero-fill was another 6-8 ms at 4096x4096).
    size_for_frame(out, 3 * n);
    // Streamed, the body starts at the first fragment whose red output begins a 64-byte line (kernels/common.cl,
    // sl_store_block, streams aligned blocks only); the `head` before it goes into the rest launch. The body
    // runs to the last fragment (one launch for a frame that is not streamed: a second launch, its padded copies
    // and its map took 0.05 ms of a 0.2 ms shading step at 512 x 512, bench_e2e).
    const bool stream = streams_output(info, n, per_item);
    const std::size_t head = stream ? fragments_to_line(out.data(), n) : 0;
    const std::size_t body = n - head >= per_item ? n - head : 0, tail = n - head - body;
    const std::size_t rest_n = round_up(head + tail, group);
    std::vector<float> rest_out(3 * rest_n);
    try {
        const auto t0 = clock::now();
        cl::Kernel k = shade_kernel(
            shade_program(mat, setup.lights, setup.precision, rt_.vector_width(), is_perspective(view)));
        const auto t1 = clock::now();
        auto& ctx = rt_.context();
        auto& q = rt_.queue();
        LaunchBuffers main, rest;
        if (body) main = body_launch(ctx, fb, head, body, out, stream);
        if (rest_n) rest = rest_launch(ctx, fb, head, head + body, rest_out);
        const std::array<cl::Buffer, 3> frame_args = set_frame_args(ctx, k, consts, lights, view, setup.ambient, mat);
        const auto t2 = clock::now();
        cl::Event ev_main, ev_rest;
        ReadMap map_main{&main.out, out.data() + head, out.size() - head};
        ReadMap map_rest{&rest.out, rest_out.data(), rest_out.size()};
        if (body) ev_main = enqueue_launch(q, k, main, round_up(body, group), local, per_item);
        if (rest_n) ev_rest = enqueue_launch(q, k, rest, rest_n, local, per_item);
        if (body) enqueue_read_map(q, map_main);
        if (rest_n) enqueue_read_map(q, map_rest);
        q.finish();
        const auto t3 = clock::now();
        if (body) finish_read_map(q, map_main);
        if (rest_n) finish_read_map(q, map_rest);
        q.finish();   // the unmaps done before the buffers and `rest_out` go
        if (rest_n) place_rest(rest_out, rest_n, head, body, out);
        const auto t4 = clock::now();
        if (timing) {
            auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
            timing->build_ms = ms(t0, t1);
            timing->upload_ms = ms(t1, t2);
            timing->kernel_ms = (body ? ms_between(ev_main) : 0.0) + (rest_n ? ms_between(ev_rest) : 0.0);
            timing->download_ms = ms(t3, t4);
        }
    } catch (const cl::Error& e) {
        rethrow_cl(e, "shading " + std::to_string(n) + " fragments with model '" + mat.model + "'");
    }
}

// The program Shader::shade builds for `mat`, one directional light and a perspective view (its lanes and chains):
// eval_directions and eval_batch run from it (their kernels take V as given), so one build serves the three kernels.
cl::Program Shader::one_light_program(const Material& mat, Precision precision) {
    const ProgramRequest req = shade_program(mat, {Light{}}, precision, rt_.vector_width(), true);
    return rt_.build(req.main_file, req.defines, req.extra_options);
}

std::vector<float> Shader::eval_directions(const Material& material, const std::vector<float>& N,
                                           const std::vector<float>& L, const std::vector<float>& V,
                                           const std::vector<float>& P, Precision precision) {
    const std::size_t n = N.size() / 3;
    if (N.size() != 3 * n || L.size() != 3 * n || V.size() != 3 * n || P.size() != 3 * n)
        throw Error("eval_directions: N, L, V, P must all hold 3n floats");
    std::vector<float> out(3 * n);
    eval_directions_into(material, N.data(), L.data(), V.data(), P.data(), n, out.data(), precision);
    return out;
}

void Shader::eval_directions_into(const Material& material, const float* N, const float* L, const float* V,
                                  const float* P, std::size_t n, float* out, Precision precision) {
    if (n == 0) return;
    const Material mat = resolve_material(material);
    // kernels/shade.cl: per_item triples a work-item, and at least per_item triples in the buffers: fewer are
    // copied into arrays of per_item triples (the last one repeated, its values not read back)
    const std::size_t per_item = frags_per_item(find_model(mat.model), rt_.vector_width());
    if (n < per_item) {
        std::vector<float> in[4], padded_out(3 * per_item);
        const float* src[4] = {N, L, V, P};
        for (int v = 0; v < 4; ++v) {
            if (!src[v]) continue;
            in[v].assign(src[v], src[v] + 3 * n);
            for (std::size_t i = n; i < per_item; ++i) in[v].insert(in[v].end(), src[v] + 3 * (n - 1), src[v] + 3 * n);
        }
        eval_directions_into(material, in[0].data(), in[1].data(), in[2].data(), P ? in[3].data() : nullptr,
                             per_item, padded_out.data(), precision);
        std::copy_n(padded_out.begin(), 3 * n, out);
        return;
    }
    const auto consts = pack_material(mat);
    try {
        cl::Kernel k(one_light_program(mat, precision), "eval_directions");
        auto& ctx = rt_.context();
        auto& q = rt_.queue();
        const std::size_t bytes = 3 * n * sizeof(float);
        // the caller's arrays in place (no copy); no P is zeros, filled on the device
        cl::Buffer bn = in_place(ctx, N, 3 * n), bl = in_place(ctx, L, 3 * n), bv = in_place(ctx, V, 3 * n);
        cl::Buffer bp = P ? in_place(ctx, P, 3 * n) : cl::Buffer(ctx, CL_MEM_READ_ONLY, bytes);
        if (!P) q.enqueueFillBuffer(bp, 0.0f, 0, bytes);
        cl::Buffer bout(ctx, CL_MEM_WRITE_ONLY | CL_MEM_USE_HOST_PTR, bytes, out);
        cl::Buffer bconsts(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, consts.size() * sizeof(ModelConsts),
                           const_cast<ModelConsts*>(consts.data()));
        k.setArg(0, bn); k.setArg(1, bl); k.setArg(2, bv); k.setArg(3, bp);
        k.setArg(4, bout);
        k.setArg(5, cl_uint(n));
        k.setArg(6, bconsts);
        cl::Buffer btab = table_buffer(ctx, mat);
        k.setArg(7, btab);
        const std::size_t group = kLocalSize / per_item;   // work-items a group: kLocalSize triples
        q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up((n + per_item - 1) / per_item, group)),
                               cl::NDRange(group));
        ReadMap map{&bout, out, 3 * n, nullptr};   // the results at `out` (on a CPU device, out itself)
        enqueue_read_map(q, map);
        q.finish();
        finish_read_map(q, map);
        q.finish();
    } catch (const cl::Error& e) {
        rethrow_cl(e, "evaluating model '" + mat.model + "' on " + std::to_string(n) + " direction triples");
    }
}

Shader::DeviceSamples Shader::upload_samples(const std::vector<float>& N, const std::vector<float>& L,
                                             const std::vector<float>& V, const std::vector<float>& P) {
    const std::size_t n = N.size() / 3;
    if (N.size() != 3 * n || L.size() != 3 * n || V.size() != 3 * n || P.size() != 3 * n)
        throw Error("upload_samples: N, L, V, P must all hold 3n floats");
    if (n == 0) throw Error("upload_samples: no samples");
    DeviceSamples d;
    d.n = n;
    d.stride = round_up(n, kLocalSize);
    std::vector<float> planes(12 * d.stride, 0.0f);   // the padding: zero directions, values never read
    const std::vector<float>* src[4] = {&N, &L, &V, &P};
    for (int v = 0; v < 4; ++v)
        for (int c = 0; c < 3; ++c)
            for (std::size_t i = 0; i < n; ++i) planes[(3 * v + c) * d.stride + i] = (*src[v])[3 * i + c];
    try {
        d.dirs = cl::Buffer(rt_.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, planes.size() * sizeof(float),
                            planes.data());
    } catch (const cl::Error& e) {
        rethrow_cl(e, "uploading " + std::to_string(n) + " fit samples");
    }
    return d;
}

std::vector<float> Shader::eval_batch(const Material& shape, const DeviceSamples& d,
                                      const std::vector<ModelConsts>& consts, Precision precision, double* kernel_ms,
                                      int planes) {
    if (planes != 1 && planes != 3) throw Error("eval_batch: planes must be 1 or 3");
    const ModelInfo& info = find_model(shape.model);
    const std::size_t per_set = 1 + std::size_t(info.children);
    if (consts.empty() || consts.size() % per_set != 0)
        throw Error("eval_batch: " + std::to_string(consts.size()) + " constant blocks is not a whole number of sets of " +
                    std::to_string(per_set) + " for model '" + shape.model + "'");
    const std::size_t sets = consts.size() / per_set;
    const std::size_t np = std::size_t(planes);
    std::vector<float> out(np * d.n * sets);
    if (kernel_ms) *kernel_ms = 0.0;
    try {
        // eval_batch runs its fragment loop, frags_per_item samples a work-item (kernels/shade.cl)
        cl::Kernel k(one_light_program(shape, precision), "eval_batch");
        const std::size_t per_item = frags_per_item(info, rt_.vector_width());   // divides kLocalSize (<= 32)
        auto& ctx = rt_.context();
        // the shape's table: every set of a batch shares it (a table is not a fitted parameter)
        cl::Buffer btab = table_buffer(ctx, resolve_material(shape));
        auto& q = rt_.queue();
        // Sets per launch: what fits the device's __constant buffer and about 64 MB of output.
        const std::size_t const_bytes = rt_.device().getInfo<CL_DEVICE_MAX_CONSTANT_BUFFER_SIZE>();
        const std::size_t by_const = std::max<std::size_t>(1, const_bytes / (per_set * sizeof(ModelConsts)));
        const std::size_t by_out = std::max<std::size_t>(1, (std::size_t(64) << 20) / (3 * d.stride * sizeof(float)));
        const std::size_t chunk = std::min({sets, by_const, by_out});
        const std::size_t plane_bytes = d.stride * sizeof(float);
        if (batch_out_bytes_ < 3 * chunk * plane_bytes) {
            batch_out_ = cl::Buffer(ctx, CL_MEM_WRITE_ONLY, 3 * chunk * plane_bytes);
            batch_out_bytes_ = 3 * chunk * plane_bytes;
        }
        cl::Buffer& bout = batch_out_;
        std::vector<float> host(d.stride == d.n ? 0 : 3 * chunk * d.stride);
        for (std::size_t s0 = 0; s0 < sets; s0 += chunk) {
            const std::size_t ns = std::min(chunk, sets - s0);
            cl::Buffer bconsts(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, ns * per_set * sizeof(ModelConsts),
                               const_cast<ModelConsts*>(consts.data() + s0 * per_set));
            k.setArg(0, d.dirs);
            k.setArg(1, bout);
            k.setArg(2, cl_uint(d.stride));
            k.setArg(3, cl_uint(per_set));
            k.setArg(4, bconsts);
            k.setArg(5, btab);
            cl::Event ev;
            q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(d.stride / per_item, ns),
                                   cl::NDRange(kLocalSize / per_item, 1), nullptr, &ev);
            if (d.stride == d.n && np == 3) {   // the layouts agree: straight into `out`
                q.enqueueReadBuffer(bout, CL_TRUE, 0, 3 * ns * plane_bytes, out.data() + 3 * s0 * d.n);
            } else if (d.stride == d.n) {       // the red plane of each set
                for (std::size_t s = 0; s < ns; ++s)
                    q.enqueueReadBuffer(bout, CL_FALSE, 3 * s * plane_bytes, plane_bytes, out.data() + (s0 + s) * d.n);
                q.finish();
            } else {
                q.enqueueReadBuffer(bout, CL_TRUE, 0, 3 * ns * plane_bytes, host.data());
                for (std::size_t s = 0; s < ns; ++s)
                    for (std::size_t c = 0; c < np; ++c)
                        std::copy_n(host.begin() + (3 * s + c) * d.stride, d.n, out.begin() + (np * (s0 + s) + c) * d.n);
            }
            if (kernel_ms) *kernel_ms += ms_between(ev);
        }
    } catch (const cl::Error& e) {
        rethrow_cl(e, "evaluating model '" + shape.model + "' for " + std::to_string(sets) + " parameter sets on " +
                          std::to_string(d.n) + " samples");
    }
    return out;
}

}  // namespace shadelab
