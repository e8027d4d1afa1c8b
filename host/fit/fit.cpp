#include "fit/fit.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

#include "color/color.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "core/lm.hpp"
#include "reference/reference.hpp"

namespace shadelab::fit {

namespace {

// ---- parameters mapped to [0, 1] ------------------------------------------------------------------------
// Linear, unless the range spans more than two decades: then logarithmic (lo > 0) or log(1 + x - lo)
// (lo >= 0 and hi - lo >= 100, e.g. a Phong exponent in [0, 10000]), so the search spends its points evenly
// on the scale where the value changes.
struct Axis {
    enum Kind { Linear, Log, Log1p } kind = Linear;
    double lo = 0.0, hi = 1.0;
    explicit Axis(const ParamSpec& p) : lo(p.lo), hi(p.hi) {
        if (p.lo > 0.0 && p.hi / p.lo >= 100.0) kind = Log;
        else if (p.hi - p.lo >= 100.0) kind = Log1p;
    }
    double x(double u) const {
        u = std::clamp(u, 0.0, 1.0);
        double v = 0.0;
        switch (kind) {
            case Linear: v = lo + u * (hi - lo); break;
            case Log: v = lo * std::exp(u * std::log(hi / lo)); break;
            case Log1p: v = lo + std::expm1(u * std::log1p(hi - lo)); break;
        }
        if (u == 0.0) return lo;
        if (u == 1.0) return hi;
        return std::clamp(v, lo, hi);
    }
    double u(double x) const {
        if (!(hi > lo)) return 0.0;
        double v = 0.0;
        switch (kind) {
            case Linear: v = (x - lo) / (hi - lo); break;
            case Log: v = std::log(x / lo) / std::log(hi / lo); break;
            case Log1p: v = std::log1p(x - lo) / std::log1p(hi - lo); break;
        }
        return std::clamp(v, 0.0, 1.0);
    }
    double dx_du(double u) const {
        switch (kind) {
            case Linear: return hi - lo;
            case Log: return x(u) * std::log(hi / lo);
            case Log1p: return (1.0 + x(u) - lo) * std::log1p(hi - lo);
        }
        return hi - lo;
    }
};

// Values of many parameter sets: per set a vector of n doubles (the first channel: fits are grey).
using ValuesFn = std::function<std::vector<std::vector<double>>(const std::vector<std::vector<double>>&)>;

ValuesFn kernel_values(Evaluator& ev, const ModelShape& shape) {
    return [&ev, shape](const std::vector<std::vector<double>>& sets) {
        const std::size_t n = ev.size();
        const auto f = ev.kernel(shape, sets, 1);
        std::vector<std::vector<double>> out(sets.size());
        for (std::size_t s = 0; s < sets.size(); ++s) {
            if (std::isnan(f[n * s])) {   // a refused set
                out[s].assign(ev.domain().outputs(), std::nan(""));
                continue;
            }
            const std::vector<double> v(f.begin() + n * s, f.begin() + n * (s + 1));
            out[s] = ev.domain().grouped() ? ev.domain().combine(v.data(), shape.albedo.x) : v;
        }
        return out;
    };
}

ValuesFn reference_values(Evaluator& ev, const ModelShape& shape) {
    return [&ev, shape](const std::vector<std::vector<double>>& sets) {
        const std::size_t n = ev.size();
        std::vector<std::vector<double>> out;
        for (const auto& x : sets) {
            const Material m = material_at(shape, x);
            if (!Evaluator::accepts(m)) {
                out.emplace_back(ev.domain().outputs(), std::nan(""));
                continue;
            }
            std::vector<double> v;
            try {
                v = ev.reference(m);
            } catch (const Error&) {   // the reference refuses this combination: no value here
                out.emplace_back(ev.domain().outputs(), std::nan(""));
                continue;
            }
            v.resize(n);
            out.push_back(ev.domain().grouped() ? ev.domain().combine(v.data(), shape.albedo.x) : std::move(v));
        }
        return out;
    };
}

// The best scale and the squared residual: a = max(0, <f, t> / <f, f>), ssr = sum (a f - t)^2 (computed
// directly, not as tt - <f,t>^2/<f,f>, which cancels for exact fits).
struct Scaled {
    double a = 0.0, ssr = 0.0;
};
Scaled best_scale(const std::vector<double>& f, const double* t, std::size_t n) {
    if (!f.empty() && std::isnan(f[0])) return Scaled{0.0, std::numeric_limits<double>::infinity()};   // refused set
    double ft = 0.0, ff = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        ft += f[i] * t[i];
        ff += f[i] * f[i];
    }
    Scaled s;
    s.a = ff > 0.0 ? std::max(0.0, ft / ff) : 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double r = s.a * f[i] - t[i];
        s.ssr += r * r;
    }
    return s;
}

double sum_sq(const double* t, std::size_t n) {
    double s = 0.0;
    for (std::size_t i = 0; i < n; ++i) s += t[i] * t[i];
    return s;
}

// The state of a fit in mapped coordinates.
struct Point {
    std::vector<double> x;   // every parameter, declared order, model units
    double a = 0.0, ssr = std::numeric_limits<double>::infinity();
};

struct Space {
    const ModelInfo* info = nullptr;
    std::vector<Axis> axes;            // one per parameter
    std::vector<std::size_t> free_c;   // continuous parameters being fitted
    std::vector<std::size_t> free_i;   // whole-number parameters being fitted
};

std::vector<double> with_u(const Space& sp, std::vector<double> x, std::size_t j, double u) {
    x[j] = sp.axes[j].x(u);
    return x;
}

