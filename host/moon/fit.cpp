#include "moon/fit.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.hpp"
#include "core/format.hpp"

namespace shadelab::moon {

namespace {
DiscPixel make_pixel(const Image& img, const Disc& d, const SunGeometry& sun, int x, int y, bool& ok) {
    DiscPixel p;
    p.x = x;
    p.y = y;
    glm::dvec3 N;
    ok = sphere_point(d, x + 0.5, y + 0.5, N);
    if (!ok) return p;
    p.X = N.x;
    p.Y = N.y;
    p.a = photometric_angles(N, sun);
    p.I = pixel_intensity(img, x, y, ok);
    return p;
}

// A line through the disc in image pixel coordinates (y down): point c + t dir.
std::vector<ProfilePixel> line_profile(const Image& img, const Disc& d, const SunGeometry& sun, glm::dvec2 dir,
                                       glm::dvec2 through, double half_length) {
    std::vector<ProfilePixel> out;
    const glm::dvec2 normal{-dir.y, dir.x};
    int last_x = -1, last_y = -1;
    const int steps = int(std::ceil(2.0 * half_length * d.radius));
    for (int k = 0; k <= steps; ++k) {
        const double t = -half_length * d.radius + k * (2.0 * half_length * d.radius) / std::max(1, steps);
        const glm::dvec2 q = through + t * dir;
        const int x = int(std::floor(q.x)), y = int(std::floor(q.y));
        if (x == last_x && y == last_y) continue;
        last_x = x;
        last_y = y;
        if (x < 0 || y < 0 || x >= img.width || y >= img.height) continue;
        bool ok = false;
        ProfilePixel pp;
        pp.p = make_pixel(img, d, sun, x, y, ok);
        if (!ok) continue;
        const glm::dvec2 rel = glm::dvec2(x + 0.5, y + 0.5) - through;
        pp.s = glm::dot(rel, dir) / d.radius;
        pp.offset = glm::dot(rel, normal) / d.radius;
        out.push_back(pp);
    }
    std::sort(out.begin(), out.end(), [](const ProfilePixel& a, const ProfilePixel& b) { return a.s < b.s; });
    return out;
}

// Image-plane (y down) directions of the world vectors u and w.
glm::dvec2 image_dir(const glm::dvec3& v) { return {v.x, -v.y}; }

// One pixel on the Minnaert plot: x = ln(mu mu0), and what the fits need.
struct Obs {
    double x = 0.0;    // ln(mu mu0)
    double mu = 0.0;
    double I = 0.0;
    int px = 0, py = 0;   // the pixel, to find its neighbour
};

double model_I(double a, double k, const Obs& o) { return std::exp(a + k * o.x) / o.mu; }   // B0 mu0^k mu^(k-1)

// The noise of I from the residuals of horizontally adjacent pixel triples: the second difference
// r(x-1) - 2 r(x) + r(x+1) cancels a smooth misfit of the law (to second order), while for independent noise its
// variance is 6 sigma^2. Needs the pixels in row order (as disc_pixels gives them); 0 with fewer than 20 triples.
double neighbour_noise(const std::vector<Obs>& obs, double a, double k) {
    double s = 0.0;
    std::size_t triples = 0;
    for (std::size_t i = 1; i + 1 < obs.size(); ++i) {
        const Obs& p = obs[i - 1];
        const Obs& q = obs[i];
        const Obs& t = obs[i + 1];
        if (p.py != q.py || t.py != q.py || p.px + 1 != q.px || q.px + 1 != t.px) continue;
        const double d = (p.I - model_I(a, k, p)) - 2.0 * (q.I - model_I(a, k, q)) + (t.I - model_I(a, k, t));
        s += d * d;
        ++triples;
    }
    return triples >= 20 ? std::sqrt(s / (6.0 * double(triples))) : 0.0;
}

// Weighted least squares of y = ln(mu I) on x, y = a + k x (or y = a_fixed + k x). Standard errors
// s^2 (X^T W X)^-1 with s^2 = sum w r^2 / (n - p): right when the weights are right up to a common factor.
void line_fit(const std::vector<Obs>& obs, const std::vector<double>& w, const std::optional<double>& fixed_a,
              MinnaertFit& f) {
    const std::size_t n = obs.size();
    double sw = 0.0, mx = 0.0, my = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        sw += w[i];
        mx += w[i] * obs[i].x;
        my += w[i] * std::log(obs[i].mu * obs[i].I);
    }
    mx /= sw;
    my /= sw;
    if (fixed_a) {   // through a fixed intercept: k = sum w x (y - a) / sum w x^2
        double sxx = 0.0, sxy = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            sxx += w[i] * obs[i].x * obs[i].x;
            sxy += w[i] * obs[i].x * (std::log(obs[i].mu * obs[i].I) - *fixed_a);
        }
        f.k = sxy / sxx;
        f.ln_B0 = *fixed_a;
        double swr2 = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            const double r = std::log(obs[i].mu * obs[i].I) - (f.ln_B0 + f.k * obs[i].x);
            swr2 += w[i] * r * r;
        }
        f.se_k = std::sqrt(swr2 / double(n - 1) / sxx);
        f.se_ln_B0 = 0.0;
        return;
    }
    double sxx = 0.0, sxy = 0.0;   // about the weighted means: numerically stable
    for (std::size_t i = 0; i < n; ++i) {
        const double dx = obs[i].x - mx;
        sxx += w[i] * dx * dx;
        sxy += w[i] * dx * (std::log(obs[i].mu * obs[i].I) - my);
    }
    f.k = sxy / sxx;
    f.ln_B0 = my - f.k * mx;
    double swr2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double r = std::log(obs[i].mu * obs[i].I) - (f.ln_B0 + f.k * obs[i].x);
        swr2 += w[i] * r * r;
    }
    const double s2 = swr2 / double(n - 2);
    f.se_k = std::sqrt(s2 / sxx);
    f.se_ln_B0 = std::sqrt(s2 * (1.0 / sw + mx * mx / sxx));
}

