// Where shadelab finds what it ships (kernels, bundled meshes), from any working directory: beside the installed
// binary or library (PREFIX/share/shadelab), the install prefix it was configured for, then the source tree it
// was built from. Defaults that name a bundled file go through here, so `shadelab contact` works outside the checkout.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace shadelab {

// The folder of the running executable ("" when the system does not say).
std::filesystem::path executable_dir();

// The folder of the binary that holds this code: the executable, or libshadelab.so / the Python module when
// shadelab is used as a library ("" when the system does not say).
std::filesystem::path module_dir();

// PREFIX/share/shadelab/<sub> for every PREFIX an installed shadelab may sit under: one to three folders above
// module_dir() (bin/, lib/, lib/<multiarch>/, lib/python3/dist-packages/) and above executable_dir(), nearest
// first.
std::vector<std::filesystem::path> installed_share_dirs(const std::string& sub);

// The bundled mesh `name` (e.g. "spot.obj"): the first existing of <exe>/../share/shadelab/meshes,
// the configured install prefix's share/shadelab/meshes and the source tree's meshes/. Throws shadelab::Error
// naming the places it looked when none has it.
std::string bundled_mesh(const std::string& name);

}  // namespace shadelab