// The Jacobian columns d(a f)/du_j at p by central (or forward) differences in mapped units, one-sided at a bound
// (never outside the box), and the scale's column f; then J^T J and the descent direction -J^T r, r = a f - t.
void fit_normal(const ValuesFn& F, const double* t, std::size_t n, const Space& sp, const Point& p,
                const std::vector<double>& f0, double h, bool central, lm::Normal& ne) {
    const std::size_t k = sp.free_c.size(), K = k + 1;
    std::vector<std::vector<double>> sets;
    std::vector<double> du(k), u(k);
    std::vector<bool> down_is_centre(k, false);
    for (std::size_t c = 0; c < k; ++c) {
        const std::size_t j = sp.free_c[c];
        u[c] = sp.axes[j].u(p.x[j]);
        double up = std::min(1.0, u[c] + h), dn = std::max(0.0, u[c] - h);
        if (!central) {
            if (u[c] + h <= 1.0) dn = u[c];   // forward
            else up = u[c];                    // backward at the upper bound
        }
        down_is_centre[c] = !central && dn == u[c];
        const bool up_is_centre = !central && up == u[c];
        if (!up_is_centre) sets.push_back(with_u(sp, p.x, j, up));
        if (!down_is_centre[c]) sets.push_back(with_u(sp, p.x, j, dn));
        du[c] = up - dn;
    }
    const auto fv = F(sets);
    std::vector<std::vector<double>> J(K, std::vector<double>(n));
    for (std::size_t c = 0, q = 0; c < k; ++c) {
        const std::vector<double>* hi_v = &f0;
        const std::vector<double>* lo_v = &f0;
        if (central) {
            hi_v = &fv[q++];
            lo_v = &fv[q++];
        } else if (down_is_centre[c]) {
            hi_v = &fv[q++];
        } else {
            lo_v = &fv[q++];
        }
        for (std::size_t i = 0; i < n; ++i) J[c][i] = du[c] > 0.0 ? p.a * ((*hi_v)[i] - (*lo_v)[i]) / du[c] : 0.0;
    }
    J[k] = f0;
    ne.A.assign(K * K, 0.0);
    ne.g.assign(K, 0.0);
    for (std::size_t r1 = 0; r1 < K; ++r1) {
        for (std::size_t r2 = r1; r2 < K; ++r2) {
            double s = 0.0;
            for (std::size_t i = 0; i < n; ++i) s += J[r1][i] * J[r2][i];
            ne.A[r1 * K + r2] = ne.A[r2 * K + r1] = s;
        }
        double s = 0.0;
        for (std::size_t i = 0; i < n; ++i) s += J[r1][i] * (p.a * f0[i] - t[i]);
        ne.g[r1] = -s;
    }
    ne.x = u;
    ne.x.push_back(p.a);
    ne.lo.assign(K, 0.0);
    ne.hi.assign(K, 1.0);
    ne.bounded.assign(K, true);
    ne.lo[k] = -std::numeric_limits<double>::infinity();   // the scale: solved along, re-solved in closed form
    ne.hi[k] = std::numeric_limits<double>::infinity();
    ne.bounded[k] = false;
}

// Bounded Levenberg-Marquardt (core/lm.hpp) over the free continuous parameters (mapped to [0, 1]) and the scale,
// the scale re-solved in closed form at every point. `h`: finite-difference step in mapped units; `trials`: damping
// values tried per iteration in one batch.
Point levenberg_marquardt(const ValuesFn& F, const double* t, std::size_t n, const Space& sp, Point p, double h,
                          int iterations, int trials, double tt, bool central) {
    const std::size_t k = sp.free_c.size();
    if (k == 0) return p;
    std::vector<double> f0 = F({p.x})[0];
    {
        const Scaled s = best_scale(f0, t, n);
        p.a = s.a;
        p.ssr = s.ssr;
    }
    lm::Settings ls;
    ls.trials = [trials](double lambda) {
        std::vector<double> lams;
        for (int q = 0; q < trials; ++q) lams.push_back(lambda * std::pow(10.0, q - (trials - 1) / 2));
        return lams;
    };
    ls.accept_divisor = 3.0;
    ls.lambda_floor = 1e-12;
    ls.reject_factor = std::pow(10.0, trials + 1);
    ls.ridge = 1e-15;
    ls.min_diagonal = 1e-24;
    ls.solve_tiny = 1e-16;
    ls.attempts = 8;
    ls.min_step = 1e-12;
    ls.max_iterations = iterations;

    std::vector<double> u(k);
    std::vector<std::vector<double>> cand, evaluated, values;   // proposed; the last batch and its values
    std::vector<Scaled> scaled;
    lm::Callbacks cb;
    cb.normal = [&](lm::Normal& ne) {
        fit_normal(F, t, n, sp, p, f0, h, central, ne);
        u.assign(ne.x.begin(), ne.x.begin() + std::ptrdiff_t(k));
    };
    cb.propose = [&](const std::vector<double>& y) {
        std::vector<double> xn = p.x;
        for (std::size_t c = 0; c < k; ++c)
            if (y[c] != u[c]) xn[sp.free_c[c]] = sp.axes[sp.free_c[c]].x(y[c]);
        if (xn == p.x) return false;
        cand.push_back(std::move(xn));
        return true;
    };
    cb.evaluate = [&] {
        evaluated = std::move(cand);
        cand.clear();
        values = F(evaluated);
        scaled.clear();
        std::vector<double> costs;
        for (const auto& v : values) {
            scaled.push_back(best_scale(v, t, n));
            costs.push_back(std::isnan(scaled.back().ssr) ? std::numeric_limits<double>::infinity() : scaled.back().ssr);
        }
        return costs;
    };
    cb.accept = [&](std::size_t i) {
        p.x = evaluated[i];
        p.a = scaled[i].a;
        p.ssr = scaled[i].ssr;
        f0 = values[i];
        return p.ssr;
    };
    cb.converged = [&](double before, double after) { return before - after <= 1e-13 * after + 1e-30 * tt; };
    lm::minimise(ls, cb, p.ssr);
    return p;
}


std::string pct(double x) { return num(100.0 * x, 3) + "%"; }

// Quasi-random point i in [0, 1)^d (Halton, first d primes).
double halton(std::uint64_t i, int dim) {
    static const unsigned primes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71};
    const unsigned b = primes[dim % 20];
    double f = 1.0 / b, r = 0.0;
    for (std::uint64_t k = i + 1; k > 0; k /= b, f /= b) r += f * double(k % b);
    return r;
}

