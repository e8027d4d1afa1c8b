#include "speed/pareto.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace shadelab::speed {

namespace {
// q dominates p: at least as fast, at least as accurate, strictly better in one (see pareto.hpp).
bool dominates(const ParetoPoint& q, const ParetoPoint& p) {
    return q.speed >= p.speed && q.error <= p.error && (q.speed > p.speed || q.error < p.error);
}
}  // namespace

std::vector<bool> pareto_front(const std::vector<ParetoPoint>& points) {
    for (std::size_t i = 0; i < points.size(); ++i)
        if (std::isnan(points[i].speed) || std::isnan(points[i].error))
            throw Error("internal: Pareto front of a point with a NaN speed or error (point " + std::to_string(i) + ")");
    std::vector<bool> on(points.size(), true);
    for (std::size_t i = 0; i < points.size(); ++i)
        for (std::size_t j = 0; j < points.size() && on[i]; ++j)
            if (j != i && dominates(points[j], points[i])) on[i] = false;
    return on;
}

std::vector<std::size_t> front_in_speed_order(const std::vector<ParetoPoint>& points, const std::vector<bool>& on_front) {
    std::vector<std::size_t> idx;
    for (std::size_t i = 0; i < points.size() && i < on_front.size(); ++i)
        if (on_front[i]) idx.push_back(i);
    std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return points[a].speed < points[b].speed; });
    return idx;
}

}  // namespace shadelab::speed
