// Fitting one catalogue model to another: the parameters of `model` (within their declared ranges) and a free
// grey scale that minimise the squared difference from the target's values over a domain (domain.hpp).
//
// Objective (issue 11): rel-rms = sqrt( sum (a f(x) - t)^2 / sum t^2 ) over the domain's outputs, t the
// target's double reference, f(x) the model's value with parameters x, a >= 0 the free scale, solved in closed
// form inside the objective (a = <f, t> / <f, f>, linear least squares). Reported `albedo` = a times the
// model's own grey albedo (the target's unless told otherwise): for a model linear in its albedo it is the
// albedo that matches; models with albedo-dependent terms (the Oren-Nayar interreflection) keep those at the
// given albedo.
//
// Search, in the parameters mapped to [0, 1] (linearly; logarithmically for ranges over two decades):
//  1. coarse: a grid (up to 3 parameters) or 2048 quasi-random points over the whole box, every integer value
//     of a whole-number parameter (up to 512 of them), screened on the first 1024 samples, the best 128 ranked
//     on the first 4096, float kernel on PoCL, all sets in a few launches;
//  2. bounded Levenberg-Marquardt from the best 2 distinct starts, float kernel on the first 16384 samples,
//     central-difference Jacobians evaluated as one batch of parameter sets per iteration, trial steps for three
//     damping values in one (over 4 parameters: at most 15 iterations);
//  3. polish on every sample in double with the references (forward differences), from the best of the
//     starts and their refinements by the references' error, until the error stops falling;
//  4. whole-number parameters: neighbours tried in double.
// A step never leaves the box: every evaluated set lies within the declared ranges (Evaluator checks).
//
// Diagnostics, in words: a parameter at its range limit; a parameter with no effect; a flat objective
// (moving a parameter by 5% of its range changes the error by < 0.1%) or a standard error over 10% of the range;
// two parameters (or one and the scale) that trade off (|correlation| > 0.995); a target the model cannot
// represent (rel-rms > 5%); and the limb check: the fit refitted (float kernel) over NoL, NoV >= 0.05 and
// compared; it is called limb-driven when the samples below the cut carry over 3x their share of the squared
// error and the refit moves a parameter by over 0.1% of its range. That catches Minnaert-like laws whose value
// diverges at grazing angles and lets a few samples drive the fit; the objective itself is never changed.
// Parameter combinations a model refuses (its pack throws: toon's thresholds must ascend) are never evaluated.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "fit/evaluate.hpp"

