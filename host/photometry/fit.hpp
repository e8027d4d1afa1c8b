// Fitting photometric laws to the pixels of one or several images at different phases, and ranking laws.
//
// The model of a pixel k of image m (phase g_m):
//   absolute laws (hapke_hen, hapke_leg, hapke_2012: Hapke's value is I/F itself)   y_k = f(g, i, e; p)
//   shape laws (lambert, lommel_seeliger, lunar_lambert, minnaert_1941, ...)          y_k = B_m f(g, i, e; p)
// with one brightness B_m per image (ISIS's phase curve B(g), one number per phase) and the shape parameters p
// shared by all images. The fit minimises RSS = sum_k (y_k - model_k)^2 inside the catalogue's parameter box
// (host/models/planetary.cpp) by Levenberg-Marquardt (Levenberg 1944, Marquardt 1963; Press et al., Numerical
// Recipes 3rd ed. 15.5) with an active set at the bounds: a parameter on a bound whose gradient points out of
// the box is held there for that step. Jacobian: central differences of the float kernel (brightnesses
// analytically). Every launch evaluates all pixels for many parameter sets at once (kernels/photometry.cl
// eval_photometric_sets): the current point, its 2n neighbours, and four trial steps.
//
// Uncertainties (Gaussian errors of one unknown variance, estimated from the residual):
//   s^2 = RSS / (N - k),   C = s^2 (J^T J)^-1,   SE_j = sqrt(C_jj),   corr_jl = C_jl / (SE_j SE_l)
// over the k free parameters not held on a bound. J^T J is inverted through its eigen-decomposition after
// scaling to unit diagonal; an eigenvalue below 1e-6 of the largest is a direction the data do not determine,
// reported in words with the parameters that make it up (their SE is then -1, printed as "not determined").
//
// Model selection (Gaussian likelihood with the variance profiled out; Akaike 1974, Schwarz 1978):
//   AIC = N ln(RSS/N) + 2k,   BIC = N ln(RSS/N) + k ln N,
// k counting every fitted number (shape parameters and brightnesses). Laws are ranked by BIC (lowest first).
// RSS/N is floored at (1e-7 mean|y|)^2, float rounding of the kernels, so that an exact fit stays finite.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "cl/runtime.hpp"
#include "photometry/isis.hpp"

namespace shadelab::photometry {

// The pixels of a fit: geometry, value and the image each came from (0-based).
struct FitData {
    std::vector<Geometry> geometry;
    std::vector<double> value;
    std::vector<int> image;
    int images = 0;
    std::vector<std::string> image_names;   // for messages and the report
};

struct FitSpec {
    std::string model;                          // catalogue name, or ISIS's name (HapkeHen, LunarLambert, ...)
    std::map<std::string, double> start;        // starting (and, for parameters not fitted, fixed) values
    std::vector<std::string> free;              // fitted parameters; empty: default_free_parameters(model)
};

struct FitOptions {
    int max_iterations = 200;
    double rtol = 1e-12;                        // stop when RSS falls by less than this fraction in an accepted step
    Precision precision = Precision::Precise;
};

struct FitParameter {
    std::string name;                           // a model parameter, or "B1", "B2", ... (the brightness of image m)
    double value = 0.0, lo = 0.0, hi = 0.0;
    double stderr_ = 0.0;                       // -1: not determined by the data; 0: held on a bound
    bool at_bound = false;
};

struct FitResult {
    std::string model;                          // catalogue name
    std::vector<FitParameter> params;           // the fitted numbers (k = params.size())
    std::map<std::string, double> fixed;        // the model's parameters not fitted, at their values
    std::vector<double> correlation;            // k x k, row-major; 0 rows for parameters on a bound
    std::vector<std::string> notes;             // directions not determined, parameters without effect, bounds
    double rss = 0.0, rms = 0.0, aic = 0.0, bic = 0.0;
    double conditioning = 0.0;                  // smallest / largest eigenvalue of J^T J scaled to unit diagonal
    std::size_t samples = 0;
    int iterations = 0;
    bool converged = false;
    std::size_t evaluations = 0;                // pixel evaluations of the law (rows x parameter sets)
    double kernel_seconds = 0.0;                // time in the launches (upload of the sets, kernel, read-back)
    double seconds = 0.0;                       // the whole fit
    Law law() const;                            // the fitted law (brightness 1)
};

// The catalogue name for a catalogue or ISIS name; throws one line listing the laws that can be fitted.
std::string fit_model_name(const std::string& name);
// Which laws are multiplied by a per-image brightness (all but Hapke's).
bool fit_has_brightness(const std::string& model);
// Hapke: wh, b0, hh, theta and hg1 (hapke_hen, hapke_2012) or bh, ch (hapke_leg); others: all their parameters.
std::vector<std::string> default_free_parameters(const std::string& model);

// Throws one line for: no pixels, an unknown law, an unknown or duplicated free parameter, a start value outside
// the parameter's range, fewer pixels than fitted numbers.
FitResult fit_law(Runtime& rt, const FitData& data, const FitSpec& spec, const FitOptions& o = {});

// Several laws fitted to the same pixels, sorted by BIC (lowest first).
std::vector<FitResult> rank_laws(Runtime& rt, const FitData& data, const std::vector<FitSpec>& specs,
                                 const FitOptions& o = {});

// The report printed by `photometry fit`: parameters with standard errors, correlations, notes, RSS, AIC, BIC.
std::string describe_fit(const FitResult& r);
std::string describe_ranking(const std::vector<FitResult>& ranked);

}  // namespace shadelab::photometry
