// What a surface is made of: a model from the catalogue, its parameters, colours, and (for models that
// blend others, such as gradient) its child materials.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace shadelab {

struct Material {
    std::string model = "lambert";
    std::map<std::string, double> params;   // by name; resolve_material() fills defaults and checks ranges
    // table-valued parameters by name (the empirical family's phase_list, k_list, ...), checked and filled the same
    std::map<std::string, std::vector<double>> tables;
    glm::dvec3 albedo{0.8, 0.8, 0.8};       // diffuse colour, linear
    glm::dvec3 specular{1.0, 1.0, 1.0};     // specular colour, linear
    std::vector<Material> children;         // sub-models (gradient: [A, B])
};

// A light as the user describes it.
struct Light {
    enum class Type { Directional, Point };
    Type type = Type::Directional;
    glm::dvec3 vec{0.0, 0.0, 1.0};   // directional: direction TO the light (any length > 0); point: position
    glm::dvec3 colour{1.0, 1.0, 1.0};
    double intensity = 1.0;
    double range = 0.0;              // point lights: 0 = unbounded inverse square; > 0 = windowed to 0 at range
};

}  // namespace shadelab
