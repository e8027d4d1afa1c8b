// ISIS's interpolation of its empirical photometric tables (NumericalApproximation CubicClamped with both end
// derivatives 1e30, which is Numerical Recipes' signal for a natural end): the natural cubic spline through the
// points (second derivative 0 at both ends). Beyond the table the end interval's cubic is continued (ISIS evaluates
// with its Extrapolate option). Used in double by host/photometry/isis.cpp (ISIS's path), the empirical family's
// reference (host/reference/empirical_ref.cpp) and, as per-segment cubics, to fill the kernels' table buffer
// (host/models/empirical.cpp).
#pragma once
#include <array>
#include <cstddef>
#include <vector>

namespace shadelab {

class NaturalSpline {
public:
    NaturalSpline() = default;
    // x strictly increasing, at least 2 points (2 points: the straight line through them).
    NaturalSpline(std::vector<double> x, std::vector<double> y);
    double operator()(double x) const;
    bool empty() const { return x_.empty(); }
    std::size_t size() const { return x_.size(); }
    const std::vector<double>& knots() const { return x_; }
    // The cubic of interval k (between knots k and k+1) in t = x - x_k: {c0, c1, c2, c3}, value
    // c0 + t (c1 + t (c2 + t c3)). The same cubic as operator() on [x_k, x_{k+1}] and, for the first and last
    // interval, beyond the ends.
    std::array<double, 4> local_cubic(std::size_t k) const;

private:
    std::vector<double> x_, y_, y2_;
};

}  // namespace shadelab