// Gauss-Newton on sum (I - B0 mu0^k mu^(k-1))^2 in (a = ln B0, k), from the current f. Jacobian of the model
// m = exp(a + k x) / mu: dm/da = m, dm/dk = m x. Covariance s^2 (J^T J)^-1, s^2 = sum r^2 / (n - p).
void intensity_fit(const std::vector<Obs>& obs, const std::optional<double>& fixed_a, MinnaertFit& f) {
    const std::size_t n = obs.size();
    double a = f.ln_B0, k = f.k;
    double jaa = 0.0, jak = 0.0, jkk = 0.0;
    for (int it = 1; it <= 100; ++it) {
        double ga = 0.0, gk = 0.0;
        jaa = jak = jkk = 0.0;
        for (const Obs& o : obs) {
            const double m = model_I(a, k, o), r = o.I - m;
            ga += m * r;
            gk += m * o.x * r;
            jaa += m * m;
            jak += m * m * o.x;
            jkk += m * m * o.x * o.x;
        }
        double da = 0.0, dk = 0.0;
        if (fixed_a) {
            dk = gk / jkk;
        } else {
            const double det = jaa * jkk - jak * jak;
            da = (jkk * ga - jak * gk) / det;
            dk = (jaa * gk - jak * ga) / det;
        }
        a += da;
        k += dk;
        f.iterations = it;
        if (!std::isfinite(a) || !std::isfinite(k)) break;
        if (std::abs(da) < 1e-13 && std::abs(dk) < 1e-13) break;
    }
    double sr2 = 0.0;
    for (const Obs& o : obs) {
        const double r = o.I - model_I(a, k, o);
        sr2 += r * r;
    }
    f.ln_B0 = a;
    f.k = k;
    if (fixed_a) {
        f.se_k = std::sqrt(sr2 / double(n - 1) / jkk);
        f.se_ln_B0 = 0.0;
    } else {
        const double s2 = sr2 / double(n - 2), det = jaa * jkk - jak * jak;
        f.se_k = std::sqrt(s2 * jaa / det);
        f.se_ln_B0 = std::sqrt(s2 * jkk / det);
    }
}

// The largest min(mu, mu0) any point of the sphere reaches at this phase: cos(alpha / 2), on the equator
// halfway between the sub-observer and the sub-solar points.
double best_min_cos(const SunGeometry& sun) { return std::cos(0.5 * sun.phase_deg * kDeg); }
}  // namespace

double pixel_intensity(const Image& img, int x, int y, bool& ok) {
    ok = true;
    switch (img.channels) {
        case 1: return img.at(x, y, 0);
        case 2: ok = img.at(x, y, 1) > 0.0f; return img.at(x, y, 0);
        default: {
            if (img.channels >= 4) ok = img.at(x, y, 3) > 0.0f;
            return (double(img.at(x, y, 0)) + img.at(x, y, 1) + img.at(x, y, 2)) / 3.0;
        }
    }
}

