#include "image/image_io.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "core/error.hpp"
#include "core/limits.hpp"

namespace fs = std::filesystem;

namespace shadelab::image_io {

namespace {

// The folder of the file this code was loaded from: the program, libshadelab.so or the Python module.
fs::path own_folder() {
    Dl_info info{};
    if (::dladdr(reinterpret_cast<void*>(&own_folder), &info) != 0 && info.dli_fname && *info.dli_fname) {
        std::error_code ec;
        const fs::path p = fs::canonical(info.dli_fname, ec);
        if (!ec) return p.parent_path();
    }
    std::error_code ec;
    const fs::path exe = fs::canonical("/proc/self/exe", ec);
    return ec ? fs::path() : exe.parent_path();
}

std::vector<fs::path> candidates() {
    std::vector<fs::path> out;
    if (const char* env = std::getenv("SHADELAB_IMAGEIO_PLUGIN"); env && *env) {
        out.emplace_back(env);
        return out;
    }
    const fs::path d = own_folder();
    if (!d.empty()) {
        for (const fs::path& rel : {fs::path("."), fs::path("shadelab"), fs::path(".."),
                                    fs::path("../" SHADELAB_PLUGIN_LIBDIR "/shadelab"), fs::path("../lib/shadelab"),
                                    fs::path("../../shadelab")})
            if (const fs::path f = (d / rel / kFileName).lexically_normal(); std::find(out.begin(), out.end(), f) == out.end())
                out.push_back(f);
    }
    out.push_back(fs::path(SHADELAB_PLUGIN_INSTALL_DIR) / kFileName);
    return out;
}

const Plugin* load() {
    static const Host host{&check_memory};
    std::string tried, last_error;
    for (const fs::path& file : candidates()) {
        tried += (tried.empty() ? "" : ", ") + file.string();
        std::error_code ec;
        if (!fs::exists(file, ec)) continue;
        void* handle = ::dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* why = ::dlerror();
            last_error = "; " + file.string() + ": " + (why ? why : "dlopen failed");
            continue;
        }
        const auto entry = reinterpret_cast<EntryPoint>(::dlsym(handle, kEntryPoint));
        const Plugin* p = entry ? entry(&host) : nullptr;
        if (!p || p->abi != kAbi)
            throw Error("the image plug-in " + file.string() + " is not this version's (interface " + std::to_string(kAbi) +
                        "): reinstall shadelab, or point SHADELAB_IMAGEIO_PLUGIN at this build's " + kFileName);
        return p;   // never unloaded: OpenImageIO keeps threads and state for the life of the process
    }
    throw Error(std::string("cannot load the image plug-in ") + kFileName + " (OpenImageIO and GDAL formats) from " +
                tried + last_error + ": reinstall shadelab, or set SHADELAB_IMAGEIO_PLUGIN to the file");
}

}  // namespace

const Plugin& plugin() {
    static std::once_flag once;
    static const Plugin* p = nullptr;
    std::call_once(once, [] { p = load(); });
    return *p;
}

}  // namespace shadelab::image_io
