#include "photometry/fit.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "core/error.hpp"
#include "core/format.hpp"
#include "core/lm.hpp"
#include "models/catalogue.hpp"
#include "shade/shader.hpp"

namespace shadelab::photometry {

namespace {

using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point t0) {
    return std::chrono::duration<double>(clock_type::now() - t0).count();
}

std::size_t round_up(std::size_t n, std::size_t m) { return (n + m - 1) / m * m; }

// The laws `photometry fit` knows, by catalogue name, with ISIS's names beside them.
const std::vector<std::pair<const char*, const char*>>& fit_laws() {
    static const std::vector<std::pair<const char*, const char*>> v = {
        {"lambert", "Lambert"},           {"lommel_seeliger", "LommelSeeliger"}, {"lunar_lambert", "LunarLambert"},
        {"lunar_lambert_mcewen", ""},     {"minnaert_1941", "Minnaert"},         {"hapke_hen", "HapkeHen"},
        {"hapke_leg", "HapkeLeg"},        {"hapke_2012", ""},
    };
    return v;
}

// ---- the law on many parameter sets: one upload of the rows, one launch per batch of sets ----------------

class SetEvaluator {
public:
    SetEvaluator(Runtime& rt, const Material& base, const std::vector<Geometry>& rows, Precision precision)
        : rt_(rt), n_(rows.size()), padded_(round_up(rows.size(), kLocal)) {
        law_.material = base;
        const PhoArrays p = pho_arrays(law_, rows, 0, n_, padded_);
        try {
            prog_ = rt.build("photometry.cl", pho_defines(law_, precision, false, rt.vector_width()), Shader::options_for(precision));
            for (const auto* v : {&p.mu0, &p.mu, &p.sin_i, &p.sin_e, &p.cos_g, &p.tan_half_g, &p.tan_half_psi})
                rows_.emplace_back(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v->size() * sizeof(float),
                                   const_cast<float*>(v->data()));
        } catch (const cl::Error& e) {
            rethrow_cl(e, "photometric fit (upload)");
        }
    }

    // values[s][k]: the law with the parameters sets[s] (on top of the base material) at row k.
    std::vector<std::vector<float>> run(const std::vector<std::map<std::string, double>>& sets) {
        std::vector<std::vector<float>> out;
        for (std::size_t first = 0; first < sets.size(); first += kMaxSets) {
            const std::size_t ns = std::min(kMaxSets, sets.size() - first);
            std::vector<ModelConsts> consts;
            for (std::size_t s = 0; s < ns; ++s) {
                Material m = law_.material;
                for (const auto& [k, v] : sets[first + s]) m.params[k] = v;
                const std::vector<ModelConsts> c = pack_material(resolve_material(m));
                if (c.size() != 1) throw Error("internal: photometric fits take models without children");
                consts.push_back(c[0]);
            }
            const auto t0 = clock_type::now();
            try {
                cl::Buffer bc(rt_.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, consts.size() * sizeof(ModelConsts),
                              consts.data());
                cl::Buffer bo(rt_.context(), CL_MEM_WRITE_ONLY, ns * padded_ * sizeof(float));
                cl::Kernel k(prog_, "eval_photometric_sets");
                for (cl_uint i = 0; i < 7; ++i) k.setArg(i, rows_[i]);
                k.setArg(7, bo);
                k.setArg(8, cl_uint(padded_));
                k.setArg(9, bc);
                enqueue_rows(rt_, k, law_, padded_, kLocal, ns);
                std::vector<float> flat(ns * padded_);
                rt_.queue().enqueueReadBuffer(bo, CL_TRUE, 0, flat.size() * sizeof(float), flat.data());
                for (std::size_t s = 0; s < ns; ++s)
                    out.emplace_back(flat.begin() + std::ptrdiff_t(s * padded_), flat.begin() + std::ptrdiff_t(s * padded_ + n_));
            } catch (const cl::Error& e) {
                rethrow_cl(e, "photometric fit (evaluation)");
            }
            seconds += seconds_since(t0);
            evaluations += ns * n_;
        }
        return out;
    }

