#include "core/atomic_file.hpp"

#include <signal.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
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

// The pid in '.<name>.tmp<pid>[suffix]', or 0 when `file` is not named like that.
long temporary_pid(const std::string& file) {
    if (file.size() < 6 || file[0] != '.') return 0;
    for (std::size_t at = file.rfind(".tmp"); at != std::string::npos && at > 0; at = file.rfind(".tmp", at - 1)) {
        std::size_t i = at + 4, j = i;
        while (j < file.size() && file[j] >= '0' && file[j] <= '9') ++j;
        if (j > i && j - i <= 9 && (j == file.size() || file[j] == '.')) return std::stol(file.substr(i, j - i));
    }
    return 0;
}

// "the disk is full (...)" when fewer than 64 kB are left in `dir` for this process (root may also use the
// blocks a file system reserves for it), else empty.
std::string disk_full(const std::string& dir) {
    struct statvfs fsinfo {};
    if (::statvfs(dir.c_str(), &fsinfo) != 0) return {};
    const double free_bytes = double(::geteuid() == 0 ? fsinfo.f_bfree : fsinfo.f_bavail) * double(fsinfo.f_frsize);
    if (free_bytes >= 65536.0) return {};
    return "the disk is full (" + std::to_string((unsigned long long)free_bytes) + " bytes free in '" + dir +
           "'): free some space or write somewhere else";
}

// Why a write into `folder` failed, asked of the file system after the fact (the libraries that write
// images and tables report a failed write, rarely its errno): a read-only mount, a folder we may not
// write to, or no space left (while the partial file is still there); empty when none of these is the case.
std::string write_failure_cause(const fs::path& folder) {
    const std::string dir = folder.empty() ? std::string(".") : folder.string();
    struct statvfs fsinfo {};
    if (::statvfs(dir.c_str(), &fsinfo) == 0 && (fsinfo.f_flag & ST_RDONLY))
        return "the folder '" + dir + "' is on a read-only file system: write somewhere else";
    if (::access(dir.c_str(), W_OK) != 0)
        return "the folder '" + dir + "' is not writable (" + std::string(std::strerror(errno)) + "): write somewhere else";
    return disk_full(dir);
}

}  // namespace

std::size_t remove_stale_temporaries(const std::string& folder) {
    std::error_code ec;
    std::size_t removed = 0;
    for (const auto& e : fs::directory_iterator(folder.empty() ? "." : folder, ec)) {
        const std::string name = e.path().filename().string();
        const long pid = temporary_pid(name);
        if (pid <= 0 || !e.is_regular_file(ec)) continue;
        // kill(pid, 0) probes without signalling: ESRCH means no such process.
        if (pid == long(::getpid()) || ::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue;
        if (fs::remove(e.path(), ec)) ++removed;
    }
    return removed;
}

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
    // OpenImageIO 2.4's PNG and EXR writers report success when the disk filled up under them (their
    // buffered writes' errors are dropped), leaving a truncated file: a write that leaves the file system
    // without room is taken as failed rather than put in place unverified.
    if (ok && !disk_full(target.parent_path().empty() ? std::string(".") : target.parent_path().string()).empty())
        ok = false;
    if (!ok) {
        const std::string cause = write_failure_cause(target.parent_path());   // before the partial file goes
        fs::remove(tmp, ec);
        throw Error("writing '" + path + "' failed: " +
                    (cause.empty() ? (why.empty() ? std::string("the library gave no reason") : why) +
                                         " (is the disk full or the folder read-only?)"
                                   : cause));
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
