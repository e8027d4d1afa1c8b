// shadelab moon geometry: the conventions figure (docs/moon.md).
#include <algorithm>
#include <cmath>
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
#include "moon/plot.hpp"

namespace fs = std::filesystem;

namespace shadelab::app::moon_cli {

namespace {

struct GeometryFigureArgs {
    double phase = 60.0, pa = 30.0, across_offset = 0.0;
    std::string output = "out/moon/geometry.png";
};

}  // namespace

void add_geometry(CLI::App* moon) {
    auto a = std::make_shared<GeometryFigureArgs>();
    auto* c = moon->add_subcommand("geometry", "Draw the conventions: disc, sun direction, position angle, "
                                               "terminator, equator -> PNG");
    c->add_option("--phase", a->phase, "Phase angle in degrees")->capture_default_str();
    c->add_option("--pa", a->pa, "Position angle in degrees")->capture_default_str();
    c->add_option("--across-offset", a->across_offset, "Across line offset (disc radii)")->capture_default_str();
    c->add_option("-o,--output", a->output, "PNG file")->capture_default_str();
    c->callback([a] {
        if (!std::isfinite(a->across_offset) || std::abs(a->across_offset) >= 1.0)
            throw Error("--across-offset must be strictly between -1 and 1");
        plot_geometry(a->output, sun_geometry(a->phase, a->pa), a->across_offset);
        std::cout << a->output << "\n";
    });
}

}  // namespace shadelab::app::moon_cli
