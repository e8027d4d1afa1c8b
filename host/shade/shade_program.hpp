// The program Shader::shade builds for a material, its lights and a precision (cl/prebuild.hpp takes it).
#pragma once
#include <vector>

#include "cl/prebuild.hpp"
#include "models/material.hpp"
#include "shade/shader.hpp"

namespace shadelab {

ProgramRequest shade_program(const Material& resolved, const std::vector<Light>& lights, Precision precision);

}  // namespace shadelab
