// Runs a material's model over a fragment buffer (or over raw direction triples) on the OpenCL device.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "cl/prebuild.hpp"
#include "cl/runtime.hpp"
#include "core/fragment_buffer.hpp"
#include "models/catalogue.hpp"
#include "models/material.hpp"

namespace shadelab {

// How the kernels compute (see kernels/common.cl): precise = the OpenCL built-ins and a double-precision pow;
// fast = native_ forms and a float pow, built with -cl-mad-enable. Errors of each are measured in docs/precision.md.
enum class Precision { Precise, Fast };
const char* precision_name(Precision p);
Precision parse_precision(const std::string& name);   // "precise" | "fast"; throws shadelab::Error

struct ShadeSetup {
    Material material;                  // resolved (resolve_material) or it will be resolved here
    std::vector<Light> lights;
    glm::dvec3 ambient{0.0};
    // w = 1: xyz is the camera position (perspective views); w = 0: xyz is the direction to the viewer,
    // the same for every fragment (orthographic views such as the moon disc).
    glm::dvec4 view{0.0, 0.0, 3.0, 1.0};
    Precision precision = Precision::Precise;
    // Work-group size of the launch in fragments (a multiple of Runtime::vector_width(), the fragments a
    // work-item shades): 0 = Shader::kLocalSize; Shader::kLocalAuto = let the OpenCL runtime choose (NullRange).
    // Only the benchmark's local-size study sets it; the result does not depend on it.
    std::size_t local_size = 0;
};

struct ShadeTiming {
    double build_ms = 0.0;     // program build (0 when cached)
    // Buffer set-up: the fragment planes are used in place (no copy on a CPU device); only the head of a
    // streamed launch (fewer than 16 fragments), or a buffer of fewer fragments than a work-item shades, is
    // copied (padded), with the material's constants and lights.
    double upload_ms = 0.0;
    double kernel_ms = 0.0;    // device time of the kernel launches (profiling events)
    // Making the results visible to the host, after the one wait for the launches and the output's read maps
    // (enqueued behind them; no copy on a CPU device): the unmaps, then the head's few results copied into place.
    double download_ms = 0.0;
};

class Shader {
public:
    explicit Shader(Runtime& runtime) : rt_(runtime) {}

    // Returns three planes of n floats: all red, then all green, then all blue (linear radiance).
    // The kernel comes from a program prepare_many() built when it holds this material's, else from the
    // material's own program (kernels/shade.cl; built at the first use, then cached by the Runtime).
    std::vector<float> shade(const FragmentBuffer& fragments, const ShadeSetup& setup, ShadeTiming* timing = nullptr);
    // The same into `out` (resized to 3n), whose memory is reused when it is large enough: a renderer that keeps
    // `out` from frame to frame pays no fresh pages (at 4096x4096, 44 MB zero-filled, 6-8 ms a frame).
    void shade_into(const FragmentBuffer& fragments, const ShadeSetup& setup, std::vector<float>& out,
                    ShadeTiming* timing = nullptr);

    // Builds, for these lights and precision, programs holding the shade kernels of many of `materials` at once
    // (kernels/shade_many.cl: up to kManyModels models of up to kManyHeaders model files per program), so that
    // shading them all costs one program build instead of one per model (PoCL's cost of a program is mostly
    // fixed: docs/speed.md, "The whole process"). Covers the materials without tables or children (those keep
    // their own programs) whose program is not prepared yet; shade() of a covered material with the same lights
    // (every light's kind in order: shade_program.hpp, light_kinds), precision and kind of view (`perspective`:
    // shade_program.hpp, is_perspective) then uses its kernel there, the same code as its own program's. Returns
    // how many distinct models it added. A build failure throws shadelab::Error (nothing is added; shade() then
    // builds each material's own program).
    // `dispatch` true: each program holds one kernel for all its models (shade_fragments_any, picking the model by
    // an argument) instead of one per model, so PoCL compiles one work-group function at the first launch instead
    // of one per model (about 0.09 s of CPU each). The same pixels, but the kernel is not vectorised: for a cold
    // run of many small launches (the contact sheet), never where shading speed matters.
    std::size_t prepare_many(const std::vector<Material>& materials, const std::vector<Light>& lights,
                             Precision precision = Precision::Precise, bool dispatch = false, bool perspective = true);
    static constexpr std::size_t kManyModels = 64, kManyHeaders = 16;   // kernels/shade_many.cl's slots

