#include "core/assets.hpp"

#include <system_error>
#include <vector>

#include "core/error.hpp"

namespace shadelab {

namespace fs = std::filesystem;

fs::path executable_dir() {
    std::error_code ec;
    fs::path p = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::path() : p.parent_path();
}

std::string bundled_mesh(const std::string& name) {
    std::vector<fs::path> places{executable_dir() / ".." / "share" / "shadelab" / "meshes",
                                 fs::path(SHADELAB_ASSET_INSTALL_DIR) / "meshes",
                                 fs::path(SHADELAB_SOURCE_DIR) / "meshes"};
    std::string tried;
    for (const auto& dir : places) {
        std::error_code ec;
        const fs::path p = dir / name;
        if (fs::is_regular_file(p, ec)) return fs::weakly_canonical(p, ec).string();
        tried += (tried.empty() ? "" : ", ") + dir.string();
    }
    throw Error("bundled mesh '" + name + "' not found (looked in " + tried +
                "): give a mesh file explicitly or reinstall shadelab");
}

}  // namespace shadelab