// Candidate values of a whole-number parameter: every integer when there are at most 512, else 512 spread
// on its axis.
std::vector<double> integer_values(const ParamSpec& p, const Axis& ax) {
    std::vector<double> v;
    const double lo = std::ceil(p.lo), hi = std::floor(p.hi);
    if (hi - lo + 1 <= 512) {
        for (double x = lo; x <= hi; x += 1.0) v.push_back(x);
    } else {
        for (int q = 0; q < 512; ++q) v.push_back(std::clamp(std::round(ax.x(q / 511.0)), lo, hi));
        v.erase(std::unique(v.begin(), v.end()), v.end());
    }
    return v;
}

// The coarse candidate sets: a grid over up to 3 parameters (per axis 129, 33, 13 points), else 2048
// quasi-random points; whole-number parameters take their candidate values; and the defaults.
std::vector<std::vector<double>> coarse_sets(const Space& sp, const std::vector<double>& base) {
    std::vector<std::size_t> dims = sp.free_c;
    dims.insert(dims.end(), sp.free_i.begin(), sp.free_i.end());
    std::vector<std::vector<double>> values(dims.size());
    const std::size_t d = dims.size();
    const int per_axis = d == 1 ? 129 : d == 2 ? 33 : 13;
    double grid = 1.0;
    for (std::size_t q = 0; q < d; ++q) {
        const std::size_t j = dims[q];
        const ParamSpec& p = sp.info->params[j];
        if (p.integer) values[q] = integer_values(p, sp.axes[j]);
        else
            for (int g = 0; g < per_axis; ++g) values[q].push_back(sp.axes[j].x(g / double(per_axis - 1)));
        grid *= double(values[q].size());
    }
    std::vector<std::vector<double>> sets;
    if (d == 0) return sets;
    if (d <= 3 && grid <= 8192) {
        std::vector<std::size_t> idx(d, 0);
        for (;;) {
            std::vector<double> x = base;
            for (std::size_t q = 0; q < d; ++q) x[dims[q]] = values[q][idx[q]];
            sets.push_back(x);
            std::size_t q = 0;
            while (q < d && ++idx[q] == values[q].size()) idx[q++] = 0;
            if (q == d) break;
        }
    } else {
        for (std::uint64_t i = 0; i < 2048; ++i) {
            std::vector<double> x = base;
            for (std::size_t q = 0; q < d; ++q) {
                const double u = halton(i, int(q));
                const std::size_t j = dims[q];
                if (sp.info->params[j].integer)
                    x[j] = values[q][std::min(values[q].size() - 1, std::size_t(u * double(values[q].size())))];
                else
                    x[j] = sp.axes[j].x(u);
            }
            sets.push_back(x);
        }
    }
    // The defaults as one more candidate, for grids too: they are often a sensible start, and a model whose
    // error is steep in its parameters (lunar_lambert_mcewen_ratio near the terminator) may have no grid point
    // near its optimum.
    std::vector<double> x = base;
    for (std::size_t q = 0; q < d; ++q) x[dims[q]] = sp.info->params[dims[q]].def;
    sets.push_back(x);
    return sets;
}

double u_distance(const Space& sp, const std::vector<double>& a, const std::vector<double>& b) {
    double m = 0.0;
    for (std::size_t j = 0; j < a.size(); ++j) m = std::max(m, std::abs(sp.axes[j].u(a[j]) - sp.axes[j].u(b[j])));
    return m;
}

// Whole-number parameters: neighbours +-1 tried while they lower the error.
Point integer_neighbours(const ValuesFn& F, const double* t, std::size_t n, const Space& sp, Point p) {
    for (int round = 0; round < 32; ++round) {
        bool moved = false;
        for (std::size_t j : sp.free_i) {
            const ParamSpec& ps = sp.info->params[j];
            std::vector<std::vector<double>> cand;
            for (double dx : {-1.0, 1.0}) {
                const double v = p.x[j] + dx;
                if (v < ps.lo || v > ps.hi) continue;
                std::vector<double> x = p.x;
                x[j] = v;
                cand.push_back(x);
            }
            if (cand.empty()) continue;
            const auto cv = F(cand);
            for (std::size_t q = 0; q < cand.size(); ++q) {
                const Scaled s = best_scale(cv[q], t, n);
                if (s.ssr < p.ssr) {
                    p.x = cand[q];
                    p.a = s.a;
                    p.ssr = s.ssr;
                    moved = true;
                }
            }
        }
        if (!moved) break;
    }
    return p;
}

