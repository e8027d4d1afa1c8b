// Disc photometry from an image: per-pixel geometry, profiles, Minnaert fits, comparison with a model.
//
// Every pixel whose centre lies strictly inside the disc is a sample; its geometry is that of the unit sphere
// under the pixel centre (photometry.hpp conventions). Its intensity is the image value: the single channel,
// or the mean of the first three (colour) channels; pixels with alpha 0 (the renderer's background and limb
// mask, FITS blanks) are skipped.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "image/image.hpp"
#include "moon/disc.hpp"
#include "moon/photometry.hpp"
#include "photometry/fit.hpp"

namespace shadelab::moon {

struct DiscPixel {
    int x = 0, y = 0;          // pixel column and row (row 0 top)
    double X = 0.0, Y = 0.0;   // centre in disc radii (x right, y up)
    PhotometricAngles a;       // mu0, mu, i, e, g, lambda, beta at the pixel centre
    double I = 0.0;            // image value
};

// The intensity of pixel (x, y) as described above; `ok` false where alpha is 0.
double pixel_intensity(const Image& img, int x, int y, bool& ok);

// Every usable pixel of the disc. Validates the disc against the image (check_disc), and throws when no
// pixel of the disc is on the image.
std::vector<DiscPixel> disc_pixels(const Image& img, const Disc& d, const SunGeometry& sun, bool allow_partial = false);

// --- Profiles: the pixels nearest to a line across the disc, one per 1-pixel step along it, each with its
// own exact geometry (no interpolation of intensities), sorted by position along the line.
struct ProfilePixel {
    DiscPixel p;
    double s = 0.0;        // position of the pixel centre along the line, disc radii (+ towards the sun / along w)
    double offset = 0.0;   // distance of the pixel centre from the line, disc radii (<= 0.5 px / R by construction)
};
// Along the intensity equator (through the centre, direction u).
std::vector<ProfilePixel> equator_profile(const Image& img, const Disc& d, const SunGeometry& sun, bool allow_partial = false);
// Across: perpendicular to the equator, crossing it `offset` disc radii from the centre (towards the sun > 0).
std::vector<ProfilePixel> across_profile(const Image& img, const Disc& d, const SunGeometry& sun, double offset,
                                         bool allow_partial = false);

// --- Minnaert fit: I = B0 mu0^k mu^(k-1), i.e. on the Minnaert plot ln(mu I) = ln(B0) + k ln(mu mu0).
enum class FitMethod {
    // Ordinary least squares of ln(mu I) on ln(mu mu0), every pixel weighted alike: the classical Minnaert plot.
    // With noise it is biased: E[ln(I + e)] = ln I - sigma^2 / (2 I^2), largest on the dim pixels, and pixels
    // with I <= 0 have no logarithm and are dropped (also a bias). Fine at high S/N (see docs/moon.md).
    MinnaertPlot,
    // The same line with weights I_model^2 (var ln I = sigma^2 / I^2 for additive noise), I_model from the
    // previous pass (observed I in the weights would bias B0 upwards), iterated.
    Weighted,
    // Non-linear least squares on I itself (Gauss-Newton from the Minnaert-plot estimate), uniform weights:
    // unbiased for additive noise, keeps pixels with I <= 0; standard errors from the Jacobian.
    Intensity,
};
FitMethod parse_fit_method(const std::string& s);   // "minnaert-plot", "weighted", "intensity"
std::string to_string(FitMethod m);

struct FitOptions {
    double mu_min = 0.2;          // keep the limb out: mu >= mu_min
    double mu0_min = 0.2;         // keep the terminator out: mu0 >= mu0_min
    std::size_t min_pixels = 50;  // fewer pixels -> the fit is refused
    double min_spread = 0.05;     // standard deviation of ln(mu mu0) below this -> k is not determined, refused
    FitMethod method = FitMethod::MinnaertPlot;
    // When set, B0 is held at exp(fixed_ln_B0) and only k is fitted (a line through a fixed intercept): what
    // the k map and the longitude bins use by default, with B0 from the whole-disc fit, because a small cell
    // spans too narrow a range of mu mu0 to separate k from B0. The spread test then uses the rms of
    // ln(mu mu0) about 0 instead of its standard deviation.
    std::optional<double> fixed_ln_B0;
};
void check_fit_options(const FitOptions& o);   // throws on thresholds outside [0, 1), min_pixels < 3, ...

struct MinnaertFit {
    double k = 0.0, se_k = 0.0;
    double B0 = 0.0, se_B0 = 0.0;       // B0 = exp(ln B0); se by the delta method, B0 * se(ln B0)
    double ln_B0 = 0.0, se_ln_B0 = 0.0;
    double rms = 0.0;                   // rms residual of ln(mu I) (pixels with I > 0)
    double rms_rel = 0.0;               // rms of I / (B0 mu0^k mu^(k-1)) - 1 over the pixels used
    int iterations = 0;                 // Weighted / Intensity: passes until converged
    // Noise of I estimated from the residual differences of horizontally adjacent pixels (a smooth misfit of
    // the law cancels there; independent noise does not); 0 when too few adjacent pairs were used.
    double noise_sigma = 0.0;
    // Minnaert-plot methods: the expected shift of k and ln B0 caused by taking logarithms of values with that
    // noise (second order): k_fit ~ k + bias_k. 0 for Intensity.
    double bias_k = 0.0, bias_ln_B0 = 0.0;
    std::size_t used = 0;               // pixels in the fit
    std::size_t candidates = 0;         // disc pixels considered
    std::size_t below_thresholds = 0;   // rejected by mu_min / mu0_min
    std::size_t non_positive = 0;       // inside the thresholds but I <= 0: no logarithm (skipped by the
                                        // Minnaert-plot methods, used by the Intensity method)
    double x_min = 0.0, x_max = 0.0;    // range of ln(mu mu0) used
    std::vector<std::string> warnings;  // things the user should know (printed by the CLI)
};

// Fits the pixels. Throws shadelab::Error (one line, saying why and what to change) when the fit would be
// meaningless: too few pixels inside the thresholds, a too narrow range of mu mu0, or a sun geometry where no
// pixel can pass (phase >= 2 acos(max(mu_min, mu0_min)), e.g. 157 deg for 0.2).
MinnaertFit fit_minnaert(const std::vector<DiscPixel>& pixels, const SunGeometry& sun, const FitOptions& o);

// The points of the Minnaert plot a fit used: x = ln(mu mu0), y = ln(mu I).
struct PlotPoint { double x, y; };
std::vector<PlotPoint> minnaert_plot_points(const std::vector<DiscPixel>& pixels, const FitOptions& o);

// k in bins of photometric longitude (equal widths over the longitudes of the pixels that pass), or in the
// cells of an n x n grid over the disc's bounding square (a k map). Bins that cannot be fitted are returned
// with ok = false and the reason.
struct BinFit {
    int i = 0, j = 0;              // bin index (grid: column i, row j from the top)
    double lo = 0.0, hi = 0.0;     // longitude bins: lambda range in degrees
    double X = 0.0, Y = 0.0;       // grid: cell centre in disc radii
    bool ok = false;
    std::string why;
    MinnaertFit fit;
};
std::vector<BinFit> fit_longitude_bins(const std::vector<DiscPixel>& pixels, const SunGeometry& sun,
                                       const FitOptions& o, int bins);
std::vector<BinFit> fit_grid(const std::vector<DiscPixel>& pixels, const SunGeometry& sun, const FitOptions& o,
                             int cells);

// --- Hapke fit of one disc image: photometry::fit_law (host/photometry/fit.hpp: bounded Levenberg-Marquardt on I,
// standard errors and correlations) on the disc pixels inside the thresholds mu >= mu_min, mu0 >= mu0_min.
// What one image determines: every pixel has the same phase g, so the opposition surge B(g) (b0, hh) and the phase
// function P(g) (hg1, hg2; bh, ch) enter only through the one number (1 + B(g)) P(g), the single-scattering factor
// beside the multiple-scattering term H(mu0e) H(mue) - 1. With w and theta-bar, ONE of them can be fitted (by
// default hg1, or bh for hapke_leg); the others are held at their given values (fit_law's starts otherwise) and
// named in `held`. Fitting two of them at once leaves a direction the data do not determine, which the fit
// reports (SE "not determined"). w and theta-bar are determined by the disc's shape (limb and terminator).
struct HapkeDiscFit {
    photometry::FitResult fit;
    std::vector<std::string> held;      // the parameters one image cannot separate, held fixed
    std::size_t candidates = 0;         // disc pixels considered
    std::size_t used = 0;               // inside the thresholds (and finite)
};
// The parameters fitted by default: wh, theta and hg1 (hapke_hen, hapke_2012) or bh (hapke_leg).
std::vector<std::string> hapke_disc_free_parameters(const std::string& model);
// Throws one line for: a law that is not a Hapke law, too few pixels (o.min_pixels) inside the thresholds, and
// what fit_law refuses (unknown parameters, values out of range).
HapkeDiscFit fit_hapke_disc(Runtime& rt, const std::vector<DiscPixel>& pixels, const SunGeometry& sun,
                            const FitOptions& o, const photometry::FitSpec& spec);
// The report: fit_law's (parameters, standard errors, correlations, notes) and what was held and why.
std::string describe_hapke_disc_fit(const HapkeDiscFit& f, const SunGeometry& sun);

// --- Comparison of image pixels with a model at their exact geometry, over mu >= mu_min, mu0 >= mu0_min.
struct Comparison {
    std::size_t n = 0;
    double max_abs = 0.0, max_rel = 0.0, rms_rel = 0.0;
    double worst_X = 0.0, worst_Y = 0.0;   // where max_rel happened (disc radii)
};
Comparison compare_pixels(const std::vector<DiscPixel>& pixels, const PhotometricModel& m, const SunGeometry& sun,
                          double mu_min, double mu0_min);

}  // namespace shadelab::moon
