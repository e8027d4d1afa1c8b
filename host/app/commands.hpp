// Each subcommand of the shadelab CLI adds itself to the app here (one file per command).
#pragma once
#include <string>

#include <CLI/CLI.hpp>
#include <glm/glm.hpp>

#include "models/material.hpp"

namespace shadelab::app {

void add_render_command(CLI::App& app);
void add_models_command(CLI::App& app);
void add_devices_command(CLI::App& app);
void add_moon_command(CLI::App& app);    // host/app/cmd_moon.cpp
void add_batch_command(CLI::App& app);   // host/app/cmd_batch.cpp
void add_compare_command(CLI::App& app); // host/app/cmd_compare.cpp
void add_plan_command(CLI::App& app);    // host/app/cmd_plan.cpp
void add_chart_command(CLI::App& app);   // host/app/cmd_chart.cpp
void add_view_command(CLI::App& app);    // host/app/cmd_view.cpp
void add_photometry_command(CLI::App& app);   // host/app/cmd_photometry.cpp

// A model name typed on the command line: throws shadelab::UsageError (exit 2) naming `option`, with the closest
// catalogue name as a hint, when it is unknown.
void require_model_name(const std::string& name, const std::string& option);
void add_fit_command(CLI::App& app);     // host/app/cmd_fit.cpp

// Small parsers shared by the commands; each throws shadelab::Error naming the option and the text.
glm::dvec3 parse_vec3(const std::string& text, const std::string& option);
// The same with every component in [lo, hi] (the error names the option, the value and the range).
glm::dvec3 parse_vec3(const std::string& text, const std::string& option, double lo, double hi);
double in_range(double value, const std::string& option, double lo, double hi);

// The ranges scene files allow (host/scene/scene.cpp), so the command line cannot ask for more: beyond them
// the float kernels overflow to Inf (refused when written) or to a silent 0.
constexpr double kMaxColour = 1e6;        // albedo, specular, light colour, ambient
constexpr double kMaxIntensity = 1e12;    // light intensity
constexpr double kMaxCoordinate = 1e30;   // positions, directions, ranges
glm::dvec4 parse_vec4(const std::string& text, const std::string& option, double default_w);
// "dir:x,y,z[:r,g,b[:intensity]]" or "point:x,y,z[:r,g,b[:intensity[:range]]]"
Light parse_light(const std::string& text);
// "name=value"
std::pair<std::string, double> parse_param(const std::string& text);
// "name=value", or "name=v1,v2,..." for a table-valued parameter (the empirical family's phase_list, k_list, ...):
// into m.params or m.tables (resolve_material checks both)
void add_param(Material& m, const std::string& text);

}  // namespace shadelab::app
