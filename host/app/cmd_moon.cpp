// shadelab moon: lunar limb darkening - analytic curves, rendered discs, profiles, Minnaert fits, comparisons.
// The work is in host/moon/; each subcommand turns options into calls and prints results in its own file
// (cmd_moon_<subcommand>.cpp); this one holds what they share and adds them. docs/moon.md is the manual.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>

#include "app/cmd_moon.hpp"
#include "app/commands.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "core/log.hpp"
#include "image/fits.hpp"

namespace fs = std::filesystem;

namespace shadelab::app {

namespace moon_cli {

std::string stem_of(const std::string& path) {
    const fs::path p(path);
    return (p.parent_path() / p.stem()).string();
}

std::string png_for(const std::string& csv, const std::string& explicit_png, const std::string& suffix) {
    return explicit_png.empty() ? stem_of(csv) + suffix + ".png" : explicit_png;
}

glm::dvec2 parse_centre(const std::string& text) {
    double x = 0, y = 0;
    char c = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%lf%c%lf%c", &x, &c, &y, &extra) != 3 || c != ',' || !std::isfinite(x) ||
        !std::isfinite(y))
        throw Error("--centre expects x,y in pixels (pixel (i, j) is centred at (i + 0.5, j + 0.5)), got '" + text + "'");
    return {x, y};
}

std::map<std::string, double> parse_params(const std::vector<std::string>& ps) {
    std::map<std::string, double> out;
    for (const auto& p : ps) {
        const auto kv = parse_param(p);
        out[kv.first] = kv.second;
    }
    return out;
}

namespace {

template <typename T>
const T* pick(const std::vector<T>& v, std::size_t i, std::size_t n, const std::string& option) {
    if (v.empty()) return nullptr;
    if (v.size() == 1) return &v[0];
    if (v.size() != n)
        throw Error(option + " has " + std::to_string(v.size()) + " values for " + std::to_string(n) +
                    " images: give one value, or one per image");
    return &v[i];
}

double header_number(const std::map<std::string, std::string>& kw, const std::string& key, const std::string& image,
                     const std::string& option) {
    auto it = kw.find(key);
    if (it == kw.end())
        throw Error("image '" + image + "': give " + option + " (it is not in the image" +
                    (kw.empty() ? std::string(")") : std::string("'s FITS header)")));
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (it->second.empty() || *end != '\0' || !std::isfinite(v))
        throw Error("image '" + image + "': FITS keyword " + key + " = '" + it->second + "' is not a number");
    return v;
}

ImageGeometry resolve_geometry(const GeometryArgs& g, std::size_t i, std::size_t n, const std::string& image,
                               const std::map<std::string, std::string>& kw) {
    ImageGeometry out;
    auto value = [&](const std::vector<double>& v, const char* option, const char* key) {
        if (const double* p = pick(v, i, n, option)) return *p;
        out.from_header.push_back(std::string(key));
        return header_number(kw, key, image, option);
    };
    const double phase = value(g.phase, "--phase", "PHASE");
    const double pa = value(g.pa, "--pa", "POSANG");
    out.disc.radius = value(g.radius, "--radius", "RADIUS");
    if (const std::string* c = pick(g.centre, i, n, "--centre")) {
        const glm::dvec2 cc = parse_centre(*c);
        out.disc.cx = cc.x;
        out.disc.cy = cc.y;
    } else {
        out.disc.cx = header_number(kw, "CENTX", image, "--centre");
        out.disc.cy = header_number(kw, "CENTY", image, "--centre");
        out.from_header.push_back("CENTX/CENTY");
    }
    out.sun = sun_geometry(phase, pa);
    return out;
}

}  // namespace

LoadedImage load(const std::string& path, const GeometryArgs& g, std::size_t i, std::size_t n) {
    std::map<std::string, std::string> kw;
    LoadedImage li;
    li.img = read_any_image(path, &kw);
    li.geo = resolve_geometry(g, i, n, path, kw);
    check_disc(li.geo.disc, li.img.width, li.img.height, g.allow_partial);
    if (!li.geo.from_header.empty()) {
        shadelab::log_out() << "image " << path << ": from its FITS header:";
        for (const auto& k : li.geo.from_header) shadelab::log_out() << " " << k;
        shadelab::log_out() << "\n";
    }
    return li;
}

std::string geometry_text(const ImageGeometry& g) {
    return "phase " + num(g.sun.phase_deg) + " deg, pa " + num(g.sun.pa_deg) + " deg, centre (" + num(g.disc.cx) +
           ", " + num(g.disc.cy) + ") px, radius " + num(g.disc.radius) + " px";
}

std::string column_name(const PhotometricModel& m) {
    const NamedLaw* l = named_law(m.kind);
    if (!l) return "I_" + m.material.model;   // a catalogue model
    if (l->param == "k") return "I_" + l->name + "_k" + num(m.k);
    if (l->param == "l") return "I_" + l->name + "_L" + num(m.lunar_l);
    return "I_" + l->name;
}

}  // namespace moon_cli

void add_moon_command(CLI::App& app) {
    auto* moon = app.add_subcommand("moon", "Lunar limb darkening: analytic curves, rendered discs, profiles, "
                                            "Minnaert fits (docs/moon.md)");
    moon->require_subcommand(1);
    moon_cli::add_curve(moon);
    moon_cli::add_render(moon);
    for (bool compare : {false, true}) moon_cli::add_profile(moon, compare);
    moon_cli::add_fit(moon);
    moon_cli::add_geometry(moon);
}

}  // namespace shadelab::app
