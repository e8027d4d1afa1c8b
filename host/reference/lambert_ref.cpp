// Lambert reference (Lambert 1760): value = albedo * max(0, N.L).
#include <algorithm>

#include "reference/reference.hpp"

namespace shadelab::ref {

static double Fd_Lambert_cos(double NoL) { return std::max(NoL, 0.0); }

void add_lambert_references(Table& t) {
    t["lambert"] = [](const dvec3& N, const dvec3& L, const dvec3&, const dvec3&, const Material& m) {
        return m.albedo * Fd_Lambert_cos(glm::dot(N, L));
    };
}

}  // namespace shadelab::ref