std::vector<DiscPixel> disc_pixels(const Image& img, const Disc& d, const SunGeometry& sun, bool allow_partial) {
    const double on_image = check_disc(d, img.width, img.height, allow_partial);
    if (on_image <= 0.0) throw Error("no pixel of the disc falls on the image");
    std::vector<DiscPixel> out;
    const int j0 = std::max(0, int(std::floor(d.cy - d.radius))), j1 = std::min(img.height - 1, int(std::ceil(d.cy + d.radius)));
    const int i0 = std::max(0, int(std::floor(d.cx - d.radius))), i1 = std::min(img.width - 1, int(std::ceil(d.cx + d.radius)));
    for (int y = j0; y <= j1; ++y)
        for (int x = i0; x <= i1; ++x) {
            bool ok = false;
            const DiscPixel p = make_pixel(img, d, sun, x, y, ok);
            if (ok && std::isfinite(p.I)) out.push_back(p);
        }
    if (out.empty()) throw Error("no usable pixel on the disc (all masked by alpha 0 or not finite)");
    return out;
}

std::vector<ProfilePixel> equator_profile(const Image& img, const Disc& d, const SunGeometry& sun, bool allow_partial) {
    check_disc(d, img.width, img.height, allow_partial);
    return line_profile(img, d, sun, image_dir(sun.u), {d.cx, d.cy}, 1.0);
}

std::vector<ProfilePixel> across_profile(const Image& img, const Disc& d, const SunGeometry& sun, double offset,
                                         bool allow_partial) {
    check_disc(d, img.width, img.height, allow_partial);
    if (!std::isfinite(offset) || std::abs(offset) >= 1.0)
        throw Error("across-profile offset " + num(offset) + " must be strictly between -1 and 1 disc radii");
    const glm::dvec2 c = glm::dvec2(d.cx, d.cy) + offset * d.radius * image_dir(sun.u);
    auto prof = line_profile(img, d, sun, image_dir(sun.w), c, std::sqrt(1.0 - offset * offset));
    return prof;
}

FitMethod parse_fit_method(const std::string& s) {
    if (s == "minnaert-plot" || s == "minnaert_plot" || s == "plot") return FitMethod::MinnaertPlot;
    if (s == "weighted") return FitMethod::Weighted;
    if (s == "intensity") return FitMethod::Intensity;
    throw Error("--method must be minnaert-plot, weighted or intensity, got '" + s + "'");
}

std::string to_string(FitMethod m) {
    switch (m) {
        case FitMethod::Weighted: return "weighted Minnaert plot (w = I_model^2)";
        case FitMethod::Intensity: return "least squares on I (Gauss-Newton)";
        default: return "Minnaert plot (ordinary least squares)";
    }
}

void check_fit_options(const FitOptions& o) {
    if (!std::isfinite(o.mu_min) || o.mu_min < 0.0 || o.mu_min >= 1.0)
        throw Error("--mu-min " + num(o.mu_min) + " must be in [0, 1)");
    if (!std::isfinite(o.mu0_min) || o.mu0_min < 0.0 || o.mu0_min >= 1.0)
        throw Error("--mu0-min " + num(o.mu0_min) + " must be in [0, 1)");
    if (o.min_pixels < 3) throw Error("--min-pixels must be at least 3 (two parameters and one degree of freedom)");
    if (!std::isfinite(o.min_spread) || o.min_spread < 0.0) throw Error("the minimum spread must be >= 0");
}

std::vector<PlotPoint> minnaert_plot_points(const std::vector<DiscPixel>& pixels, const FitOptions& o) {
    std::vector<PlotPoint> out;
    for (const DiscPixel& p : pixels)
        if (p.a.mu >= o.mu_min && p.a.mu0 >= o.mu0_min && p.a.mu > 0.0 && p.a.mu0 > 0.0 && p.I > 0.0)
            out.push_back({std::log(p.a.mu * p.a.mu0), std::log(p.a.mu * p.I)});
    return out;
}

