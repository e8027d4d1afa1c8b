#include "core/atomic_file.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"

namespace fs = std::filesystem;

namespace shadelab {

namespace {

// '.<name>.tmp<pid><suffix>' in the target's folder: hidden, per process, and on the target's file
// system so the final rename is atomic.
fs::path temporary_beside(const fs::path& target, const std::string& suffix) {
    return target.parent_path() / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()) + suffix);
}

void create_parent_folder(const fs::path& target, const std::string& path) {
    std::error_code ec;
    if (!target.has_parent_path() || fs::is_directory(target.parent_path(), ec)) return;
    fs::create_directories(target.parent_path(), ec);
    if (ec) throw Error("cannot create folder '" + target.parent_path().string() + "' for '" + path + "': " + ec.message());
}

}  // namespace

void write_file_atomically(const std::string& path, const std::string& what, const FillFile& fill,
                           const std::string& tmp_suffix) {
    const fs::path target(path);
    create_parent_folder(target, path);
    const fs::path tmp = temporary_beside(target, tmp_suffix);
    std::error_code ec;
    std::string why;
    bool ok = false;
    try {
        ok = fill(tmp.string(), why);
    } catch (...) {
        fs::remove(tmp, ec);
        throw;
    }
    if (!ok) {
        fs::remove(tmp, ec);
        throw Error("writing '" + path + "' failed" + (why.empty() ? "" : ": " + why) +
                    " (is the disk full or the folder read-only?)");
    }
    fs::rename(tmp, target, ec);
    if (ec) {
        const std::string reason = ec.message();
        fs::remove(tmp, ec);
        throw Error("cannot move the finished " + what + " into place at '" + path + "': " + reason);
    }
}

void write_text_atomically(const std::string& path, const std::string& what, const std::string& bytes) {
    write_file_atomically(path, what, [&](const std::string& tmp, std::string&) {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), std::streamsize(bytes.size()));
        out.close();
        return bool(out);
    });
}

}  // namespace shadelab
