// The program Shader::shade builds for a material, its lights and a precision (cl/prebuild.hpp takes it).
#pragma once
#include <vector>

#include "cl/prebuild.hpp"
#include "models/material.hpp"
#include "shade/shader.hpp"

namespace shadelab {

// True when no light is a point light: the shade kernels are then built with SL_ALL_DIRECTIONAL=1, without the
// point-light arithmetic (kernels/shade_parts.cl). Part of what decides a program, with the light count and the
// precision, so what decides whether two jobs' kernels can share one (scene/batch.cpp).
bool all_lights_directional(const std::vector<Light>& lights);

// True for a perspective view (ShadeSetup::view with w != 0: a camera position), false for an orthographic one
// (w = 0: the direction to the viewer). The shade kernels are built for one kind (SL_PERSPECTIVE, kernels/
// shade_parts.cl), so it is part of what decides a program too.
bool is_perspective(const glm::dvec4& view);

// On a device of `device_width` lanes (Runtime::vector_width()), which decides the model's chains
// (Shader::chains_for), for a perspective view or an orthographic one (is_perspective).
ProgramRequest shade_program(const Material& resolved, const std::vector<Light>& lights, Precision precision,
                             std::size_t device_width, bool perspective);

}  // namespace shadelab