namespace {

// Refuses a phase at which no pixel can pass both thresholds.
void check_phase_reachable(const SunGeometry& sun, const FitOptions& o) {
    const double need = std::max(o.mu_min, o.mu0_min);
    if (best_min_cos(sun) <= need)
        throw Error("at phase " + num(sun.phase_deg) + " deg no point of the disc has mu >= " + num(o.mu_min) +
                    " and mu0 >= " + num(o.mu0_min) + " (the best is cos(phase/2) = " + num(best_min_cos(sun)) +
                    "): the Minnaert fit is meaningless this close to 180 deg; lower the thresholds or use a "
                    "smaller phase (at most " + num(2.0 * std::acos(need) / kDeg) + " deg for these thresholds)");
}

// The pixels inside the thresholds: `all` of them, and `logs`, those with I > 0 (the Minnaert plot's points).
void collect_obs(const std::vector<DiscPixel>& pixels, const FitOptions& o, MinnaertFit& f, std::vector<Obs>& logs,
                 std::vector<Obs>& all) {
    f.candidates = pixels.size();
    for (const DiscPixel& p : pixels) {
        if (!(p.a.mu >= o.mu_min && p.a.mu0 >= o.mu0_min && p.a.mu > 0.0 && p.a.mu0 > 0.0) || !std::isfinite(p.I)) {
            ++f.below_thresholds;
            continue;
        }
        const Obs ob{std::log(p.a.mu * p.a.mu0), p.a.mu, p.I, p.x, p.y};
        all.push_back(ob);
        if (p.I > 0.0)
            logs.push_back(ob);
        else
            ++f.non_positive;
    }
}

// Refuses too few pixels and too narrow a range of ln(mu mu0) (free B0: its standard deviation; fixed B0: its rms
// about 0, where k has no lever).
void check_obs(const std::vector<Obs>& logs, std::size_t on_disc, const FitOptions& o) {
    if (logs.size() < o.min_pixels)
        throw Error("only " + std::to_string(logs.size()) + " pixels have mu >= " + num(o.mu_min) + ", mu0 >= " +
                    num(o.mu0_min) + " and I > 0 (of " + std::to_string(on_disc) + " on the disc); the fit needs "
                    "at least " + std::to_string(o.min_pixels) + ": use a larger disc, a smaller phase or lower thresholds");
    if (o.fixed_ln_B0 && !std::isfinite(*o.fixed_ln_B0)) throw Error("the fixed ln B0 is not finite");
    double m = 0.0, m2 = 0.0;
    for (const Obs& ob : logs) {
        m += ob.x;
        m2 += ob.x * ob.x;
    }
    m /= double(logs.size());
    const double spread = std::sqrt(std::max(0.0, m2 / double(logs.size()) - (o.fixed_ln_B0 ? 0.0 : m * m)));
    if (spread < o.min_spread)
        throw Error("the " + std::to_string(logs.size()) + " pixels span too narrow a range of ln(mu mu0) (" +
                    (o.fixed_ln_B0 ? std::string("rms ") : std::string("standard deviation ")) + num(spread) + " < " +
                    num(o.min_spread) + ") to determine k" + (o.fixed_ln_B0 ? "" : " and B0 together") +
                    ": use a larger part of the disc");
}

// The fit itself: the Minnaert plot (the classical answer and the start of the others), then the weighted
// iterations or the fit on I. Returns the weights of the last line fit (for the bias estimate).
std::vector<double> fit_by_method(const std::vector<Obs>& logs, const std::vector<Obs>& all, const FitOptions& o,
                                  MinnaertFit& f) {
    std::vector<double> w(logs.size(), 1.0);
    line_fit(logs, w, o.fixed_ln_B0, f);
    f.used = logs.size();
    if (o.method == FitMethod::Weighted) {
        for (int it = 1; it <= 20; ++it) {
            const double k0 = f.k, a0 = f.ln_B0;
            for (std::size_t i = 0; i < logs.size(); ++i) {
                const double m = model_I(f.ln_B0, f.k, logs[i]);
                w[i] = m * m;
            }
            line_fit(logs, w, o.fixed_ln_B0, f);
            f.iterations = it;
            if (std::abs(f.k - k0) < 1e-12 && std::abs(f.ln_B0 - a0) < 1e-12) break;
        }
    } else if (o.method == FitMethod::Intensity) {
        intensity_fit(all, o.fixed_ln_B0, f);
        f.used = all.size();
    }
    f.B0 = std::exp(f.ln_B0);
    f.se_B0 = f.B0 * f.se_ln_B0;
    return w;
}

// The range of ln(mu mu0) used and the rms residuals (of ln(mu I) over I > 0, and relative).
void summarise_residuals(const std::vector<Obs>& used, MinnaertFit& f) {
    f.x_min = 1e300;
    f.x_max = -1e300;
    double sr2 = 0.0, srel2 = 0.0;
    std::size_t nlog = 0;
    for (const Obs& ob : used) {
        f.x_min = std::min(f.x_min, ob.x);
        f.x_max = std::max(f.x_max, ob.x);
        const double m = model_I(f.ln_B0, f.k, ob);
        const double rel = ob.I / m - 1.0;
        srel2 += rel * rel;
        if (ob.I > 0.0) {
            const double r = std::log(ob.I / m);
            sr2 += r * r;
            ++nlog;
        }
    }
    f.rms = nlog ? std::sqrt(sr2 / double(nlog)) : 0.0;
    f.rms_rel = std::sqrt(srel2 / double(f.used));
}

// Pixels with I <= 0: skipped by the log fits (a bias at low S/N), used by the fit on I.
void warn_non_positive(const FitOptions& o, std::size_t logs, MinnaertFit& f) {
    if (f.non_positive == 0) return;
    const double frac = double(f.non_positive) / double(f.non_positive + logs);
    std::ostringstream msg;
    if (o.method == FitMethod::Intensity)
        msg << f.non_positive << " pixels inside the thresholds have I <= 0 (" << 100.0 * frac
            << "%): used as they are by the fit on I";
    else
        msg << f.non_positive << " pixels inside the thresholds have I <= 0 and were skipped (" << 100.0 * frac
            << "%)" << (frac > 0.001 ? ": at this S/N the Minnaert plot is biased; use --method intensity" : "");
    f.warnings.push_back(msg.str());
}

// The pixel noise from neighbouring pixels, and a warning when the residuals are well above it (the law does not
// describe the disc exactly).
void estimate_noise(const std::vector<Obs>& all, MinnaertFit& f) {
    f.noise_sigma = neighbour_noise(all, f.ln_B0, f.k);
    double rms_abs = 0.0;
    for (const Obs& ob : all) {
        const double r = ob.I - model_I(f.ln_B0, f.k, ob);
        rms_abs += r * r;
    }
    rms_abs = std::sqrt(rms_abs / double(all.size()));
    if (f.noise_sigma > 0.0 && rms_abs > 3.0 * f.noise_sigma) {
        std::ostringstream msg;
        msg << "the residuals (rms " << rms_abs << " in I) are " << rms_abs / f.noise_sigma << " times the pixel noise ("
            << f.noise_sigma << "): the Minnaert law does not describe this disc exactly, so k and B0 are a best-fit "
            << "description and their standard errors (which assume independent residuals) understate how much "
            << "they change with the thresholds";
        f.warnings.push_back(msg.str());
    }
}

// The log fits' noise bias, to second order: with additive noise of variance sigma^2 (from neighbouring pixels),
// E[ln(I + e)] = ln I - sigma^2 / (2 I^2). The fit is linear in its y values, so the same regression applied to
// those offsets gives the bias of k and ln B0.
void estimate_log_bias(const std::vector<Obs>& logs, const std::vector<double>& w, const FitOptions& o,
                       MinnaertFit& f) {
    if (o.method == FitMethod::Intensity || f.noise_sigma <= 0.0) return;
    const double s2 = f.noise_sigma * f.noise_sigma;
    std::vector<Obs> shifted = logs;
    for (std::size_t i = 0; i < logs.size(); ++i) {
        const double m = model_I(f.ln_B0, f.k, logs[i]);
        shifted[i].I = m * std::exp(-s2 / (2.0 * m * m));   // ln(mu I) moved by the expected bias
    }
    MinnaertFit b;
    line_fit(shifted, w, o.fixed_ln_B0, b);
    f.bias_k = b.k - f.k;
    f.bias_ln_B0 = b.ln_B0 - f.ln_B0;
    if (std::abs(f.bias_k) > 0.5 * f.se_k || (!o.fixed_ln_B0 && std::abs(f.bias_ln_B0) > 0.5 * f.se_ln_B0)) {
        std::ostringstream msg;
        msg << "with noise sigma ~ " << f.noise_sigma << " in I (from neighbouring pixels), the logarithms bias "
            << "this fit by about " << f.bias_k << " in k (" << f.bias_k / f.se_k << " sigma) and "
            << f.bias_ln_B0 << " in ln B0: --method intensity fits I itself and has no such bias";
        f.warnings.push_back(msg.str());
    }
}

}  // namespace

