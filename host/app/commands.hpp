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
glm::dvec4 parse_vec4(const std::string& text, const std::string& option, double default_w);
// "dir:x,y,z[:r,g,b[:intensity]]" or "point:x,y,z[:r,g,b[:intensity[:range]]]"
Light parse_light(const std::string& text);
// "name=value"
std::pair<std::string, double> parse_param(const std::string& text);

}  // namespace shadelab::app
