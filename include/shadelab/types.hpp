// shadelab's public value types: plain structs with no dependency beyond the C++17 standard library.
#pragma once
#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace shadelab::api {

using Vec3 = std::array<double, 3>;
using Params = std::map<std::string, double>;   // model parameter name -> value ('shadelab models NAME')

// A surface: a catalogue model, its parameters (missing ones take their defaults), colours (linear RGB).
struct Material {
    std::string model = "lambert";
    Params params;
    Vec3 albedo{0.8, 0.8, 0.8};
    Vec3 specular{1.0, 1.0, 1.0};
};

// A light: directional (vec = direction TO the light) or point (vec = position, inverse-square falloff,
// windowed to zero at `range` when range > 0).
struct Light {
    bool point = false;
    Vec3 vec{1.0, 1.0, 1.0};
    Vec3 colour{1.0, 1.0, 1.0};
    double intensity = 1.0;
    double range = 0.0;
};

// A float image in memory: linear values, row-major, row 0 at the top, `channels` interleaved
// (renders are RGBA with alpha = coverage).
struct Image {
    int width = 0;
    int height = 0;
    int channels = 4;
    std::vector<float> pixels;
};

// One parameter of a model, as the catalogue declares it.
struct ParamInfo {
    std::string name;
    double def = 0.0, min = 0.0, max = 1.0;
    bool integer = false;
    std::string doc;
};

struct ModelInfo {
    std::string name, family, summary, source;
    std::vector<ParamInfo> params;
};

}  // namespace shadelab::api