MinnaertFit fit_minnaert(const std::vector<DiscPixel>& pixels, const SunGeometry& sun, const FitOptions& o) {
    check_fit_options(o);
    check_phase_reachable(sun, o);
    MinnaertFit f;
    std::vector<Obs> logs, all;
    collect_obs(pixels, o, f, logs, all);
    check_obs(logs, pixels.size(), o);
    const std::vector<double> w = fit_by_method(logs, all, o, f);
    summarise_residuals(o.method == FitMethod::Intensity ? all : logs, f);
    warn_non_positive(o, logs.size(), f);
    estimate_noise(all, f);
    estimate_log_bias(logs, w, o, f);
    if (sun.phase_deg > 120.0)
        f.warnings.push_back("phase " + num(sun.phase_deg) + " deg: only a crescent is lit, and mu and mu0 are "
                             "anti-correlated on it; k is determined by few pixels near the bright limb");
    if (!std::isfinite(f.k) || !std::isfinite(f.se_k) || !std::isfinite(f.B0) || !std::isfinite(f.se_B0))
        throw Error("the Minnaert fit did not converge to finite numbers (degenerate pixel set)");
    return f;
}

std::vector<BinFit> fit_longitude_bins(const std::vector<DiscPixel>& pixels, const SunGeometry& sun,
                                       const FitOptions& o, int bins) {
    if (bins < 1 || bins > 1000) throw Error("--bins " + std::to_string(bins) + " must be in [1, 1000]");
    check_fit_options(o);
    double lo = 1e300, hi = -1e300;
    for (const DiscPixel& p : pixels)
        if (p.a.mu >= o.mu_min && p.a.mu0 >= o.mu0_min && p.I > 0.0) {
            lo = std::min(lo, p.a.lambda_deg);
            hi = std::max(hi, p.a.lambda_deg);
        }
    if (!(hi > lo)) throw Error("no pixel passes mu >= " + num(o.mu_min) + ", mu0 >= " + num(o.mu0_min) + ": nothing to bin");
    std::vector<std::vector<DiscPixel>> members(static_cast<std::size_t>(bins));
    for (const DiscPixel& p : pixels) {
        const int b = std::min(bins - 1, std::max(0, int((p.a.lambda_deg - lo) / (hi - lo) * bins)));
        if (p.a.lambda_deg >= lo && p.a.lambda_deg <= hi) members[std::size_t(b)].push_back(p);
    }
    std::vector<BinFit> out;
    for (int b = 0; b < bins; ++b) {
        BinFit r;
        r.i = b;
        r.lo = lo + (hi - lo) * b / bins;
        r.hi = lo + (hi - lo) * (b + 1) / bins;
        try {
            r.fit = fit_minnaert(members[std::size_t(b)], sun, o);
            r.ok = true;
        } catch (const Error& e) {
            r.why = e.what();
        }
        out.push_back(r);
    }
    return out;
}