    // Fragments a work-item of a model's shade kernel evaluates on a device of `device_width` lanes
    // (Runtime::vector_width()): all of them, except that the models that read normals only (`normals_only`:
    // ModelInfo::normals_only) take no more than kNormalsOnlyLanes (their programs are built with SL_MAX_LANES,
    // kernels/common.cl). Those run at memory speed, and 16 lanes in 512-bit registers ran them at 0.80-0.87x
    // of 8 lanes on an Intel AVX-512 host, while every model with more arithmetic gained (docs/speed.md,
    // "Sixteen lanes").
    static constexpr std::size_t kNormalsOnlyLanes = 8;
    static std::size_t lanes_for(bool normals_only, std::size_t device_width);
    // The lanes of `info`'s shade kernel: lanes_for(info.normals_only, device_width), except that on a device of 8
    // lanes (an AVX2 host's) the models registered with sixteen (ModelInfo::lanes_avx2; their programs are built
    // with SL_MODEL_LANES=16) take kWideLanes, unless the environment's SHADELAB_WIDE_LANES (0 or 1) sets it for
    // every model but those of N and L only (for measuring the choice); throws shadelab::Error on any other value.
    static constexpr std::size_t kWideLanes = 16;
    static std::size_t lanes_for(const ModelInfo& info, std::size_t device_width);
    // Chains a work-item of `info`'s shade kernel runs on a device of `device_width` lanes (kernels/common.cl,
    // SL_CHAINS): ModelInfo::chains at 16 lanes (AVX-512 hosts), ModelInfo::chains_avx2 at fewer (AVX2 hosts),
    // unless the environment's SHADELAB_CHAINS (1 or 2) sets it for every model (for measuring the choice); throws
    // shadelab::Error on any other value of it.
    static std::size_t chains_for(const ModelInfo& info, std::size_t device_width);
    // Fragments a work-item of `info`'s shade kernel evaluates: lanes_for(info) times chains_for, by frags_of.
    static std::size_t frags_per_item(const ModelInfo& info, std::size_t device_width);
    // Fragments (or photometric rows) a work-item of `lanes` lanes and `chains` chains evaluates: lanes x chains,
    // and 1 at one lane, where there is no fragment loop and so no second chain (kernels/common.cl,
    // SL_FRAGS_PER_ITEM).
    static std::size_t frags_of(std::size_t lanes, std::size_t chains) { return lanes > 1 ? lanes * chains : 1; }
    // Whether a launch shading n fragments writes its output planes with streaming (non-temporal) stores
    // (kernels/common.cl, sl_store_block): when the three planes, 12n bytes, are at least kStreamOutputBytes, past
    // the last-level cache, where a plain store first reads each line from memory. The environment's
    // SHADELAB_STREAM_STORES (0 or 1) sets it for every launch (for measuring the choice); throws
    // shadelab::Error on any other value of it. docs/speed.md, "Streaming stores".
    static constexpr std::size_t kStreamOutputBytes = std::size_t(32) << 20;
    static bool streams_output(std::size_t n);
    // The same for a launch of `info`'s kernel: plain stores at every size for a model with
    // ModelInfo::plain_stores (streaming measured slower for it), unless SHADELAB_STREAM_STORES sets it.
    static bool streams_output(const ModelInfo& info, std::size_t n);
    // The same for a launch whose work-items shade `per_item` fragments each: plain stores (unless
    // SHADELAB_STREAM_STORES sets it) where a work-item's block of a plane is not a whole number of 64-byte lines
    // (8 lanes at one chain, an AVX2 host's one-chain models: 32 bytes), except for the models of N and L only
    // (half_lambert lost 0.82-0.94x with plain stores: it runs at memory speed). Each line is then written by two
    // work-items' non-temporal stores, half each, and that measured slower than plain stores on an AMD Zen 3
    // (minnaert_1941 at one chain, 16M fragments: 173-189 Mfrag/s streamed, 246-249 plain; docs/speed.md,
    // "Half lines").
    static constexpr std::size_t kLineBytes = 64;
    static bool streams_output(const ModelInfo& info, std::size_t n, std::size_t per_item);

    // The model alone for direction triples: N, L, V, P are xyz-interleaved (3n floats each);
    // returns rgb interleaved (3n floats). Used by the kernel-vs-reference sweeps.
    std::vector<float> eval_directions(const Material& material, const std::vector<float>& N,
                                       const std::vector<float>& L, const std::vector<float>& V,
                                       const std::vector<float>& P, Precision precision = Precision::Precise);
    // The same from the caller's arrays (3n floats each, read in place: no copy) into `out` (3n floats); P may be
    // null (zeros). The library's and Python's shade use it.
    void eval_directions_into(const Material& material, const float* N, const float* L, const float* V,
                              const float* P, std::size_t n, float* out, Precision precision = Precision::Precise);

    // Fitting (host/fit/): samples uploaded once, then the model alone (as eval_directions) at every sample for
    // many constant sets per launch (kernels/shade.cl, eval_batch). N, L, V, P are xyz-interleaved, 3n floats.
    struct DeviceSamples {
        cl::Buffer dirs;              // 12 planes of `stride` floats: N, L, V, P by component
        std::size_t n = 0, stride = 0;
    };
    DeviceSamples upload_samples(const std::vector<float>& N, const std::vector<float>& L,
                                 const std::vector<float>& V, const std::vector<float>& P);
    // `consts` holds one set after another, each pack_material(m) of a material of `shape`'s model (and
    // children count): consts.size() = sets * (1 + children). Returns per set `planes` planes (1: red only,
    // for grey fits; 3: r, g, b) of n floats, the sets one after another. `kernel_ms`, when given, gets the
    // device time.
    std::vector<float> eval_batch(const Material& shape, const DeviceSamples& samples,
                                  const std::vector<ModelConsts>& consts, Precision precision = Precision::Precise,
                                  double* kernel_ms = nullptr, int planes = 3);

    // The -D defines a material (and light count) is built with; also the program cache key.
    static std::vector<std::string> defines_for(const Material& resolved, int num_lights,
                                                Precision precision = Precision::Precise);
    static std::string options_for(Precision precision);

    // Work-group size used for the launches (a multiple of the vector width helps PoCL's vectoriser).
    static constexpr std::size_t kLocalSize = 256;
    static constexpr std::size_t kLocalAuto = ~std::size_t(0);

private:
    Runtime& rt_;
    struct SharedKernel {
        cl::Program program;
        std::string kernel;              // shade_fragments_<eval function>, or shade_fragments_any ...
        int model = -1;                  // ... and its model argument (the slot), -1 for the per-model kernels
    };
    std::map<std::string, SharedKernel> many_;   // by the single-model program it stands for (request_key)
    cl::Kernel shade_kernel(const ProgramRequest& single);
    cl::Program one_light_program(const Material& mat, Precision precision);
    cl::Buffer batch_out_;              // eval_batch's output, kept between calls (no fresh pages per launch)
    std::size_t batch_out_bytes_ = 0;
};

}  // namespace shadelab
