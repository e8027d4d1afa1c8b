#include "core/assets.hpp"

#include <dlfcn.h>

#include <algorithm>
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

fs::path module_dir() {
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&module_dir), &info) == 0 || info.dli_fname == nullptr) return {};
    std::error_code ec;
    const fs::path p = fs::canonical(info.dli_fname, ec);
    return ec ? fs::path() : p.parent_path();
}

std::vector<fs::path> installed_share_dirs(const std::string& sub) {
    std::vector<fs::path> out;
    for (const fs::path& dir : {module_dir(), executable_dir()}) {
        if (dir.empty()) continue;
        // bin/ or lib/ (1 up), lib/<multiarch>/ (2), lib/python3/dist-packages/ (3)
        for (const fs::path& up : {dir / "..", dir / ".." / "..", dir / ".." / ".." / ".."}) {
            const fs::path p = up / "share" / "shadelab" / sub;
            if (std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
        }
    }
    return out;
}

std::string bundled_mesh(const std::string& name) {
    std::vector<fs::path> places = installed_share_dirs("meshes");
    places.push_back(fs::path(SHADELAB_ASSET_INSTALL_DIR) / "meshes");
    places.push_back(fs::path(SHADELAB_SOURCE_DIR) / "meshes");
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