std::vector<BinFit> fit_grid(const std::vector<DiscPixel>& pixels, const SunGeometry& sun, const FitOptions& o,
                             int cells) {
    if (cells < 1 || cells > 200) throw Error("--grid " + std::to_string(cells) + " must be in [1, 200]");
    check_fit_options(o);
    std::vector<std::vector<DiscPixel>> members(std::size_t(cells) * std::size_t(cells));
    for (const DiscPixel& p : pixels) {
        const int i = std::min(cells - 1, std::max(0, int((p.X + 1.0) * 0.5 * cells)));
        const int j = std::min(cells - 1, std::max(0, int((1.0 - p.Y) * 0.5 * cells)));   // row 0 at the top
        members[std::size_t(j) * std::size_t(cells) + std::size_t(i)].push_back(p);
    }
    std::vector<BinFit> out;
    for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i) {
            BinFit r;
            r.i = i;
            r.j = j;
            r.X = -1.0 + (i + 0.5) * 2.0 / cells;
            r.Y = 1.0 - (j + 0.5) * 2.0 / cells;
            const auto& m = members[std::size_t(j) * std::size_t(cells) + std::size_t(i)];
            if (m.empty()) {
                r.why = "off the disc";
            } else {
                try {
                    r.fit = fit_minnaert(m, sun, o);
                    r.ok = true;
                } catch (const Error& e) {
                    r.why = e.what();
                }
            }
            out.push_back(r);
        }
    return out;
}

