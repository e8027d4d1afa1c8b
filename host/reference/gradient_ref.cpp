// Gradient blend reference: t = (1 + cos(2 pi (P . g) / period + phase)) / 2, value = (1 - t) A + t B,
// with g normalised here from the user's (gx, gy, gz) and A, B the children's own references.
#include <cmath>

#include "core/error.hpp"
#include "reference/reference.hpp"

namespace shadelab::ref {

static double Gradient_Weight(const dvec3& P, const Material& m) {
    dvec3 g{m.params.at("gx"), m.params.at("gy"), m.params.at("gz")};
    const double len = std::hypot(g.x, g.y, g.z);   // C++17 three-argument hypot: no underflow for tiny g
    if (!(len > 0.0)) throw Error("model 'gradient': the gradient direction (gx, gy, gz) is zero");
    g /= len;
    return 0.5 + 0.5 * std::cos(2.0 * M_PI * glm::dot(P, g) / m.params.at("period") + m.params.at("phase"));
}

void add_gradient_references(Table& t) {
    t["gradient"] = [](const dvec3& N, const dvec3& L, const dvec3& V, const dvec3& P, const Material& m) {
        const double w = Gradient_Weight(P, m);
        return (1.0 - w) * eval_material(N, L, V, P, m.children[0]) + w * eval_material(N, L, V, P, m.children[1]);
    };
}

}  // namespace shadelab::ref
