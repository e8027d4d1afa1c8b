#include "core/spline.hpp"

#include <algorithm>

#include "core/error.hpp"

namespace shadelab {

NaturalSpline::NaturalSpline(std::vector<double> x, std::vector<double> y) : x_(std::move(x)), y_(std::move(y)) {
    const std::size_t n = x_.size();
    if (n < 2 || y_.size() != n) throw Error("internal: a spline needs two or more (x, y) pairs");
    // Second derivatives M_k of the natural spline: M_0 = M_{n-1} = 0 and, for 0 < k < n-1,
    //   h_{k-1} M_{k-1} + 2 (h_{k-1} + h_k) M_k + h_k M_{k+1} = 6 (d_k - d_{k-1}),  d_k = (y_{k+1} - y_k) / h_k,
    // solved by the tridiagonal (Thomas) algorithm.
    y2_.assign(n, 0.0);
    if (n < 3) return;
    std::vector<double> c(n, 0.0), r(n, 0.0);
    for (std::size_t k = 1; k + 1 < n; ++k) {
        const double h0 = x_[k] - x_[k - 1], h1 = x_[k + 1] - x_[k];
        const double rhs = 6.0 * ((y_[k + 1] - y_[k]) / h1 - (y_[k] - y_[k - 1]) / h0);
        const double diag = 2.0 * (h0 + h1) - h0 * c[k - 1];
        c[k] = h1 / diag;
        r[k] = (rhs - h0 * r[k - 1]) / diag;
    }
    for (std::size_t k = n - 2; k >= 1; --k) y2_[k] = r[k] - c[k] * y2_[k + 1];
}

double NaturalSpline::operator()(double x) const {
    // The interval [x_k, x_{k+1}] holding x; the first or last interval beyond the ends (its cubic continued).
    const std::size_t n = x_.size();
    std::size_t k = std::size_t(std::upper_bound(x_.begin(), x_.end(), x) - x_.begin());
    k = std::clamp<std::size_t>(k, 1, n - 1) - 1;
    const double h = x_[k + 1] - x_[k], a = (x_[k + 1] - x) / h, b = (x - x_[k]) / h;
    return a * y_[k] + b * y_[k + 1] + ((a * a * a - a) * y2_[k] + (b * b * b - b) * y2_[k + 1]) * h * h / 6.0;
}

// operator()'s form expanded in t = x - x_k (a = 1 - t/h, b = t/h):
//   y_k + t ((y_{k+1} - y_k)/h - h (2 M_k + M_{k+1})/6) + t^2 M_k / 2 + t^3 (M_{k+1} - M_k) / (6 h).
std::array<double, 4> NaturalSpline::local_cubic(std::size_t k) const {
    if (k + 1 >= x_.size()) throw Error("internal: spline interval " + std::to_string(k) + " does not exist");
    const double h = x_[k + 1] - x_[k];
    return {y_[k], (y_[k + 1] - y_[k]) / h - h * (2.0 * y2_[k] + y2_[k + 1]) / 6.0, 0.5 * y2_[k],
            (y2_[k + 1] - y2_[k]) / (6.0 * h)};
}

}  // namespace shadelab
