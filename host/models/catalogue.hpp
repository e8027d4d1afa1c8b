// The model catalogue: every lighting model shadelab knows, with its parameters (ranges, defaults),
// its kernel (file + eval function) and the host code that turns parameters into the kernel's constants.
// The double-precision references live apart, in host/reference/, and share no code with this.
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

struct ModelInfo {
    std::string name;      // unique, what users type: "minnaert_1941"
    std::string family;    // "minnaert"
    std::string summary;   // one line for --help and docs
    std::string source;    // the paper or seed it comes from
    std::string header;    // kernel file, relative to kernels/: "models/minnaert.cl"
    std::string eval;      // kernel function: float3 f(float3 N, float3 L, float3 V, float3 P, consts*)
    std::vector<ParamSpec> params;
    int children = 0;      // number of child materials it blends (gradient: 2)
    PackFn pack;           // its constants (none: the model reads only albedo and specular)
    bool reciprocal = false;         // f_r(L, V) == f_r(V, L) (value / NoL symmetric) at EVERY parameter value in range
    bool energy_conserving = false;  // directional albedo <= 1 for albedo 1, at every parameter value in range
};

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

// Families add themselves here (one file each under host/models/).
void register_lambert_family(std::vector<ModelInfo>& out);
void register_wrap_family(std::vector<ModelInfo>& out);
void register_phong_family(std::vector<ModelInfo>& out);
void register_banded_toon_family(std::vector<ModelInfo>& out);
void register_minnaert_family(std::vector<ModelInfo>& out);
void register_oren_nayar_family(std::vector<ModelInfo>& out);
void register_cook_torrance_family(std::vector<ModelInfo>& out);
void register_gradient_family(std::vector<ModelInfo>& out);
void register_planetary_family(std::vector<ModelInfo>& out);

}  // namespace shadelab
