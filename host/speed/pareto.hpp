// The Pareto front of speed against error: the configurations nothing else beats on both at once.
#pragma once
#include <vector>

namespace shadelab::speed {

struct ParetoPoint {
    double speed = 0.0;   // higher is better (fragments per second)
    double error = 0.0;   // lower is better
};

// on_front[i] is true when no other point dominates point i. Point q dominates p when q is at least as fast
// (q.speed >= p.speed), at least as accurate (q.error <= p.error) and strictly better in one of the two.
// Tie rule: two points equal in both speed and error do not dominate each other (both stay on the front);
// a point as fast as another but strictly more accurate does dominate it (and vice versa).
// Throws shadelab::Error on a NaN speed or error (Inf is allowed and compares as usual).
std::vector<bool> pareto_front(const std::vector<ParetoPoint>& points);

// The indices of the front members, ordered by speed (slowest first), the order the front line is drawn in.
std::vector<std::size_t> front_in_speed_order(const std::vector<ParetoPoint>& points, const std::vector<bool>& on_front);

}  // namespace shadelab::speed
