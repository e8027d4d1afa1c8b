// Evaluating models over a fit domain: the float kernel for many parameter sets per launch (Shader::eval_batch,
// PoCL), the double-precision reference (host/reference/) for the target and the final polish. Every
// evaluation passes through here, so the range check and the counters are in one place.
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "cl/runtime.hpp"
#include "fit/domain.hpp"
#include "models/catalogue.hpp"
#include "shade/shader.hpp"

namespace shadelab::fit {

// What a fitted model is evaluated with besides its parameters: its colours, and for a model that blends others
// (gradient) its children.
struct ModelShape {
    std::string model;
    glm::dvec3 albedo{0.8};
    glm::dvec3 specular{1.0};
    std::vector<Material> children;   // resolved; as many as the model blends
};

// The shape's material with parameter values `x` (the model's declared order). Throws an internal error when
// a value lies outside its declared range or is not whole where it must be: the fit never evaluates there.
Material material_at(const ModelShape& shape, const std::vector<double>& x);

class Evaluator {
public:
    Evaluator(Runtime& rt, Domain domain, Precision precision = Precision::Precise);

    const Domain& domain() const { return domain_; }
    std::size_t size() const { return domain_.size(); }

    // Kernel values for each parameter set: per set `planes` planes (1: red only; 3: r, g, b) of size() floats,
    // sets one after another.
    std::vector<float> kernel(const ModelShape& shape, const std::vector<std::vector<double>>& sets, int planes = 3);
    // Whether the model accepts this combination of parameter values (each within range, but some models
    // constrain them together: toon's thresholds ascend). The kernel gives NaN values for a refused set.
    static bool accepts(const Material& m);
    // Reference values of one material: 3 planes of size() doubles. Runs on the hardware threads (at most 8);
    // the result does not depend on their number. The last few materials' values are kept: a fit asks again for
    // the optimum it has just evaluated (its values, the numeric error of --all), and gets them without a second
    // evaluation (the counter counts evaluations done).
    std::vector<double> reference(const Material& m);
    std::vector<double> reference(const ModelShape& shape, const std::vector<double>& x) {
        return reference(material_at(shape, x));
    }

    // Counters: model evaluations (samples x parameter sets) on the device and in the reference.
    std::size_t kernel_evaluations() const { return kernel_evals_; }
    std::size_t reference_evaluations() const { return reference_evals_; }
    double kernel_ms() const { return kernel_ms_; }
    // Called with the model and every parameter set about to be evaluated (tests check the ranges with it).
    std::function<void(const std::string& model, const std::vector<double>& x)> observer;

private:
    std::vector<double> evaluate_reference(const Material& m);
    Shader shader_;
    Domain domain_;
    Precision precision_;
    Shader::DeviceSamples device_;
    std::size_t kernel_evals_ = 0, reference_evals_ = 0;
    struct Kept {
        std::vector<double> key;   // the material, as numbers (material_key)
        std::string model;
        std::vector<double> values;
    };
    std::vector<Kept> kept_;       // most recent last
    double kernel_ms_ = 0.0;
};

}  // namespace shadelab::fit
