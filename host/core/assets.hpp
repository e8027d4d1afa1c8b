// Where shadelab finds what it ships (the bundled meshes), from any working directory: next to the installed
// binary (PREFIX/share/shadelab), the install prefix it was configured for, then the source tree it was built
// from. Defaults that name a bundled file go through here, so `shadelab contact` works outside the checkout.
#pragma once
#include <filesystem>
#include <string>

namespace shadelab {

// The folder of the running executable ("" when the system does not say).
std::filesystem::path executable_dir();

// The bundled mesh `name` (e.g. "spot.obj"): the first existing of <exe>/../share/shadelab/meshes,
// the configured install prefix's share/shadelab/meshes and the source tree's meshes/. Throws shadelab::Error
// naming the places it looked when none has it.
std::string bundled_mesh(const std::string& name);

}  // namespace shadelab