// Coarse search, then LM in float from the best distinct starts, then polish in double.
// `start`: refine from there (no coarse search). `float_only`: the float LM alone, on every sample (on the
// float_samples prefix for over 4 parameters), no double polish: the limb check's refit, which compares
// parameters at 1e-3 of their range.
Point search(Problem& problem, const ModelShape& shape, const Space& sp, const std::vector<double>& base,
             const FitOptions& o, const Point* start, bool float_only = false) {
    Evaluator& full = problem.full();
    const std::vector<double>& t_full = problem.target();
    const Problem::Prefix coarse = problem.prefix(o.coarse_samples),
                          mid = problem.prefix(float_only && sp.free_c.size() <= 4 ? full.size() : o.float_samples);
    const std::size_t n = full.domain().outputs(), nm = mid.ev->domain().outputs();
    const double tt = sum_sq(t_full.data(), n), tt_mid = sum_sq(mid.target->data(), nm);
    const ValuesFn Fk = kernel_values(*mid.ev, shape), Fr = reference_values(full, shape);
    std::vector<Point> starts;
    if (start) {
        starts.push_back(*start);
    } else {
        const auto sets = coarse_sets(sp, base);
        if (sets.empty()) {
            starts.push_back(Point{base});
        } else {
            // Every set's error on a prefix of the domain, best first.
            auto ranked = [&](const Problem::Prefix& pre, const std::vector<std::vector<double>>& xs) {
                const ValuesFn Fc = kernel_values(*pre.ev, shape);
                const std::size_t np = pre.ev->domain().outputs();
                std::vector<Point> pts;
                for (std::size_t s0 = 0; s0 < xs.size(); s0 += 512) {
                    const std::vector<std::vector<double>> chunk(xs.begin() + s0, xs.begin() + std::min(xs.size(), s0 + 512));
                    const auto v = Fc(chunk);
                    for (std::size_t q = 0; q < chunk.size(); ++q) {
                        const Scaled s = best_scale(v[q], pre.target->data(), np);
                        pts.push_back(Point{chunk[q], s.a, s.ssr});
                    }
                }
                std::stable_sort(pts.begin(), pts.end(), [](const Point& a, const Point& b) { return a.ssr < b.ssr; });
                return pts;
            };
            // Coarser, then finer: a large candidate list is screened on the first coarse_screen samples and only
            // its best coarse_keep sets are ranked on coarse_samples (where the starts are picked, as before).
            std::vector<Point> all;
            const Problem::Prefix screen = problem.prefix(o.coarse_screen);
            if (sets.size() > o.coarse_keep && screen.ev->size() < coarse.ev->size()) {
                const std::vector<Point> first = ranked(screen, sets);
                std::vector<std::vector<double>> kept;
                for (std::size_t q = 0; q < first.size() && kept.size() < o.coarse_keep; ++q) kept.push_back(first[q].x);
                all = ranked(coarse, kept);
            } else {
                all = ranked(coarse, sets);
            }
            for (const auto& p : all) {
                const std::size_t d = sp.free_c.size() + sp.free_i.size();
                if (int(starts.size()) >= (d > 4 ? 2 : o.starts)) break;
                bool distinct = true;
                for (const auto& q : starts) distinct = distinct && u_distance(sp, p.x, q.x) > 0.1;
                if (distinct) starts.push_back(p);
            }
        }
    }
    Point best;
    std::vector<Point> candidates = starts;   // the starts themselves too: the float LM may drift off an exact start
    for (Point p : starts) {
        // Over 4 parameters (each iteration a batch of 2d sets) fewer float iterations.
        const int iters = sp.free_c.size() > 4 ? std::min(o.float_iterations, 15) : o.float_iterations;
        if (!start || float_only) p = levenberg_marquardt(Fk, mid.target->data(), nm, sp, p, 1e-3, iters, 3, tt_mid, true);
        if (p.ssr < best.ssr || best.x.empty()) best = p;
        candidates.push_back(p);
    }
    if (float_only) return best;
    // Polish in double: the best of the candidates by the references' error, then LM with small steps.
    {
        const auto fv = Fr([&] {
            std::vector<std::vector<double>> xs;
            for (const auto& c : candidates) xs.push_back(c.x);
            return xs;
        }());
        best = Point{};
        for (std::size_t q = 0; q < candidates.size(); ++q) {
            const Scaled s = best_scale(fv[q], t_full.data(), n);
            if (s.ssr < best.ssr || best.x.empty()) best = Point{candidates[q].x, s.a, s.ssr};
        }
    }
    const int polish = sp.free_c.size() > 4 ? std::min(o.double_iterations, 3) : o.double_iterations;
    best = levenberg_marquardt(Fr, t_full.data(), n, sp, best, 1e-7, polish, 1, tt, false);
    if (!sp.free_i.empty()) {
        best = integer_neighbours(Fr, t_full.data(), n, sp, best);
        best = levenberg_marquardt(Fr, t_full.data(), n, sp, best, 1e-7, polish, 1, tt, false);
    }
    return best;
}

}  // namespace

// ---- Problem --------------------------------------------------------------------------------------------------

Problem::Problem(Runtime& rt, Domain domain, Material target, Precision precision)
    : rt_(rt), precision_(precision), target_m_(resolve_material(target, "fit target")) {
    full_ = std::make_unique<Evaluator>(rt_, std::move(domain), precision_);
    const auto v = full_->reference(target_m_);   // 3 planes; grey: the first
    target_ = full_->domain().combine(v.data(), target_m_.albedo.x);
    target_name_ = target_m_.model;
}

Problem::Problem(Runtime& rt, Domain domain, std::vector<double> values, const std::string& name, Precision precision)
    : rt_(rt), precision_(precision), target_name_(name) {
    target_m_.model = "lambert";   // only its grey albedo (0.8) is read: the fitted model's albedo before the scale
    target_m_ = resolve_material(target_m_);
    full_ = std::make_unique<Evaluator>(rt_, std::move(domain), precision_);
    if (values.size() != full_->domain().outputs())
        throw Error("internal: " + std::to_string(values.size()) + " target values for " +
                    std::to_string(full_->domain().outputs()) + " outputs");
    for (double& x : values)
        if (!std::isfinite(x)) x = 0.0;
    target_ = std::move(values);
}

void Problem::set_observer(std::function<void(const std::string&, const std::vector<double>&)> f) {
    observer_ = f;
    full_->observer = f;
    for (auto& [_, o] : prefixes_) o.ev->observer = f;
    if (grazing_) grazing_->set_observer(f);
}

std::size_t Problem::kernel_evaluations() const {
    std::size_t s = full_->kernel_evaluations() + (grazing_ ? grazing_->kernel_evaluations() : 0);
    for (const auto& [_, o] : prefixes_) s += o.ev->kernel_evaluations();
    return s;
}

std::size_t Problem::reference_evaluations() const {
    std::size_t s = full_->reference_evaluations() + (grazing_ ? grazing_->reference_evaluations() : 0);
    for (const auto& [_, o] : prefixes_) s += o.ev->reference_evaluations();
    return s;
}

double Problem::kernel_ms() const {
    double s = full_->kernel_ms() + (grazing_ ? grazing_->kernel_ms() : 0.0);
    for (const auto& [_, o] : prefixes_) s += o.ev->kernel_ms();
    return s;
}

