// The model catalogue: every lighting model shadelab knows, with its parameters (ranges, defaults), flags,
// precision bounds, documentation page, its kernel (file + eval function) and the host code that turns
// parameters into the kernel's constants. Each family registers all of that in one place, its
// host/models/<family>.cpp (register_<family>_family, found by the build: cmake/model_families.cmake), and
// everything else derives from it: this catalogue, the references' dispatch (host/reference/<family>_ref.cpp,
// add_<family>_references), the precision test's rows, the docs index test and `shadelab models`.
// docs/adding-a-model.md walks through adding one. The double-precision references share no code with this.
#pragma once
#include <array>
#include <cstring>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

#include "consts/model_consts.h"   // ModelConsts, shared with the kernels (kernels/consts/)
#include "models/material.hpp"

namespace shadelab {

constexpr int kModelConstCount = SL_MAX_CONSTS;   // floats in ModelConsts.block

// Parameter-only constants, computed once per material: params in the model's `params` order, resolved; writes
// the model's struct (kernels/consts/<family>.h) into ModelConsts.block.
using PackFn = std::function<void(const std::vector<double>& params, float* block)>;

// A PackFn from a function that returns the model's constant struct T (e.g. OrenNayarConsts), so that a family
// fills named fields and never an offset.
template <class T, class F>
PackFn packer(F make) {
    static_assert(std::is_trivially_copyable_v<T>, "a model's constants are plain floats");
    static_assert(sizeof(T) <= sizeof(ModelConsts::block), "a model's constants must fit ModelConsts.block");
    return [make](const std::vector<double>& params, float* block) {
        const T k = make(params);
        std::memcpy(block, &k, sizeof k);
    };
}

// The model's struct T as packed into `k` (what a kernel reads through SL_CONSTS).
template <class T>
T consts_of(const ModelConsts& k) {
    static_assert(std::is_trivially_copyable_v<T> && sizeof(T) <= sizeof(ModelConsts::block));
    T out;
    std::memcpy(&out, k.block, sizeof out);
    return out;
}

struct ParamSpec {
    std::string name;
    double def = 0.0;
    double lo = 0.0;
    double hi = 1.0;
    std::string doc;
    bool integer = false;   // must be a whole number (band counts)
};

// A table-valued parameter (the empirical family's tables over phase). Every table of a model has the same length,
// from 2 to max_length entries, each finite and in [lo, hi]; the model's `knots` table is strictly increasing.
// `isis` is ISIS's keyword for it, accepted as a name too (resolve_material renames it).
struct TableSpec {
    std::string name;        // "phase_list"
    std::string isis;        // "PhaseList"
    std::vector<double> def;
    double lo = 0.0, hi = 1.0;
    std::string doc;
    bool knots = false;      // the abscissae (phases) of the other tables
    std::size_t max_length = 2;
    // For a table over the knots: its natural cubic spline (host/core/spline.hpp), continued beyond the table,
    // must stay in [curve_lo, curve_hi] over every phase 0..180 (so that no geometry gives a runaway value).
    double curve_lo = 0.0, curve_hi = 0.0;
};

// A table model's buffer (kernels/shade.cl's `tab` argument) from its resolved material.
using TablePackFn = std::function<std::vector<float>(const Material& resolved)>;

// One asserted bound of a model's kernel against its reference: tests/test_precision.cpp measures every model in
// both precision modes and asserts these (docs/precision.md lists them). Relative error |k - r| / |r| over the
// well-conditioned values, max over the probes (defaults and range ends). probe "*" is the model's own row (every
// model needs one); a probe "param=value" overrides it for that parameter set only, where the input rounding alone
// is amplified past the row. measured_*: what the test saw when the bound was set (50,000 triples, seed 4242).
struct PrecisionBound {
    std::string probe;
    double measured_precise, precise;   // precise mode: measured max rel, asserted bound
    double measured_fast, fast;         // fast mode: measured max rel, asserted bound
};

struct ModelInfo {
    std::string name;      // unique, what users type: "minnaert_1941"
    std::string family;    // "minnaert" (set from the family it is registered in)
    std::string summary;   // one line for --help and docs
    std::string source;    // the paper or seed it comes from
    std::string header;    // kernel file, relative to kernels/: "models/minnaert.cl"
    std::string eval;      // kernel function: float3 f(float3 N, float3 L, float3 V, float3 P, consts*)
    std::vector<ParamSpec> params;
    std::vector<TableSpec> tables;   // table-valued parameters (most models: none)
    TablePackFn pack_table;          // set iff `tables` is not empty; the eval then takes `tab` (kernels/shade.cl)
    int children = 0;      // number of child materials it blends (gradient: 2)
    PackFn pack;           // its constants (none: the model reads only albedo and specular)
    bool reciprocal = false;         // f_r(L, V) == f_r(V, L) (value / NoL symmetric) at EVERY parameter value in range
    bool energy_conserving = false;  // directional albedo <= 1 for albedo 1, at every parameter value in range
    // Its value depends on N and L alone (its eval reads neither V nor P): the kernel needs 24 bytes a fragment,
    // its arithmetic is a few operations, and it runs at memory speed. Such models are shaded at no more than
    // kNormalsOnlyLanes fragments a work-item (host/shade/shader.hpp, lanes_for); bench_models counts their bytes.
    bool normals_only = false;
    // Independent chains of lanes a shading work-item runs through the model (kernels/common.cl, SL_CHAINS): 2 for
    // the models whose arithmetic is a long latency-bound chain, where a second chain fills the first's waits; 1
    // for the others, which a second chain slowed (the models near memory speed). Chosen by measuring each model
    // at both (docs/speed.md, "Two chains"); Shader::chains_for picks one by the device's lanes. `chains` on
    // devices of 16 lanes (AVX-512 hosts; measured on Intel ones), `chains_avx2` on devices of 8 lanes or fewer
    // (AVX2 hosts; measured on an AMD Zen 3, where a second chain gained for far more models: "Chains on AVX2").
    int chains = 1;
    int chains_avx2 = 1;
    // Lanes a shading work-item runs on devices of 8 lanes (AVX2 hosts): 0 for the device's 8, 16 (two 256-bit
    // registers a step, kernels/common.cl's SL_MODEL_LANES) for the models measured faster so there (docs/speed.md,
    // "Sixteen lanes on AVX2"; Shader::lanes_for). `chains_avx2` then counts chains of 16 lanes. Set by its
    // family's registration (use_sixteen_lanes_on_avx2).
    int lanes_avx2 = 0;
    // Its shaded planes are written with plain stores at every size: streaming (non-temporal) stores, which the
    // launches past the cache use (Shader::streams_output), measured slower for it (docs/speed.md, "Streaming
    // stores"). Set by its family's registration (use_plain_stores).
    bool plain_stores = false;
    // Fast mode computes something else for it, faster: its kernel calls pow, which fast mode maps to
    // sl_fast_pow (kernels/common.cl; docs/precision.md, "Fast-mode pow"). For every other model fast mode is the
    // same program as precise: nothing faster exists here (the trigonometry is common.cl's own in both modes,
    // and PoCL's native_ forms of exp, log, sqrt and rsqrt are its full functions). `shadelab models NAME` says
    // which; set by its family's registration (use_fast_pow), and tests/test_precision.cpp holds it to that:
    // fast output bit-identical to precise over the whole sweep exactly where it is not set.
    bool fast_differs = false;
    std::vector<PrecisionBound> precision;   // kernel vs reference, both modes (see PrecisionBound)
    std::string doc;       // its documentation page from the repository root (set from its family's)
};

// A family as it registers itself: register_<name>_family() in host/models/<name>.cpp returns one.
struct ModelFamily {
    std::string name;    // "oren_nayar": host/models/<name>.cpp, host/reference/<name>_ref.cpp (add_<name>_references)
    int rank = 0;        // its place in the catalogue (listing and contact-sheet order), unique
    std::string title;   // its row's name in docs/models/README.md ("Oren-Nayar")
    std::string doc;     // its documentation page from the repository root ("docs/models/oren_nayar.md")
    std::vector<ModelInfo> models;
};

// Every registered family, by rank.
const std::vector<ModelFamily>& model_families();

// Sets ModelInfo::chains and chains_avx2 = 2 for the named models of `family` (its registration's last step):
// two chains on every device; throws shadelab::Error for a name that is not one of its models.
void use_two_chains(ModelFamily& family, const std::vector<std::string>& names);
// Sets ModelInfo::chains_avx2 = 2 only: two chains on devices of 8 lanes or fewer (AVX2 hosts), one on AVX-512.
void use_two_chains_on_avx2(ModelFamily& family, const std::vector<std::string>& names);
// Sets ModelInfo::lanes_avx2 = 16 and chains_avx2 = `chains` (1 or 2, measured at those lanes; after
// use_two_chains, which it overrides on AVX2): sixteen lanes a work-item on devices of 8 lanes. Throws
// shadelab::Error for a name that is not one of its models or for a model of N and L only (those keep 8 lanes:
// Shader::lanes_for).
void use_sixteen_lanes_on_avx2(ModelFamily& family, const std::vector<std::string>& names, int chains);

// Sets ModelInfo::plain_stores for the named models of `family` (its registration's last step); throws
// shadelab::Error for a name that is not one of its models.
void use_plain_stores(ModelFamily& family, const std::vector<std::string>& names);

// Sets ModelInfo::fast_differs for the named models of `family` (the models whose kernel calls pow); throws
// shadelab::Error for a name that is not one of its models.
void use_fast_pow(ModelFamily& family, const std::vector<std::string>& names);

// Every model, family by family (by rank), each family's in its registered order.
const std::vector<ModelInfo>& model_catalogue();

// Throws shadelab::Error listing the known names when `name` is unknown.
const ModelInfo& find_model(const std::string& name);

// Fills defaults, rejects unknown parameter names and out-of-range or non-finite values with one clear
// line naming the model, the parameter and its allowed range; checks child count; recurses into children.
// `where` prefixes messages (e.g. "scene 'a.json', material 'm'").
Material resolve_material(const Material& m, const std::string& where = "");

// Gives a model that blends others (info.children > 0) its children for a demonstration: Lambert surfaces of
// contrasting colour (orange, blue), so the blend shows. What the contact sheet and the chart draw.
void add_demo_children(Material& m, const ModelInfo& info);

// Parameters of a resolved material in the model's declared order.
std::vector<double> ordered_params(const ModelInfo& info, const Material& m);

// Packs albedo, specular and the model's constants. Gradient-like models get children after themselves.
std::vector<ModelConsts> pack_material(const Material& resolved);

// The material's table buffer (kernels/shade.cl's `tab`): its model's pack_table, or one 0 for a model without
// tables (an OpenCL buffer cannot be empty; it is never read).
std::vector<float> pack_table(const Material& resolved);

// True when the model reads a table (its eval takes `tab`).
inline bool has_tables(const ModelInfo& info) { return !info.tables.empty(); }


}  // namespace shadelab
