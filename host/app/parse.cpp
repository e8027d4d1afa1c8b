#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "core/text.hpp"

namespace shadelab::app {

namespace {
double parse_number(const std::string& t, const std::string& what) {
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (t.empty() || *end != '\0' || !std::isfinite(v)) throw Error(what + ": '" + t + "' is not a finite number");
    return v;
}
}  // namespace

glm::dvec3 parse_vec3(const std::string& text, const std::string& option) {
    const auto parts = split(text, ',');
    if (parts.size() != 3) throw Error(option + " expects three comma-separated numbers x,y,z, got '" + text + "'");
    return {parse_number(parts[0], option), parse_number(parts[1], option), parse_number(parts[2], option)};
}

glm::dvec3 parse_vec3(const std::string& text, const std::string& option, double lo, double hi) {
    const glm::dvec3 v = parse_vec3(text, option);
    for (int c = 0; c < 3; ++c) in_range(v[c], option, lo, hi);
    return v;
}

double in_range(double v, const std::string& option, double lo, double hi) {
    if (!(v >= lo && v <= hi)) {
        std::ostringstream s;
        s << option << ": " << v << " is out of range: allowed [" << lo << ", " << hi << "] (the same as in scene files)";
        throw Error(s.str());
    }
    return v;
}

glm::dvec4 parse_vec4(const std::string& text, const std::string& option, double default_w) {
    const auto parts = split(text, ',');
    if (parts.size() == 3) return glm::dvec4(parse_vec3(text, option), default_w);
    if (parts.size() != 4) throw Error(option + " expects r,g,b or r,g,b,a, got '" + text + "'");
    return {parse_number(parts[0], option), parse_number(parts[1], option), parse_number(parts[2], option),
            parse_number(parts[3], option)};
}

Light parse_light(const std::string& text) {
    const std::string opt = "--light '" + text + "'";
    const auto parts = split(text, ':');
    if (parts.size() < 2) throw Error(opt + ": expected dir:x,y,z[:r,g,b[:intensity]] or point:x,y,z[:r,g,b[:intensity[:range]]]");
    Light l;
    if (parts[0] == "dir" || parts[0] == "directional") l.type = Light::Type::Directional;
    else if (parts[0] == "point") l.type = Light::Type::Point;
    else throw Error(opt + ": light type must be 'dir' or 'point', got '" + parts[0] + "'");
    // The ranges of scene files (host/scene/scene.cpp): beyond them float shading overflows to Inf or 0.
    l.vec = parse_vec3(parts[1], opt, -kMaxCoordinate, kMaxCoordinate);
    if (parts.size() > 2) l.colour = parse_vec3(parts[2], opt + " colour", 0.0, kMaxColour);
    if (parts.size() > 3) l.intensity = in_range(parse_number(parts[3], opt + " intensity"), opt + " intensity", 0.0, kMaxIntensity);
    if (parts.size() > 4) {
        if (l.type != Light::Type::Point) throw Error(opt + ": only point lights take a range");
        l.range = in_range(parse_number(parts[4], opt + " range"), opt + " range", 0.0, kMaxCoordinate);
    }
    if (parts.size() > 5) throw Error(opt + ": too many ':'-separated fields");
    if (l.type == Light::Type::Directional && glm::length(l.vec) == 0.0)
        throw Error(opt + ": a directional light needs a non-zero direction");
    if (l.intensity < 0 || l.range < 0) throw Error(opt + ": intensity and range must be >= 0");
    return l;
}

std::pair<std::string, double> parse_param(const std::string& text) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0) throw Error("--param expects name=value, got '" + text + "'");
    if (text.find(',', eq) != std::string::npos)
        throw Error("--param " + text.substr(0, eq) + ": '" + text.substr(eq + 1) +
                    "' is a list (a table), and this option takes one number per parameter");
    return {text.substr(0, eq), parse_number(text.substr(eq + 1), "--param " + text.substr(0, eq))};
}

void add_param(Material& m, const std::string& text) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0) throw Error("--param expects name=value or name=v1,v2,..., got '" + text + "'");
    const std::string name = text.substr(0, eq), value = text.substr(eq + 1);
    if (value.find(',') == std::string::npos) {
        m.params[name] = parse_number(value, "--param " + name);
        return;
    }
    std::vector<double> list;
    for (const auto& item : split(value, ','))
        list.push_back(parse_number(item, "--param " + name + " (entry " + std::to_string(list.size() + 1) + ")"));
    m.tables[name] = list;
}

}  // namespace shadelab::app
