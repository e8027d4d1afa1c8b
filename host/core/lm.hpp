// Bounded Levenberg-Marquardt: the one damped least-squares loop of the project (host/fit/fit.cpp fits catalogue
// models to each other, host/photometry/fit.cpp fits photometric laws to images).
//
// Levenberg (1944), Marquardt (1963): at the point x with Jacobian J and residual r, the step d solves
//     (J^T J + lambda D) d = -J^T r
// with D the diagonal of J^T J (Marquardt's scaling, optionally plus a small ridge). A box lo <= x <= hi is kept
// by an active set (a coordinate on a bound whose descent direction leaves the box is held for the step) and
// by clamping the step into the box. Several damping values are tried per step and evaluated as one batch (the
// callers evaluate on the OpenCL device, where a batch costs about as much as one point); the lowest cost that
// beats the current one is taken, else the damping grows.
//
// The caller owns the point, the Jacobian and the evaluations; the loop calls back for the normal equations at the
// current point, proposes candidate coordinates, asks for their costs and tells which one to move to.
#pragma once
#include <cstddef>
#include <functional>
#include <limits>
#include <vector>

namespace shadelab::lm {

// The normal equations at the current point, k columns.
struct Normal {
    std::vector<double> A;         // J^T J, k x k, row-major
    std::vector<double> g;         // the descent direction -J^T r (r = model - data)
    std::vector<double> x;         // the current coordinates
    std::vector<double> lo, hi;    // their box
    std::vector<bool> bounded;     // per column: a coordinate of the point (stepped and clamped); false: a column
                                   // solved along with the others whose step the caller discards (a scale it
                                   // re-solves in closed form), never held
    std::size_t k() const { return g.size(); }
};

struct Settings {
    double lambda = 1e-3;                           // initial damping
    // The damping values tried per step, from the current lambda (e.g. lambda / 10, lambda, 10 lambda).
    std::function<std::vector<double>(double lambda)> trials;
    double accept_divisor = 1.0;                    // after a step with damping l: lambda = max(floor, l / this)
    double lambda_floor = 1e-12;
    double reject_factor = 10.0;                    // no trial lowered the cost: lambda *= this
    double lambda_ceiling = 1e12;                   // beyond it no step lowers the cost: converged
    bool multiplicative = false;                    // damping A_ii * (1 + l) instead of A_ii + l A_ii + ridge
    double ridge = 0.0;                             // (additive damping) + ridge * the largest diagonal entry
    double min_diagonal = 0.0;                      // a bounded column with A_jj <= this * largest diagonal is held
    bool hold_at_zero_gradient = false;             // a coordinate on a bound with zero descent is held too
    double solve_tiny = 0.0;                        // pivots below this * largest diagonal: singular
    int attempts = 1;                               // batches of trials per iteration before giving up on it
    bool retry_next_iteration = false;              // all attempts failed below the ceiling: go on (true) or stop
    bool stop_at_zero_cost = false;                 // a cost of exactly 0 is converged
    double min_step = 0.0;                          // an accepted step moving no coordinate more than this: stop
    int max_iterations = 100;
};

struct Callbacks {
    std::function<void(Normal&)> normal;                          // at the current point
    // A candidate at coordinates y (bounded ones clamped, the others as solved); false: not worth evaluating
    // (the same point). The caller keeps the accepted ones in order.
    std::function<bool(const std::vector<double>& y)> propose;
    std::function<std::vector<double>()> evaluate;                // costs of the kept candidates, then forgets them
    std::function<double(std::size_t)> accept;                    // move to kept candidate i; returns the new cost
    // After an accepted step from cost `before` to `after`: true stops the loop (converged).
    std::function<bool(double before, double after)> converged;
};

struct Outcome {
    int iterations = 0;     // completed iterations (the one that converged not counted, as a for-loop index)
    bool converged = false;
    double cost = std::numeric_limits<double>::infinity();
};

// Runs the loop from the caller's current point, whose cost is `cost`.
Outcome minimise(const Settings& settings, const Callbacks& callbacks, double cost);

// Solves A x = b (k x k, symmetric positive semi-definite) by Gaussian elimination with partial pivoting.
// Returns false when a pivot is not above tiny * max |diagonal| (singular to working precision) or the solution
// is not finite.
bool solve(std::vector<double> A, std::vector<double> b, std::size_t k, std::vector<double>& x, double tiny = 1e-14);

}  // namespace shadelab::lm
