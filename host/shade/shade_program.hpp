// The program Shader::shade builds for a material, its lights and a precision (cl/prebuild.hpp takes it).
#pragma once
#include <string>
#include <vector>

#include "cl/prebuild.hpp"
#include "models/material.hpp"
#include "shade/shader.hpp"

namespace shadelab {

// The lights' kinds as the shade kernels are built for them (kernels/shade_parts.cl, light_incident_v3):
// SL_POINT_LIGHTS and SL_RANGED_LIGHTS, bit l set when light l is a point light, and a point light with a range
// (> 0). The light loop is unrolled, so each light computes only its own kind's arithmetic. Part of what decides a
// program, with the light count and the precision, so what decides whether two jobs' kernels can share one
// (scene/batch.cpp, light_kinds). None for more than 64 lights (a scene has at most 64): the kinds are then read
// per light at run time.
std::vector<std::string> light_defines(const std::vector<Light>& lights);
// The same as a short text, a letter a light: 'd' directional, 'p' point, 'r' point with a range ("dpr").
std::string light_kinds(const std::vector<Light>& lights);
// True unless SHADELAB_LIGHT_KINDS=0 (how the choice is measured: the kinds are then read per light at run time,
// the way of programs built without the defines); any other value than 0 or 1 throws one line naming it.
bool light_kinds_in_programs();

// True for a perspective view (ShadeSetup::view with w != 0: a camera position), false for an orthographic one
// (w = 0: the direction to the viewer). The shade kernels are built for one kind (SL_PERSPECTIVE, kernels/
// shade_parts.cl), so it is part of what decides a program too.
bool is_perspective(const glm::dvec4& view);

// On a device of `device_width` lanes (Runtime::vector_width()), which decides the model's chains
// (Shader::chains_for), for a perspective view or an orthographic one (is_perspective).
ProgramRequest shade_program(const Material& resolved, const std::vector<Light>& lights, Precision precision,
                             std::size_t device_width, bool perspective);

}  // namespace shadelab
