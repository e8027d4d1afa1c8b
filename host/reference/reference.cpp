#include "reference/reference.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace shadelab::ref {

// Every registered family's references (host/reference/<family>_ref.cpp), from the list the build writes from
// host/models/ (cmake/model_families.cmake): a family without its reference file does not link.
#define SL_FAMILY(name) void add_##name##_references(Table& t);
#include "model_families.inc"
#undef SL_FAMILY

namespace {
const Table& table() {
    static const Table t = [] {
        Table x;
#define SL_FAMILY(name) add_##name##_references(x);
#include "model_families.inc"
#undef SL_FAMILY
        return x;
    }();
    return t;
}
}  // namespace

const ModelFn& reference_for(const std::string& model) {
    auto it = table().vectors.find(model);
    if (it == table().vectors.end()) throw Error("model '" + model + "' has no double-precision reference");
    return it->second;
}

const AngleFn* angle_reference_for(const std::string& model) {
    auto it = table().angles.find(model);
    return it == table().angles.end() ? nullptr : &it->second;
}

std::vector<std::string> models_with_reference() {
    std::vector<std::string> v;
    for (const auto& [k, _] : table().vectors) v.push_back(k);
    return v;
}

dvec3 eval_material(const dvec3& N, const dvec3& L, const dvec3& V, const dvec3& P, const Material& m) {
    return reference_for(m.model)(N, L, V, P, m);
}

// Point-light falloff: inverse square, optionally windowed by (1 - (d/range)^4)^2 clamped at 0
// (Karis 2013, "Real Shading in Unreal Engine 4"), which reaches exactly 0 at d = range.
static double point_attenuation(double d2, double range) {
    double window = 1.0;
    if (range > 0.0) {
        const double q = d2 / (range * range);
        window = std::clamp(1.0 - q * q, 0.0, 1.0);
        window *= window;
    }
    return window / d2;
}

double light_incident(const Light& li, const dvec3& P, dvec3& L) {
    if (li.type == Light::Type::Directional) {
        L = glm::normalize(li.vec);
        return 1.0;
    }
    const dvec3 d = li.vec - P;
    const double d2 = std::max(glm::dot(d, d), 1e-12);
    L = d / std::sqrt(d2);
    return point_attenuation(d2, li.range);
}

dvec3 shade_point(const dvec3& P, const dvec3& N, const dvec3& V, const Material& m,
                  const std::vector<Light>& lights, const dvec3& ambient) {
    dvec3 sum = ambient * m.albedo;
    for (const Light& li : lights) {
        dvec3 L;
        const double atten = light_incident(li, P, L);
        sum += li.colour * li.intensity * atten * eval_material(N, L, V, P, m);
    }
    return sum;
}

}  // namespace shadelab::ref