    std::size_t evaluations = 0;
    double seconds = 0.0;

private:
    static constexpr std::size_t kLocal = 256, kMaxSets = 32;
    Runtime& rt_;
    Law law_;   // the base material's law: the program's defines and its rows a work-item
    std::size_t n_, padded_;
    cl::Program prog_;
    std::vector<cl::Buffer> rows_;
};

// ---- small dense linear algebra (k <= a few tens) --------------------------------------------------------

// Eigen-decomposition of a symmetric matrix by cyclic Jacobi rotations (Golub & Van Loan 8.5): A = V diag(w) V^T,
// the eigenvectors in V's columns.
void symmetric_eigen(std::vector<double> A, std::size_t n, std::vector<double>& w, std::vector<double>& V) {
    V.assign(n * n, 0.0);
    for (std::size_t i = 0; i < n; ++i) V[i * n + i] = 1.0;
    for (int sweep = 0; sweep < 100; ++sweep) {
        double off = 0.0, diag = 0.0;
        for (std::size_t p = 0; p < n; ++p)
            for (std::size_t q = 0; q < n; ++q) (p == q ? diag : off) += A[p * n + q] * A[p * n + q];
        if (off <= 1e-30 * diag) break;
        for (std::size_t p = 0; p < n; ++p)
            for (std::size_t q = p + 1; q < n; ++q) {
                if (A[p * n + q] == 0.0) continue;
                const double theta = (A[q * n + q] - A[p * n + p]) / (2.0 * A[p * n + q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (std::size_t k = 0; k < n; ++k) {   // A <- A J (columns p, q)
                    const double akp = A[k * n + p], akq = A[k * n + q];
                    A[k * n + p] = c * akp - s * akq;
                    A[k * n + q] = s * akp + c * akq;
                }
                for (std::size_t k = 0; k < n; ++k) {   // A <- J^T A (rows p, q)
                    const double apk = A[p * n + k], aqk = A[q * n + k];
                    A[p * n + k] = c * apk - s * aqk;
                    A[q * n + k] = s * apk + c * aqk;
                }
                for (std::size_t k = 0; k < n; ++k) {
                    const double vkp = V[k * n + p], vkq = V[k * n + q];
                    V[k * n + p] = c * vkp - s * vkq;
                    V[k * n + q] = s * vkp + c * vkq;
                }
            }
    }
    w.resize(n);
    for (std::size_t i = 0; i < n; ++i) w[i] = A[i * n + i];
}

// ---- the fit ----------------------------------------------------------------------------------------------

struct Problem {
    const FitData& data;
    std::string model;
    bool brightness;
    std::vector<std::string> shape;          // free model parameters
    std::vector<double> lo, hi;              // bounds of all k fitted numbers (shape, then brightnesses)
    std::map<std::string, double> fixed;     // every model parameter not fitted
    std::size_t k() const { return lo.size(); }
};

std::map<std::string, double> shape_set(const Problem& P, const std::vector<double>& x) {
    std::map<std::string, double> s = P.fixed;
    for (std::size_t j = 0; j < P.shape.size(); ++j) s[P.shape[j]] = x[j];
    return s;
}

// model_k = B_{image(k)} u_k (shape laws) or u_k (Hapke).
double model_value(const Problem& P, const std::vector<double>& x, const std::vector<float>& u, std::size_t k) {
    return P.brightness ? x[P.shape.size() + std::size_t(P.data.image[k])] * double(u[k]) : double(u[k]);
}

double rss_of(const Problem& P, const std::vector<double>& x, const std::vector<float>& u) {
    double s = 0.0;
    for (std::size_t k = 0; k < u.size(); ++k) {
        const double r = P.data.value[k] - model_value(P, x, u, k);
        s += r * r;
    }
    return s;
}

// The finite-difference step of a shape parameter: 1e-3 of its size or of 1% of its range, whichever is larger.
double fd_step(double v, double lo, double hi) { return 1e-3 * std::max(std::abs(v), 0.01 * (hi - lo)); }

// The central-difference points of every shape parameter, clamped into the box.
std::vector<std::map<std::string, double>> jacobian_sets(const Problem& P, const std::vector<double>& x,
                                                         std::vector<double>& xp, std::vector<double>& xm) {
    std::vector<std::map<std::string, double>> sets = {shape_set(P, x)};
    xp.assign(P.shape.size(), 0.0);
    xm.assign(P.shape.size(), 0.0);
    for (std::size_t j = 0; j < P.shape.size(); ++j) {
        const double h = fd_step(x[j], P.lo[j], P.hi[j]);
        xp[j] = std::min(x[j] + h, P.hi[j]);
        xm[j] = std::max(x[j] - h, P.lo[j]);
        for (double v : {xp[j], xm[j]}) {
            std::vector<double> y = x;
            y[j] = v;
            sets.push_back(shape_set(P, y));
        }
    }
    return sets;
}

// J^T J and J^T r at x, from the launch of jacobian_sets (values[0] at x, then +- per shape parameter).
void normal_equations(const Problem& P, const std::vector<double>& x, const std::vector<std::vector<float>>& values,
                      const std::vector<double>& xp, const std::vector<double>& xm, std::vector<double>& A,
                      std::vector<double>& g) {
    const std::size_t k = P.k(), ns = P.shape.size(), n = P.data.value.size();
    A.assign(k * k, 0.0);
    g.assign(k, 0.0);
    std::vector<double> row(k);
    std::vector<std::size_t> nz;
    for (std::size_t i = 0; i < n; ++i) {
        const double B = P.brightness ? x[ns + std::size_t(P.data.image[i])] : 1.0;
        nz.clear();
        for (std::size_t j = 0; j < ns; ++j) {
            row[j] = B * (double(values[1 + 2 * j][i]) - double(values[2 + 2 * j][i])) / (xp[j] - xm[j]);
            nz.push_back(j);
        }
        if (P.brightness) {
            const std::size_t m = ns + std::size_t(P.data.image[i]);
            row[m] = double(values[0][i]);
            nz.push_back(m);
        }
        const double r = P.data.value[i] - model_value(P, x, values[0], i);
        for (std::size_t a : nz) {
            g[a] += row[a] * r;
            for (std::size_t b : nz) A[a * k + b] += row[a] * row[b];
        }
    }
}

bool on_bound(double v, double lo, double hi) { return v <= lo || v >= hi; }

// Standard errors, correlations and the directions the data do not determine, at the converged x.
void uncertainties(const Problem& P, FitResult& r, const std::vector<double>& A) {
    const std::size_t k = P.k();
    const std::size_t dof = r.samples > k ? r.samples - k : 1;
    const double s2 = r.rss / double(dof);
    std::vector<std::size_t> idx;   // free and off the bounds
    for (std::size_t j = 0; j < k; ++j) {
        if (r.params[j].at_bound) continue;
        if (!(A[j * k + j] > 0.0)) {
            r.params[j].stderr_ = -1.0;
            r.notes.push_back(r.params[j].name + " does not change the law at these pixels: it is not determined");
            continue;
        }
        idx.push_back(j);
    }
    r.correlation.assign(k * k, 0.0);
    for (std::size_t j = 0; j < k; ++j) r.correlation[j * k + j] = 1.0;
    const std::size_t m = idx.size();
    if (m == 0) return;
    std::vector<double> D(m), M(m * m);
    for (std::size_t a = 0; a < m; ++a) D[a] = std::sqrt(A[idx[a] * k + idx[a]]);
    for (std::size_t a = 0; a < m; ++a)
        for (std::size_t b = 0; b < m; ++b) M[a * m + b] = A[idx[a] * k + idx[b]] / (D[a] * D[b]);
    std::vector<double> w, V;
    symmetric_eigen(M, m, w, V);
    const double wmax = *std::max_element(w.begin(), w.end());
    r.conditioning = wmax > 0.0 ? std::max(0.0, *std::min_element(w.begin(), w.end())) / wmax : 0.0;
    std::vector<double> Minv(m * m, 0.0);
    std::vector<char> undetermined(m, 0);
    for (std::size_t e = 0; e < m; ++e) {
        if (w[e] > 1e-6 * wmax) {
            for (std::size_t a = 0; a < m; ++a)
                for (std::size_t b = 0; b < m; ++b) Minv[a * m + b] += V[a * m + e] * V[b * m + e] / w[e];
            continue;
        }
        // a direction the data do not determine: the parameters that make it up
        std::string names;
        for (std::size_t a = 0; a < m; ++a)
            if (std::abs(V[a * m + e]) > 0.1) {
                undetermined[a] = 1;
                names += (names.empty() ? "" : ", ") + r.params[idx[a]].name;
            }
        r.notes.push_back("not separately identifiable from these pixels: " + names +
                          " (they trade off against each other: fix some with -p or add phases)");
    }
    for (std::size_t a = 0; a < m; ++a) {
        FitParameter& p = r.params[idx[a]];
        p.stderr_ = undetermined[a] ? -1.0 : std::sqrt(std::max(0.0, s2 * Minv[a * m + a])) / D[a];
    }
    for (std::size_t a = 0; a < m; ++a)
        for (std::size_t b = 0; b < m; ++b) {
            if (a == b || undetermined[a] || undetermined[b]) continue;
            const double c = Minv[a * m + b] / std::sqrt(Minv[a * m + a] * Minv[b * m + b]);
            r.correlation[idx[a] * k + idx[b]] = std::isfinite(c) ? std::clamp(c, -1.0, 1.0) : 0.0;
            if (a < b && std::abs(c) > 0.99)
                r.notes.push_back(r.params[idx[a]].name + " and " + r.params[idx[b]].name + " are correlated by " +
                                  num(c, 4) + ": each is determined only given the other");
        }
}

// N ln(RSS/N) with RSS/N floored at (1e-7 mean|y|)^2 (float rounding of the kernels).
double log_likelihood_term(const FitData& d, double rss) {
    double mean = 0.0;
    for (double v : d.value) mean += std::abs(v);
    mean /= double(d.value.size());
    const double n = double(d.value.size());
    const double floor = std::max(1e-7 * mean, 1e-30);
    return n * std::log(std::max(rss / n, floor * floor));
}

}  // namespace

// ---- names ----------------------------------------------------------------------------------------------

std::string fit_model_name(const std::string& name) {
    for (const auto& [cat, isis] : fit_laws())
        if (pvl::iequals(name, cat) || (*isis && pvl::iequals(name, isis))) return cat;
    if (pvl::iequals(name, "minnaert")) return "minnaert_1941";
    std::string known;
    for (const auto& [cat, isis] : fit_laws())
        known += (known.empty() ? "" : ", ") + std::string(cat) + (*isis ? std::string(" (") + isis + ")" : "");
    throw Error("photometry fit: the law '" + name + "' cannot be fitted: choose one of " + known);
}

bool fit_has_brightness(const std::string& model) { return model.rfind("hapke", 0) != 0; }

std::vector<std::string> default_free_parameters(const std::string& model) {
    if (model == "hapke_hen" || model == "hapke_2012") return {"wh", "b0", "hh", "theta", "hg1"};
    if (model == "hapke_leg") return {"wh", "b0", "hh", "theta", "bh", "ch"};
    std::vector<std::string> v;
    for (const auto& p : find_model(model).params) v.push_back(p.name);
    return v;
}

Law FitResult::law() const {
    std::map<std::string, double> p = fixed;
    const auto& spec = find_model(model).params;
    for (const auto& q : params)
        if (std::any_of(spec.begin(), spec.end(), [&](const ParamSpec& s) { return s.name == q.name; })) p[q.name] = q.value;
    return law_from_model(model, p);
}

// ---- fitting ----------------------------------------------------------------------------------------------

FitResult fit_law(Runtime& rt, const FitData& data, const FitSpec& spec, const FitOptions& o) {
    const auto t_start = clock_type::now();
    if (data.value.empty() || data.value.size() != data.geometry.size() || data.image.size() != data.value.size())
        throw Error("photometry fit: no pixels to fit (is the disc on the image, are the limits too tight?)");
    for (std::size_t k = 0; k < data.geometry.size(); ++k) {
        check_geometry(data.geometry[k], "pixel " + std::to_string(k + 1));
        if (!std::isfinite(data.value[k])) throw Error("photometry fit: pixel " + std::to_string(k + 1) + " is not finite");
    }
    Problem P{data, fit_model_name(spec.model), false, {}, {}, {}, {}};
    P.brightness = fit_has_brightness(P.model);
    const ModelInfo& info = find_model(P.model);
    P.shape = spec.free.empty() ? default_free_parameters(P.model) : spec.free;
    for (const auto& [name, v] : spec.start) {
        const auto it = std::find_if(info.params.begin(), info.params.end(), [&](const ParamSpec& s) { return s.name == name; });
        if (it == info.params.end())
            throw Error("photometry fit: " + P.model + " has no parameter '" + name + "' (-p " + name + "=...)");
        if (!(v >= it->lo && v <= it->hi))
            throw Error("photometry fit: -p " + name + "=" + num(v) + " is out of range for " + P.model + ": allowed " +
                        num(it->lo) + " <= " + name + " <= " + num(it->hi));
    }
    // Starting values: -p, else a start inside the box where the model's default would make a parameter inert
    // (Hapke's B0 = 0 leaves h without effect, and h = 0 leaves B0 without effect).
    const std::map<std::string, double> hapke_start = {{"wh", 0.3}, {"b0", 1.0}, {"hh", 0.1}, {"theta", 15.0}, {"hg1", 0.1}};
    std::vector<double> x;
    for (const auto& p : info.params) {
        double v = p.def;
        if (!fit_has_brightness(P.model) && hapke_start.count(p.name)) v = hapke_start.at(p.name);
        if (auto it = spec.start.find(p.name); it != spec.start.end()) v = it->second;
        P.fixed[p.name] = v;
    }
    for (std::size_t j = 0; j < P.shape.size(); ++j) {
        const auto it = std::find_if(info.params.begin(), info.params.end(),
                                     [&](const ParamSpec& s) { return s.name == P.shape[j]; });
        if (it == info.params.end()) {
            std::string names;
            for (const auto& p : info.params) names += (names.empty() ? "" : ", ") + p.name;
            throw Error("photometry fit: --free " + P.shape[j] + " is not a parameter of " + P.model + " (it has " +
                        (names.empty() ? std::string("none") : names) + ")");
        }
        if (std::count(P.shape.begin(), P.shape.end(), P.shape[j]) > 1)
            throw Error("photometry fit: --free names " + P.shape[j] + " twice");
        // hh = 0 switches the surge off (a step in the law): the fit keeps h >= 1e-4
        P.lo.push_back(it->name == "hh" ? std::max(it->lo, 1e-4) : it->lo);
        P.hi.push_back(it->hi);
        x.push_back(std::clamp(P.fixed[P.shape[j]], P.lo.back(), P.hi.back()));
        P.fixed.erase(P.shape[j]);
    }
    Material base;
    base.model = P.model;
    base.albedo = glm::dvec3(1.0);
    base.params = shape_set(P, x);
    SetEvaluator ev(rt, resolve_material(base), data.geometry, o.precision);
    if (P.brightness) {
        // brightnesses start at their least-squares values for the starting shape
        const std::vector<float> u = ev.run({shape_set(P, x)})[0];
        std::vector<double> yu(std::size_t(data.images), 0.0), uu(std::size_t(data.images), 0.0);
        for (std::size_t i = 0; i < u.size(); ++i) {
            yu[std::size_t(data.image[i])] += data.value[i] * u[i];
            uu[std::size_t(data.image[i])] += double(u[i]) * u[i];
        }
        for (int m = 0; m < data.images; ++m) {
            x.push_back(uu[std::size_t(m)] > 0.0 ? yu[std::size_t(m)] / uu[std::size_t(m)] : 0.0);
            P.lo.push_back(0.0);
            P.hi.push_back(1e6);
        }
    }
    const std::size_t k = P.k();
    if (data.value.size() <= k)
        throw Error("photometry fit: " + std::to_string(data.value.size()) + " pixels for " + std::to_string(k) +
                    " fitted numbers: give more pixels or fix parameters");

    FitResult r;
    r.model = P.model;
    r.samples = data.value.size();
    std::vector<double> xp, xm, A, g;
    auto values = ev.run(jacobian_sets(P, x, xp, xm));
    // Bounded Levenberg-Marquardt (core/lm.hpp): four damped steps evaluated in one launch (lambda / 10, lambda,
    // 10 lambda, 100 lambda), Marquardt's damping A_ii (1 + lambda).
    lm::Settings ls;
    ls.trials = [](double lambda) { return std::vector<double>{lambda / 10.0, lambda, lambda * 10.0, lambda * 100.0}; };
    ls.lambda_floor = 1e-9;
    ls.reject_factor = 1e3;
    ls.multiplicative = true;
    ls.hold_at_zero_gradient = true;
    ls.retry_next_iteration = true;
    ls.stop_at_zero_cost = true;
    ls.max_iterations = o.max_iterations;
    std::vector<std::vector<double>> trials, tried;
    std::vector<double> trss;
    lm::Callbacks cb;
    cb.normal = [&](lm::Normal& ne) {
        normal_equations(P, x, values, xp, xm, ne.A, ne.g);
        ne.x = x;
        ne.lo = P.lo;
        ne.hi = P.hi;
        ne.bounded.assign(k, true);
    };
    cb.propose = [&](const std::vector<double>& y) {
        trials.push_back(y);
        return true;
    };
    cb.evaluate = [&] {
        tried = std::move(trials);
        trials.clear();
        std::vector<std::map<std::string, double>> sets;
        for (const auto& y : tried) sets.push_back(shape_set(P, y));
        const auto tv = ev.run(sets);
        trss.assign(tried.size(), 0.0);
        for (std::size_t t = 0; t < tried.size(); ++t) trss[t] = rss_of(P, tried[t], tv[t]);
        return trss;
    };
    cb.accept = [&](std::size_t best) {
        x = tried[best];
        values = ev.run(jacobian_sets(P, x, xp, xm));
        return rss_of(P, x, values[0]);
    };
    cb.converged = [&](double before, double after) { return (before - after) / before < o.rtol; };
    const lm::Outcome lo = lm::minimise(ls, cb, rss_of(P, x, values[0]));
    r.iterations = lo.iterations;
    r.converged = lo.converged;
    const double rss = lo.cost;
    normal_equations(P, x, values, xp, xm, A, g);

    for (std::size_t j = 0; j < k; ++j) {
        FitParameter p;
        p.name = j < P.shape.size() ? P.shape[j] : "B" + std::to_string(j - P.shape.size() + 1);
        p.value = x[j];
        p.lo = P.lo[j];
        p.hi = P.hi[j];
        p.at_bound = on_bound(x[j], P.lo[j], P.hi[j]);
        if (p.at_bound) r.notes.push_back(p.name + " is on its bound " + num(x[j]) + " (allowed " + num(P.lo[j]) + " to " +
                                          num(P.hi[j]) + "): no standard error");
        r.params.push_back(p);
    }
    r.fixed = P.fixed;
    r.rss = rss;
    r.rms = std::sqrt(rss / double(r.samples));
    const double ll = log_likelihood_term(data, rss);
    r.aic = ll + 2.0 * double(k);
    r.bic = ll + double(k) * std::log(double(r.samples));
    uncertainties(P, r, A);
    r.evaluations = ev.evaluations;
    r.kernel_seconds = ev.seconds;
    r.seconds = seconds_since(t_start);
    return r;
}

std::vector<FitResult> rank_laws(Runtime& rt, const FitData& data, const std::vector<FitSpec>& specs, const FitOptions& o) {
    std::vector<FitResult> out;
    for (const auto& s : specs) out.push_back(fit_law(rt, data, s, o));
    std::stable_sort(out.begin(), out.end(), [](const FitResult& a, const FitResult& b) { return a.bic < b.bic; });
    return out;
}

// ---- reports ----------------------------------------------------------------------------------------------

std::string describe_fit(const FitResult& r) {
    std::ostringstream s;
    const std::size_t k = r.params.size();
    s << "law: " << r.model << ", " << k << " fitted numbers on " << r.samples << " pixels, " << r.iterations
      << " iterations, " << (r.converged ? "converged" : "NOT converged (raise --max-iterations)") << "\n";
    s << std::left << std::setw(10) << "parameter" << std::right << std::setw(16) << "value" << std::setw(16)
      << "std. error" << "\n";
    for (const auto& p : r.params) {
        s << std::left << std::setw(10) << p.name << std::right << std::setw(16) << num(p.value, 8) << std::setw(16)
          << (p.at_bound ? std::string("on bound") : p.stderr_ < 0.0 ? std::string("not determined") : num(p.stderr_, 3))
          << "\n";
    }
    for (const auto& [name, v] : r.fixed) s << std::left << std::setw(10) << name << std::right << std::setw(16) << num(v, 8)
                                            << std::setw(16) << "fixed" << "\n";
    if (k > 1) {
        s << "correlation:\n" << std::setw(10) << "";
        for (const auto& p : r.params) s << std::setw(9) << p.name;
        s << "\n";
        for (std::size_t a = 0; a < k; ++a) {
            s << std::left << std::setw(10) << r.params[a].name << std::right;
            for (std::size_t b = 0; b < k; ++b) s << std::setw(9) << fixed(r.correlation[a * k + b], 4);
            s << "\n";
        }
    }
    for (const auto& n : r.notes) s << "note: " << n << "\n";
    if (k > 1) s << "smallest / largest eigenvalue of the scaled J^T J: " << num(r.conditioning, 3) << " (below 1e-6: not determined)\n";
    s << "rss: " << num(r.rss) << ", rms: " << num(r.rms) << ", AIC: " << num(r.aic, 8) << ", BIC: " << num(r.bic, 8)
      << "\n";
    const double rate = r.kernel_seconds > 0.0 ? double(r.evaluations) / r.kernel_seconds : 0.0;
    s << "evaluations: " << r.evaluations << " in " << num(r.kernel_seconds, 3) << " s of launches ("
      << num(rate, 3) << " per second), fit " << num(r.seconds, 3) << " s\n";
    return s.str();
}

std::string describe_ranking(const std::vector<FitResult>& ranked) {
    std::ostringstream s;
    s << "ranking by BIC = N ln(RSS/N) + k ln N (lowest first; AIC = N ln(RSS/N) + 2k beside it):\n"
      << std::setw(5) << "rank" << std::setw(22) << "law" << std::setw(4) << "k" << std::setw(14) << "rms"
      << std::setw(16) << "AIC" << std::setw(16) << "BIC" << std::setw(14) << "dBIC" << "\n";
    for (std::size_t i = 0; i < ranked.size(); ++i) {
        const auto& r = ranked[i];
        s << std::setw(5) << i + 1 << std::setw(22) << r.model << std::setw(4) << r.params.size() << std::setw(14)
          << num(r.rms, 5) << std::setw(16) << num(r.aic, 8) << std::setw(16) << num(r.bic, 8) << std::setw(14)
          << num(r.bic - ranked[0].bic, 6) << "\n";
    }
    return s.str();
}

}  // namespace shadelab::photometry