namespace shadelab::fit {

struct FitOptions {
    bool limb_check = true;
    double limb_cos = 0.05;          // the limb check's cut: NoL, NoV >= limb_cos
    int starts = 2;                  // distinct coarse minima refined (1 for more than 4 parameters)
    std::size_t coarse_samples = 4096;   // the coarse search runs on the domain's first samples
    std::size_t coarse_screen = 1024;    // over coarse_keep coarse sets: all screened on this many samples first,
    std::size_t coarse_keep = 128;       // the best coarse_keep of them ranked on coarse_samples
    std::size_t float_samples = 16384;   // and the float Levenberg-Marquardt on these (the polish on all)
    int float_iterations = 25;
    int double_iterations = 20;
    double representable = 0.05;     // rel-rms above this: the target is not representable
};

// A target on a domain: its reference values computed once, the coarse subset and the limb-check subset
// (built on first use). Shared by every model fitted to the same target (fit --all).
class Problem {
public:
    Problem(Runtime& rt, Domain domain, Material target, Precision precision = Precision::Precise);
    // A measured target (an image's pixels): `values` one per output; `name` says what it is. The fitted model
    // gets `albedo_hint`'s grey albedo before its free scale.
    Problem(Runtime& rt, Domain domain, std::vector<double> values, const std::string& name,
            Precision precision = Precision::Precise);
    const std::string& target_name() const { return target_name_; }
    Evaluator& full() { return *full_; }
    // The domain's first `samples` samples (all of them when there are fewer) and the target there: the
    // quasi-random points' prefixes are themselves evenly spread.
    struct Prefix {
        Evaluator* ev = nullptr;
        const std::vector<double>* target = nullptr;
    };
    Prefix prefix(std::size_t samples);
    // The limb-check sub-problem (NoL, NoV >= c) and the indices of its samples in the full domain.
    Problem& grazing(double c);
    const std::vector<std::size_t>& grazing_indices() const { return grazing_kept_; }
    const std::vector<double>& target() const { return target_; }         // 3 planes of full().size()
    const Material& target_material() const { return target_m_; }
    // Model evaluations so far on every evaluator of the problem (full, coarse, limb check).
    std::size_t kernel_evaluations() const;
    std::size_t reference_evaluations() const;
    double kernel_ms() const;   // device time of those kernel evaluations
    // Observer passed to every evaluator (tests).
    void set_observer(std::function<void(const std::string&, const std::vector<double>&)> f);

private:
    Runtime& rt_;
    Precision precision_;
    Material target_m_;
    std::string target_name_;
    std::unique_ptr<Evaluator> full_;
    std::vector<double> target_;
    struct Owned {
        std::unique_ptr<Evaluator> ev;
        std::vector<double> target;
    };
    std::map<std::size_t, Owned> prefixes_;
    std::unique_ptr<Problem> grazing_;
    double grazing_c_ = -1.0;
    std::vector<std::size_t> grazing_kept_;
    std::function<void(const std::string&, const std::vector<double>&)> observer_;
};

struct FittedParam {
    std::string name;
    double value = 0.0;
    double se = 0.0;          // standard error from the Jacobian at the optimum
    bool se_known = false;    // false: not determined (no effect, singular normal matrix)
    double lo = 0.0, hi = 0.0;
    bool integer = false;
    bool fixed = false;       // held at a value the user gave
};

struct Diagnostic {
    std::string kind;   // at_limit, no_effect, flat, poorly_determined, trade_off, not_representable, limb
    std::string text;
    bool ill_posed = true;   // false for facts that do not make the fit ill-posed (not representable; an exact fit at a limit)
};

struct WorstSample {
    std::size_t index = 0;
    SampleAngles angles;
    double target = 0.0, fit = 0.0;
};

struct LimbCheck {
    bool done = false;           // the shares measured and the verdict made
    bool refitted = false;       // the refit run (only when the error share is over 3x the sample share)
    double cos_min = 0.05;
    double sample_share = 0.0;   // share of the samples with NoL or NoV below cos_min
    double error_share = 0.0;    // their share of the squared residual
    std::vector<double> params;  // refitted over the rest (when refitted)
    double albedo = 0.0;
    double rel_rms = 0.0;        // of the refit, over the rest
    double max_shift = 0.0;      // largest |refit - fit| / range over the fitted parameters
    bool sensitive = false;
};

struct FitResult {
    std::string model, target;
    std::map<std::string, double> target_params;
    std::vector<FittedParam> params;
    double scale = 0.0;            // a
    double albedo = 0.0, se_albedo = 0.0;
    std::map<std::string, double> error;   // rel-rms, rms, max-abs, rel-max
    WorstSample worst;
    std::vector<Diagnostic> diagnostics;
    bool well_posed = true;
    bool representable = true;
    LimbCheck limb;
    std::string domain, domain_description;
    std::size_t samples = 0;
    std::size_t kernel_evaluations = 0, reference_evaluations = 0;
    double seconds = 0.0;
    std::string note;              // e.g. how children were chosen
    std::vector<double> values() const;   // the fitted parameter values in declared order
};

// The shape a model is fitted with against `target`: the target's albedo, `specular` (the target's when
// negative), and for a model that blends others, grey Lambert children of that albedo (note says so).
ModelShape shape_for(const std::string& model, const Material& target, double specular, std::string* note);

// Fits `shape.model` to the problem's target. `fixed` holds model parameters at given values (not fitted).
// Throws shadelab::Error for unknown or out-of-range fixed parameters; otherwise always returns its best fit
// (no NaN, no exception for a poor or ill-posed one: the diagnostics say so).
FitResult fit_model(Problem& problem, const ModelShape& shape, const std::map<std::string, double>& fixed = {},
                    const FitOptions& options = {});

// rel-rms of the values `f` (3 planes) against the target `t` with the best scale: what the objective computes,
// exposed for tests and the table. Only the first `channels` planes are used.
double best_scale_rel_rms(const std::vector<double>& f, const std::vector<double>& t, std::size_t n, double* scale = nullptr);

}  // namespace shadelab::fit