Problem::Prefix Problem::prefix(std::size_t samples) {
    const std::size_t pg = full_->domain().per_group;
    samples = samples / pg * pg;
    if (samples >= full_->size() || samples == 0) return Prefix{full_.get(), &target_};
    auto it = prefixes_.find(samples);
    if (it == prefixes_.end()) {
        Owned o;
        o.ev = std::make_unique<Evaluator>(rt_, full_->domain().prefix(samples), precision_);
        o.ev->observer = observer_;
        o.target.assign(target_.begin(), target_.begin() + o.ev->domain().outputs());   // outputs are fragment-major
        it = prefixes_.emplace(samples, std::move(o)).first;
    }
    return Prefix{it->second.ev.get(), &it->second.target};
}

Problem& Problem::grazing(double c) {
    if (!grazing_ || grazing_c_ != c) {
        Domain d = grazing_cut(full_->domain(), c, &grazing_kept_);
        if (d.size() < 64) throw Error("the limb check keeps fewer than 64 samples: the domain is all grazing");
        std::vector<double> t;   // the target's values there (not grouped: one output per sample)
        for (std::size_t i : grazing_kept_) t.push_back(target_[i]);
        grazing_ = std::make_unique<Problem>(rt_, std::move(d), std::move(t), target_name_, precision_);
        grazing_->target_m_ = target_m_;
        grazing_->set_observer(observer_);
        grazing_c_ = c;
    }
    return *grazing_;
}

// ---- fitting -----------------------------------------------------------------------------------------------------

std::vector<double> FitResult::values() const {
    std::vector<double> v;
    for (const auto& p : params) v.push_back(p.value);
    return v;
}

double best_scale_rel_rms(const std::vector<double>& f, const std::vector<double>& t, std::size_t n, double* scale) {
    const Scaled s = best_scale(f, t.data(), n);
    if (scale) *scale = s.a;
    const double tt = sum_sq(t.data(), n);
    return tt > 0.0 ? std::sqrt(s.ssr / tt) : 0.0;
}

ModelShape shape_for(const std::string& model, const Material& target, double specular, std::string* note) {
    const ModelInfo& info = find_model(model);
    ModelShape s;
    s.model = info.name;
    s.albedo = target.albedo;
    s.specular = specular < 0.0 ? target.specular : glm::dvec3(specular);
    for (int c = 0; c < info.children; ++c) {
        Material child;
        child.model = "lambert";
        child.albedo = glm::dvec3(1.0);
        s.children.push_back(resolve_material(child));
    }
    if (info.children > 0 && note)
        *note = "'" + info.name + "' blends " + std::to_string(info.children) +
                " child materials; fitted with white Lambert children (a scene's children are its own), so it "
                "is Lambert times its blend";
    if (has_tables(info) && note)
        *note = "'" + info.name + "' reads tables (" + info.tables.front().name +
                ", ...): fitted with its default tables held, since a fit varies no table";
    return s;
}

namespace {

// What the reports after the search read: the problem, the model, the optimum and its values there.
struct Optimum {
    Problem& problem;
    const ModelShape& shape;
    const ModelInfo& info;
    const Space& sp;
    const std::vector<double>& base;
    const Point& best;
    const std::vector<double>& fbest;   // the model's values at the optimum (references), before the scale
    const std::vector<double>& t;       // the target's
    std::size_t n;                      // outputs
    double tt, rel_rms;
};

// The Jacobian at the optimum and what follows from it: parameters with no effect, the covariance.
struct Sensitivity {
    std::vector<std::vector<double>> J;   // d(a f)/dx_j per free continuous parameter, then f (the scale's)
    std::vector<double> colnorm;
    std::vector<bool> no_effect;
    std::vector<std::size_t> live;        // columns in the covariance (the last: the scale)
    std::vector<double> cov;              // (J^T J)^-1 over `live`, row-major
    bool cov_ok = true;
};

void say(FitResult& r, const std::string& kind, const std::string& text, bool ill = true) {
    r.diagnostics.push_back({kind, text, ill});
}

// The errors of the optimum in double (and Delta E 2000 of the rendered colours on a scene), and where the
// largest difference is.
void measure_errors(const Optimum& z, FitResult& r) {
    const Point& best = z.best;
    const std::vector<double>& fbest = z.fbest;
    const std::vector<double>& t = z.t;
    const std::size_t n = z.n;
    const Domain& dom = z.problem.full().domain();
    double max_abs = 0.0, max_t = 0.0;
    std::size_t worst = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double d = std::abs(best.a * fbest[i] - t[i]);
        if (d > max_abs) max_abs = d, worst = i;
        max_t = std::max(max_t, std::abs(t[i]));
    }
    r.error["rel-rms"] = z.rel_rms;
    r.error["rms"] = std::sqrt(best.ssr / double(n));
    r.error["max-abs"] = max_abs;
    r.error["rel-max"] = max_t > 0.0 ? max_abs / max_t : 0.0;
    r.worst.index = worst;
    // Scene outputs are fragment channels: the angles of the fragment's first light.
    r.worst.angles = angles_of(dom, dom.grouped() ? worst / 3 * dom.per_group : worst);
    if (dom.grouped()) {
        // The rendered colours (linear sRGB) as CIE L*a*b*: Delta E 2000 per fragment.
        std::vector<double> de;
        for (std::size_t f = 0; f + 2 < n; f += 3) {
            const glm::dvec3 tc(t[f], t[f + 1], t[f + 2]), fc(best.a * fbest[f], best.a * fbest[f + 1], best.a * fbest[f + 2]);
            const double e = delta_e2000(lab_from_linear_srgb(glm::max(tc, 0.0)), lab_from_linear_srgb(glm::max(fc, 0.0)));
            de.push_back(std::isfinite(e) ? e : 0.0);
        }
        std::sort(de.begin(), de.end());
        double sum = 0.0;
        for (double e : de) sum += e;
        r.error["de2000-mean"] = de.empty() ? 0.0 : sum / double(de.size());
        r.error["de2000-p99"] = de.empty() ? 0.0 : de[std::min(de.size() - 1, std::size_t(0.99 * double(de.size())))];
        r.error["de2000-max"] = de.empty() ? 0.0 : de.back();
    }
    r.worst.target = t[worst];
    r.worst.fit = best.a * fbest[worst];
}