std::vector<std::string> hapke_disc_free_parameters(const std::string& model) {
    if (model == "hapke_leg") return {"wh", "theta", "bh"};
    return {"wh", "theta", "hg1"};
}

namespace {
// The parameters of a Hapke law that act only through (1 + B(g)) P(g) at the image's single phase.
std::vector<std::string> single_phase_group(const std::string& model) {
    if (model == "hapke_leg") return {"b0", "hh", "bh", "ch"};
    std::vector<std::string> g = {"b0", "hh", "hg1", "hg2"};
    if (model == "hapke_2012") g.insert(g.end(), {"bc0", "hc"});   // the coherent backscatter B_CB(g) as well
    return g;
}
}  // namespace

HapkeDiscFit fit_hapke_disc(Runtime& rt, const std::vector<DiscPixel>& pixels, const SunGeometry& sun,
                            const FitOptions& o, const photometry::FitSpec& spec) {
    check_fit_options(o);
    const std::string model = photometry::fit_model_name(spec.model);
    if (photometry::fit_has_brightness(model))
        throw Error("moon fit: --law " + spec.model + " is not a Hapke law: use minnaert (the default), hapke_hen, "
                    "hapke_leg or hapke_2012 (photometry fit fits the other laws)");
    HapkeDiscFit r;
    r.candidates = pixels.size();
    photometry::FitData d;
    d.images = 1;
    for (const DiscPixel& p : pixels) {
        if (!(p.a.mu >= o.mu_min && p.a.mu0 >= o.mu0_min && p.a.mu > 0.0 && p.a.mu0 > 0.0) || !std::isfinite(p.I))
            continue;
        d.geometry.push_back({p.a.g_deg, p.a.i_deg, p.a.e_deg});
        d.value.push_back(p.I);
        d.image.push_back(0);
    }
    r.used = d.value.size();
    if (r.used < o.min_pixels)
        throw Error("only " + std::to_string(r.used) + " pixels have mu >= " + num(o.mu_min) + " and mu0 >= " +
                    num(o.mu0_min) + " (of " + std::to_string(pixels.size()) + " on the disc at phase " +
                    num(sun.phase_deg) + " deg); the Hapke fit needs at least " + std::to_string(o.min_pixels) +
                    ": use a larger disc, a smaller phase or lower thresholds");
    photometry::FitSpec s = spec;
    s.model = model;
    if (s.free.empty()) s.free = hapke_disc_free_parameters(model);
    for (const auto& name : single_phase_group(model))
        if (std::find(s.free.begin(), s.free.end(), name) == s.free.end()) r.held.push_back(name);
    r.fit = photometry::fit_law(rt, d, s);
    return r;
}

std::string describe_hapke_disc_fit(const HapkeDiscFit& f, const SunGeometry& sun) {
    std::ostringstream s;
    s << photometry::describe_fit(f.fit);
    s << "pixels used " << f.used << " of " << f.candidates << " on the disc\n";
    std::string held;
    for (const auto& h : f.held) held += (held.empty() ? "" : ", ") + h;
    s << "held: " << held << ": one image has one phase (" << num(sun.phase_deg)
      << " deg), where the opposition surge and the phase function act only through the single number "
         "(1 + B(g)) P(g); fit images at several phases with `photometry fit` to separate them\n";
    return s.str();
}

Comparison compare_pixels(const std::vector<DiscPixel>& pixels, const PhotometricModel& m, const SunGeometry& sun,
                          double mu_min, double mu0_min) {
    Comparison c;
    double s2 = 0.0;
    for (const DiscPixel& p : pixels) {
        if (!(p.a.mu >= mu_min && p.a.mu0 >= mu0_min && p.a.mu > 0.0 && p.a.mu0 > 0.0)) continue;
        const glm::dvec3 N{p.X, p.Y, std::sqrt(std::max(0.0, 1.0 - p.X * p.X - p.Y * p.Y))};
        const double model = m.value(N, sun);
        const double err = std::abs(p.I - model);
        c.max_abs = std::max(c.max_abs, err);
        if (model > 0.0) {
            const double rel = err / model;
            if (rel > c.max_rel) {
                c.max_rel = rel;
                c.worst_X = p.X;
                c.worst_Y = p.Y;
            }
            s2 += rel * rel;
        }
        ++c.n;
    }
    c.rms_rel = c.n ? std::sqrt(s2 / double(c.n)) : 0.0;
    return c;
}

}  // namespace shadelab::moon
