// The bounded Levenberg-Marquardt loop (see lm.hpp).
#include "core/lm.hpp"

#include <algorithm>
#include <cmath>

namespace shadelab::lm {

namespace {

double largest_diagonal(const Normal& ne) {
    double m = 0.0;
    for (std::size_t c = 0; c < ne.k(); ++c) m = std::max(m, ne.A[c * ne.k() + c]);
    return m;
}

// The columns that move this step: a bounded coordinate on a bound whose descent direction points out of the box
// is held, and so is one without effect (no direction to move in).
std::vector<std::size_t> active_columns(const Settings& s, const Normal& ne, double maxd) {
    const std::size_t k = ne.k();
    std::vector<std::size_t> act;
    for (std::size_t c = 0; c < k; ++c) {
        if (ne.bounded[c]) {
            const double g = ne.g[c];
            const bool out = s.hold_at_zero_gradient ? (ne.x[c] <= ne.lo[c] && g <= 0.0) || (ne.x[c] >= ne.hi[c] && g >= 0.0)
                                                     : (ne.x[c] <= ne.lo[c] && g < 0.0) || (ne.x[c] >= ne.hi[c] && g > 0.0);
            if (out || !(ne.A[c * k + c] > s.min_diagonal * maxd)) continue;
        }
        act.push_back(c);
    }
    return act;
}

// The damped step on the active columns for damping `lam`: y = x + d, bounded coordinates clamped into the box.
// Returns false when the damped system is singular.
bool damped_step(const Settings& s, const Normal& ne, const std::vector<std::size_t>& act, double lam, double maxd,
                 std::vector<double>& y) {
    const std::size_t k = ne.k(), m = act.size();
    std::vector<double> A(m * m), b(m), d;
    for (std::size_t r1 = 0; r1 < m; ++r1) {
        for (std::size_t r2 = 0; r2 < m; ++r2) A[r1 * m + r2] = ne.A[act[r1] * k + act[r2]];
        if (s.multiplicative) A[r1 * m + r1] *= 1.0 + lam;
        else A[r1 * m + r1] += lam * ne.A[act[r1] * k + act[r1]] + s.ridge * maxd;
        b[r1] = ne.g[act[r1]];
    }
    if (!solve(A, b, m, d, s.solve_tiny)) return false;
    y = ne.x;
    for (std::size_t r = 0; r < m; ++r) {
        const std::size_t c = act[r];
        y[c] = ne.bounded[c] ? std::clamp(ne.x[c] + d[r], ne.lo[c], ne.hi[c]) : ne.x[c] + d[r];
    }
    return true;
}

}  // namespace

bool solve(std::vector<double> A, std::vector<double> b, std::size_t k, std::vector<double>& x, double tiny) {
    double scale = 0.0;
    for (std::size_t i = 0; i < k; ++i) scale = std::max(scale, std::abs(A[i * k + i]));
    if (!(scale > 0.0)) return false;
    for (std::size_t c = 0; c < k; ++c) {
        std::size_t p = c;
        for (std::size_t r = c + 1; r < k; ++r)
            if (std::abs(A[r * k + c]) > std::abs(A[p * k + c])) p = r;
        if (!(std::abs(A[p * k + c]) > tiny * scale)) return false;
        if (p != c) {
            for (std::size_t j = 0; j < k; ++j) std::swap(A[c * k + j], A[p * k + j]);
            std::swap(b[c], b[p]);
        }
        for (std::size_t r = c + 1; r < k; ++r) {
            const double f = A[r * k + c] / A[c * k + c];
            for (std::size_t j = c; j < k; ++j) A[r * k + j] -= f * A[c * k + j];
            b[r] -= f * b[c];
        }
    }
    x.assign(k, 0.0);
    for (std::size_t c = k; c-- > 0;) {
        double s = b[c];
        for (std::size_t j = c + 1; j < k; ++j) s -= A[c * k + j] * x[j];
        x[c] = s / A[c * k + c];
    }
    for (double v : x)
        if (!std::isfinite(v)) return false;
    return true;
}

Outcome minimise(const Settings& s, const Callbacks& cb, double cost) {
    Outcome out;
    out.cost = cost;
    double lambda = s.lambda;
    Normal ne;
    for (out.iterations = 0; out.iterations < s.max_iterations; ++out.iterations) {
        cb.normal(ne);
        const double maxd = largest_diagonal(ne);
        const std::vector<std::size_t> act = active_columns(s, ne, maxd);
        std::vector<std::size_t> stepped;
        for (std::size_t c : act)
            if (ne.bounded[c]) stepped.push_back(c);
        if (stepped.empty() || (s.stop_at_zero_cost && out.cost == 0.0)) {
            out.converged = true;
            return out;
        }
        bool accepted = false, exhausted = false;
        double step_size = 0.0;
        for (int attempt = 0; attempt < s.attempts && !accepted && !exhausted; ++attempt) {
            // One batch: a candidate per damping value (the current point where the damped system is singular,
            // which the caller may drop as the same point).
            const std::vector<double> lams = s.trials(lambda);
            std::vector<double> kept_lam;
            std::vector<std::vector<double>> kept_y;
            for (double lam : lams) {
                std::vector<double> y;
                const bool solved = damped_step(s, ne, act, lam, maxd, y);
                if (!solved) y = ne.x;
                if (cb.propose(y)) {
                    kept_lam.push_back(lam);
                    kept_y.push_back(std::move(y));
                }
            }
            if (kept_y.empty()) {   // every damped step lands on the current point: nothing moves it
                out.converged = true;
                return out;
            }
            const std::vector<double> costs = cb.evaluate();
            std::size_t best = 0;
            for (std::size_t q = 1; q < costs.size(); ++q)
                if (costs[q] < costs[best]) best = q;
            if (!(costs[best] < out.cost)) {
                lambda *= s.reject_factor;
                exhausted = lambda > s.lambda_ceiling;
                continue;
            }
            const double before = out.cost;
            step_size = 0.0;
            for (std::size_t c : stepped) step_size = std::max(step_size, std::abs(kept_y[best][c] - ne.x[c]));
            out.cost = cb.accept(best);
            lambda = std::max(s.lambda_floor, kept_lam[best] / s.accept_divisor);
            accepted = true;
            if (cb.converged && cb.converged(before, costs[best])) {
                out.converged = true;
                return out;
            }
        }
        if (exhausted) {   // no step lowers the cost: at the minimum to the evaluation's rounding
            out.converged = true;
            return out;
        }
        if (!accepted && !s.retry_next_iteration) return out;
        if (accepted && step_size < s.min_step) return out;
    }
    return out;
}

}  // namespace shadelab::lm