// Standard errors from the Jacobian at the optimum (into r), the parameters with no effect, the covariance.
Sensitivity sensitivity(const Optimum& z, FitResult& r) {
    const Space& sp = z.sp;
    const Point& best = z.best;
    const std::vector<double>& fbest = z.fbest;
    const std::size_t n = z.n;
    const ValuesFn Fr = reference_values(z.problem.full(), z.shape), Fk = kernel_values(z.problem.full(), z.shape);
    Sensitivity sens;
    auto& J = sens.J;
    auto& colnorm = sens.colnorm;
    auto& no_effect = sens.no_effect;
    auto& live = sens.live;
    auto& cov = sens.cov;
    bool& cov_ok = sens.cov_ok;
    // Standard errors: cov = s^2 (J^T J)^-1 over the free continuous parameters (model units) and the scale,
    // s^2 = ssr / (n - p), J by central differences in double at the optimum (one-sided at a bound).
    const std::size_t k = sp.free_c.size();
    colnorm.assign(k, 0.0);
    {
        // Over 4 parameters: forward differences (half the reference evaluations; ample for standard errors).
        const bool central = k <= 4;
        std::vector<std::vector<double>> sets;
        std::vector<double> dx(k);
        for (std::size_t c = 0; c < k; ++c) {
            const std::size_t j = sp.free_c[c];
            const double u = sp.axes[j].u(best.x[j]);
            double up = std::min(1.0, u + 1e-5), dn = std::max(0.0, u - 1e-5);
            if (!central && up > u) dn = u;
            auto xu = with_u(sp, best.x, j, up), xd = with_u(sp, best.x, j, dn);
            dx[c] = xu[j] - xd[j];
            sets.push_back(xu);
            if (central || dn < u) sets.push_back(xd);
            else sets.push_back({});   // the optimum itself: fbest
        }
        std::vector<std::vector<double>> todo;
        for (const auto& x : sets)
            if (!x.empty()) todo.push_back(x);
        const auto got = todo.empty() ? std::vector<std::vector<double>>{} : Fr(todo);
        std::vector<std::vector<double>> fv;
        for (std::size_t q = 0, g = 0; q < sets.size(); ++q) fv.push_back(sets[q].empty() ? fbest : got[g++]);
        for (std::size_t c = 0; c < k; ++c) {
            std::vector<double> col(n, 0.0);
            if (dx[c] > 0.0)
                for (std::size_t i = 0; i < n; ++i) col[i] = best.a * (fv[2 * c][i] - fv[2 * c + 1][i]) / dx[c];
            for (double v : col) colnorm[c] += v * v;
            J.push_back(std::move(col));
        }
        J.push_back(fbest);
    }
    // No effect: the model's values at the two ends of the parameter's range, the others as fitted, equal to
    // the fitted values within float rounding (kernel; one batch for all parameters).
    no_effect.assign(k, false);
    if (k > 0) {
        std::vector<std::vector<double>> sets;
        for (std::size_t c = 0; c < k; ++c) {
            const std::size_t j = sp.free_c[c];
            sets.push_back(with_u(sp, best.x, j, 0.0));
            sets.push_back(with_u(sp, best.x, j, 1.0));
        }
        const auto fv = Fk(sets);
        double fmax = 0.0;
        for (double v : fbest) fmax = std::max(fmax, std::abs(v));
        for (std::size_t c = 0; c < k; ++c) {
            double d = 0.0;
            for (int e = 0; e < 2; ++e)
                for (std::size_t i = 0; i < n; ++i) d = std::max(d, std::abs(fv[2 * c + e][i] - fbest[i]));
            no_effect[c] = d <= 1e-6 * fmax;
        }
    }
    for (std::size_t c = 0; c < k; ++c)
        if (!no_effect[c] && colnorm[c] > 0.0) live.push_back(c);
    live.push_back(k);   // the scale
    const std::size_t m = live.size();
    std::vector<double> A(m * m, 0.0);
    for (std::size_t a1 = 0; a1 < m; ++a1)
        for (std::size_t a2 = a1; a2 < m; ++a2) {
            double s = 0.0;
            for (std::size_t i = 0; i < n; ++i) s += J[live[a1]][i] * J[live[a2]][i];
            A[a1 * m + a2] = A[a2 * m + a1] = s;
        }
    cov.assign(m * m, 0.0);
    cov_ok = true;
    for (std::size_t c = 0; c < m && cov_ok; ++c) {
        std::vector<double> e(m, 0.0), col;
        e[c] = 1.0;
        cov_ok = lm::solve(A, e, m, col, 1e-13);
        for (std::size_t q = 0; q < m && cov_ok; ++q) cov[q * m + c] = col[q];
    }
    const double dof = double(n) > double(m) ? double(n) - double(m) : 1.0;
    const double s2 = best.ssr / dof;
    if (cov_ok) {
        for (std::size_t q = 0; q < m; ++q) {
            const double v = std::sqrt(std::max(0.0, s2 * cov[q * m + q]));
            if (live[q] == k) {
                r.se_albedo = v * z.shape.albedo.x;
            } else {
                r.params[sp.free_c[live[q]]].se = v;
                r.params[sp.free_c[live[q]]].se_known = std::isfinite(v);
            }
        }
    }
    return sens;
}

