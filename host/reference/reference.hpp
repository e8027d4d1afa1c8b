// Double-precision scalar references, written from the papers' formulas. They share no code with the
// kernels (or with host/models/, which packs the kernels' constants): a reference computes its own derived
// constants from the user's parameters, so a slip in one side shows up as a difference.
//
// Same convention as the kernels: value = outgoing radiance per unit light radiance, incident cosine
// included, scaled so that a white Lambert surface lit head-on gives 1 (pi * f_r * NoL for BRDFs).
#pragma once
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/fragment_buffer.hpp"
#include "models/material.hpp"
#include "reference/planetary_ref.hpp"

namespace shadelab::ref {

using dvec3 = glm::dvec3;

// N, L, V unit; P world position (used by the gradient model only); m a resolved material.
using ModelFn = std::function<dvec3(const dvec3& N, const dvec3& L, const dvec3& V, const dvec3& P,
                                    const Material& m)>;

// Throws shadelab::Error if the model has no reference.
const ModelFn& reference_for(const std::string& model);
std::vector<std::string> models_with_reference();

// Evaluates the material (its own model, which may call its children's references).
dvec3 eval_material(const dvec3& N, const dvec3& L, const dvec3& V, const dvec3& P, const Material& m);

// Light `li` at P: sets L to the unit direction to it and returns its attenuation (1 for directional lights;
// inverse square, windowed to 0 at the range, for point lights: the kernels' light_incident_v3).
double light_incident(const Light& li, const dvec3& P, dvec3& L);

// The multi-light sum of the Shader Story equation for one point:
//   sum_i  colour_i * intensity_i * atten_i(P) * model(N, L_i, V)  +  ambient * albedo
dvec3 shade_point(const dvec3& P, const dvec3& N, const dvec3& V, const Material& m,
                  const std::vector<Light>& lights, const dvec3& ambient);

// shade_point over a whole fragment buffer, viewer at `eye`, on the fragments' float positions and normals:
// three planes of n floats (all red, then green, then blue), the layout Shader::shade returns. Runs on all
// hardware threads (at most 8); the result does not depend on the thread count.
std::vector<float> shade_fragments(const FragmentBuffer& fb, const Material& m, const std::vector<Light>& lights,
                                   const dvec3& ambient, const dvec3& eye);

// A law's value for albedo 1 at photometric angles (laws written in them, such as ISIS's: planetary_ref.hpp).
using AngleFn = std::function<double(const Material& m, const PhotometricAngles& a)>;

// What a family's reference file fills, one per family: add_<family>_references(Table&) in
// host/reference/<family>_ref.cpp, called for every registered family (the list the build writes from
// host/models/, cmake/model_families.cmake). t["name"] = ... adds a model's reference at vectors; laws that
// also have a form in photometric angles add it to `angles` (what planetary_value dispatches on).
struct Table {
    std::map<std::string, ModelFn> vectors;
    std::map<std::string, AngleFn> angles;
    ModelFn& operator[](const std::string& model) { return vectors[model]; }
};

// The photometric-angle form of `model`, or nullptr when it has none.
const AngleFn* angle_reference_for(const std::string& model);

}  // namespace shadelab::ref