// The diagnostics in words: not representable; per parameter no effect, at a limit, poorly determined, flat;
// trade-offs from the covariance.
void diagnose(const Optimum& z, const Sensitivity& sens, const FitOptions& o, FitResult& r) {
    const ModelInfo& info = z.info;
    const Space& sp = z.sp;
    const Point& best = z.best;
    const std::vector<double>& fbest = z.fbest;
    const std::vector<double>& t = z.t;
    const std::size_t n = z.n;
    const double tt = z.tt, rel_rms = z.rel_rms;
    const ValuesFn Fk = kernel_values(z.problem.full(), z.shape);
    const auto& J = sens.J;
    const auto& no_effect = sens.no_effect;
    const auto& live = sens.live;
    const auto& cov = sens.cov;
    const bool cov_ok = sens.cov_ok;
    const std::size_t k = sp.free_c.size(), m = live.size();
    // Not representable.
    if (rel_rms > o.representable) {
        r.representable = false;
        const auto& a = r.worst.angles;
        say(r, "not_representable",
            "the model cannot represent the target on this domain: its best fit leaves a rel-rms of " + pct(rel_rms) +
                " (largest difference at theta_i " + num(a.theta_i, 3) + ", theta_r " + num(a.theta_r, 3) + ", dphi " +
                num(a.dphi, 3) + " deg: target " + num(r.worst.target, 4) + ", fit " + num(r.worst.fit, 4) + ")",
            false);
    }
    // Per parameter: no effect, at a limit, flat.
    std::vector<std::vector<double>> flat_sets;
    std::vector<std::size_t> flat_of;
    for (std::size_t c = 0; c < k; ++c) {
        const std::size_t j = sp.free_c[c];
        const ParamSpec& p = info.params[j];
        if (no_effect[c]) {
            say(r, "no_effect", p.name + " has no effect on the value over this domain (with the other parameters as "
                             "fitted): any value in [" + num(p.lo) + ", " + num(p.hi) + "] fits equally; reported at " +
                                 num(best.x[j]));
            continue;
        }
        const double u = sp.axes[j].u(best.x[j]);
        if (u <= 1e-9 || u >= 1.0 - 1e-9) {
            const bool lower = u <= 1e-9;
            // Does the error fall beyond the limit? The gradient of ssr in the outward direction.
            double g = 0.0;
            for (std::size_t i = 0; i < n; ++i) g += J[c][i] * (best.a * fbest[i] - t[i]);
            const bool outward = lower ? g > 0.0 : g < 0.0;
            say(r, "at_limit", p.name + " is at the " + (lower ? "lower" : "upper") + " limit of its range (" +
                                num(lower ? p.lo : p.hi) + ")" +
                                (outward && rel_rms > 1e-8 ? ": the error would fall further beyond it"
                                                           : ", where the fit is best"),
                outward && rel_rms > 1e-8);
        }
        for (double du : {-0.05, 0.05}) {
            const double uu = std::clamp(u + du, 0.0, 1.0);
            if (std::abs(uu - u) < 0.025) continue;   // at a limit: only the inward side
            flat_sets.push_back(with_u(sp, best.x, j, uu));
            flat_of.push_back(c);
        }
        if (r.params[j].se_known && r.params[j].se > 0.1 * (p.hi - p.lo))
            say(r, "poorly_determined", p.name + " is poorly determined: standard error " + num(r.params[j].se, 3) +
                                         " against a range of [" + num(p.lo) + ", " + num(p.hi) + "]");
    }
    if (!flat_sets.empty()) {
        const auto fv = Fk(flat_sets);
        std::vector<double> rise(k, std::numeric_limits<double>::infinity());
        const double float_floor = 1e-6;   // the float kernel's own rel-rms noise is ~1e-7
        for (std::size_t q = 0; q < flat_sets.size(); ++q) {
            const Scaled s = best_scale(fv[q], t.data(), n);
            rise[flat_of[q]] = std::min(rise[flat_of[q]], std::sqrt(s.ssr / tt) - rel_rms);
        }
        for (std::size_t c = 0; c < k; ++c)
            if (std::isfinite(rise[c]) && rise[c] < std::max(1e-3 * rel_rms, float_floor)) {
                const ParamSpec& p = info.params[sp.free_c[c]];
                say(r, "flat", "the objective is flat in " + p.name + ": moving it by 5% of its range changes the "
                            "rel-rms by " + num(std::max(0.0, rise[c]), 2) + " (of " + num(rel_rms, 3) +
                            "), so the value is not pinned down");
            }
    }
    // Trade-offs (covariance correlations), scale included.
    if (cov_ok)
        for (std::size_t a1 = 0; a1 < m; ++a1)
            for (std::size_t a2 = a1 + 1; a2 < m; ++a2) {
                const double den = std::sqrt(cov[a1 * m + a1] * cov[a2 * m + a2]);
                if (!(den > 0.0)) continue;
                const double corr = cov[a1 * m + a2] / den;
                if (std::abs(corr) > 0.995) {
                    auto nm = [&](std::size_t q) {
                        return live[q] == k ? std::string("the albedo") : info.params[sp.free_c[live[q]]].name;
                    };
                    say(r, "trade_off", nm(a1) + " and " + nm(a2) + " trade off (correlation " + num(corr, 4) +
                                         "): this domain hardly separates them");
                }
            }
    if (!cov_ok && k > 0)
        say(r, "trade_off", "the normal matrix is singular: some parameters (or a parameter and the albedo) have the "
                         "same effect on this domain, so no standard errors");
}

// The limb check (hemisphere-like domains only: a scene's outputs sum several lights, so a sample cut would split
// fragments): the share of the squared residual carried by near-grazing samples, and a refit without them.
void limb_check(const Optimum& z, const FitOptions& o, FitResult& r) {
    const ModelInfo& info = z.info;
    const ModelShape& shape = z.shape;
    const Space& sp = z.sp;
    const std::vector<double>& base = z.base;
    const Point& best = z.best;
    const std::vector<double>& fbest = z.fbest;
    const std::vector<double>& t = z.t;
    const std::size_t n = z.n;
    const double rel_rms = z.rel_rms;
    // (Not on scene domains: their outputs sum several lights, so a sample cut would split fragments.)
    if (o.limb_check && !z.problem.full().domain().grouped() && !(sp.free_c.empty() && sp.free_i.empty()) && rel_rms > 1e-9) {
        LimbCheck& lc = r.limb;
        lc.cos_min = o.limb_cos;
        Problem* gp = nullptr;
        try {
            gp = &z.problem.grazing(o.limb_cos);
        } catch (const Error&) {
            gp = nullptr;   // (almost) every sample is grazing: no refit
        }
        if (gp) {
            Problem& g = *gp;
            std::vector<bool> kept(n, false);
            for (std::size_t i : z.problem.grazing_indices()) kept[i] = true;
            double ssr_g = 0.0;
            std::size_t n_g = 0;
            for (std::size_t i = 0; i < n; ++i)
                if (!kept[i]) {
                    const double d = best.a * fbest[i] - t[i];
                    ssr_g += d * d;
                    ++n_g;
                }
            lc.sample_share = double(n_g) / double(n);
            lc.error_share = best.ssr > 0.0 ? ssr_g / best.ssr : 0.0;
            // The verdict needs both: the grazing samples over 3x their share AND the refit moving. Below that
            // share the fit is not limb-driven whatever the refit would say, so it is not run (fit --all spends
            // most of its kernel time on refits otherwise).
            if (g.full().size() >= 64 && lc.error_share <= 3.0 * lc.sample_share) {
                lc.done = true;
            } else if (g.full().size() >= 64) {
                FitOptions og = o;
                og.limb_check = false;
                Point start{best.x, best.a, std::numeric_limits<double>::infinity()};
                const Point pg = search(g, shape, sp, base, og, &start, true);
                lc.done = true;
                lc.refitted = true;
                lc.params = pg.x;
                lc.albedo = pg.a * shape.albedo.x;
                const double ttg = sum_sq(g.target().data(), g.full().size());
                lc.rel_rms = ttg > 0.0 ? std::sqrt(pg.ssr / ttg) : 0.0;
                for (std::size_t j : sp.free_c)
                    lc.max_shift = std::max(lc.max_shift, std::abs(pg.x[j] - best.x[j]) / (info.params[j].hi - info.params[j].lo));
                for (std::size_t j : sp.free_i) lc.max_shift = std::max(lc.max_shift, pg.x[j] != best.x[j] ? 1.0 : 0.0);
                lc.sensitive = lc.error_share > 3.0 * lc.sample_share && lc.max_shift > 1e-3;
                if (lc.sensitive) {
                    std::string moved;
                    for (std::size_t j : sp.free_c)
                        moved += (moved.empty() ? "" : ", ") + info.params[j].name + " = " + num(pg.x[j], 5) +
                                 " instead of " + num(best.x[j], 5);
                    say(r, "limb", "near-grazing samples drive the fit (limb sensitivity, as Minnaert's singularity at NoL, "
                                "NoV -> 0): the " + pct(lc.sample_share) + " of samples with NoL or NoV < " +
                                    num(o.limb_cos) + " carry " + pct(lc.error_share) +
                                    " of the squared error, and refitted over NoL, NoV >= " + num(o.limb_cos) + " " +
                                    moved);
                }
            }
        }
    }
}

}  // namespace

FitResult fit_model(Problem& problem, const ModelShape& shape, const std::map<std::string, double>& fixed,
                    const FitOptions& o) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    const ModelInfo& info = find_model(shape.model);
    Evaluator& full = problem.full();
    const std::size_t n = full.domain().outputs();
    const std::size_t k0 = problem.kernel_evaluations(), r0 = problem.reference_evaluations();
    const std::vector<double>& t = problem.target();
    const double tt = sum_sq(t.data(), n);

    // Parameters: fixed ones at their value, the rest free; the start at the defaults.
    Space sp;
    sp.info = &info;
    std::vector<double> base;
    for (const auto& [name, v] : fixed) {
        bool known = false;
        for (const auto& p : info.params) known = known || p.name == name;
        if (!known) throw Error("model '" + info.name + "' has no parameter '" + name + "' to hold fixed");
    }
    for (std::size_t j = 0; j < info.params.size(); ++j) {
        const ParamSpec& p = info.params[j];
        sp.axes.emplace_back(p);
        auto it = fixed.find(p.name);
        if (it == fixed.end() && !(p.hi > p.lo)) {   // a range of one value: nothing to fit
            base.push_back(p.lo);
            continue;
        }
        if (it != fixed.end()) {
            const double v = it->second;
            if (!std::isfinite(v) || v < p.lo || v > p.hi || (p.integer && v != std::floor(v)))
                throw Error("fixed parameter '" + p.name + "' of model '" + info.name + "' is " + num(v) +
                            ": allowed range is [" + num(p.lo) + ", " + num(p.hi) + "]");
            base.push_back(v);
        } else {
            base.push_back(p.def);
            (p.integer ? sp.free_i : sp.free_c).push_back(j);
        }
    }
    Point best = search(problem, shape, sp, base, o, nullptr);
    const std::vector<double> fbest = reference_values(full, shape)({best.x})[0];

    FitResult r;
    r.model = info.name;
    r.target = problem.target_name();
    if (r.target == problem.target_material().model) r.target_params = problem.target_material().params;
    r.domain = full.domain().name;
    r.domain_description = full.domain().description;
    r.samples = full.size();
    r.scale = best.a;
    r.albedo = best.a * shape.albedo.x;
    for (std::size_t j = 0; j < info.params.size(); ++j) {
        FittedParam fp;
        fp.name = info.params[j].name;
        fp.value = best.x[j];
        fp.lo = info.params[j].lo;
        fp.hi = info.params[j].hi;
        fp.integer = info.params[j].integer;
        fp.fixed = fixed.count(fp.name) > 0;
        r.params.push_back(fp);
    }
    const Optimum z{problem, shape, info, sp, base, best, fbest, t, n, tt, tt > 0.0 ? std::sqrt(best.ssr / tt) : 0.0};
    measure_errors(z, r);
    const Sensitivity sens = sensitivity(z, r);
    diagnose(z, sens, o, r);
    limb_check(z, o, r);
    for (const auto& d : r.diagnostics)
        if (d.ill_posed) r.well_posed = false;
    r.kernel_evaluations = problem.kernel_evaluations() - k0;
    r.reference_evaluations = problem.reference_evaluations() - r0;
    r.seconds = std::chrono::duration<double>(clock::now() - t0).count();
    return r;
}

}  // namespace shadelab::fit
