#include "plot/gnuplot.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/format.hpp"

extern char** environ;

namespace fs = std::filesystem;

namespace shadelab::plot {

// ------------------------------------------------------------------------------------------ gnuplot

namespace {
bool executable(const std::string& p) { return ::access(p.c_str(), X_OK) == 0 && !fs::is_directory(p); }

}  // namespace

std::string gp_number(double x, int digits) { return num(x, digits); }

std::string gnuplot_preamble(const std::string& png, int width, int height, int font_size) {
    std::ostringstream s;
    s << "set terminal pngcairo size " << width << "," << height << " enhanced font 'sans," << font_size << "'\n"
      << "set output " << gp_string(png) << "\n"
      << "set datafile separator comma\n"
      << "set datafile columnheaders\n"
      << "set datafile missing ''\n"
      << "set grid lc rgb '#dddddd'\n";
    return s.str();
}

std::string gp_string(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += (c == '\'') ? std::string("''") : std::string(1, c);
    return out + "'";
}

std::string find_gnuplot() {
    if (const char* env = std::getenv("SHADELAB_GNUPLOT"); env && *env) {
        if (executable(env)) return env;
        throw Error(std::string("gnuplot not found at SHADELAB_GNUPLOT=") + env +
                    ": install the Debian package gnuplot-nox or point SHADELAB_GNUPLOT at a gnuplot executable");
    }
    const char* path = std::getenv("PATH");
    std::istringstream dirs(path ? path : "/usr/bin:/bin");
    std::string d;
    while (std::getline(dirs, d, ':')) {
        const std::string p = (d.empty() ? std::string(".") : d) + "/gnuplot";
        if (executable(p)) return p;
    }
    throw Error("gnuplot not found on PATH: install the Debian package gnuplot-nox (apt-get install gnuplot-nox)");
}

void run_gnuplot(const std::string& script, const std::string& png, const std::string& what_was_written) {
    const std::string tail = what_was_written.empty() ? "" : " (" + what_was_written + ")";
    std::string exe;
    try {
        exe = find_gnuplot();
    } catch (const Error& e) {
        throw Error(std::string("cannot draw '") + png + "': " + e.what() + tail);
    }
    const fs::path out(png);
    std::error_code ec;
    if (out.has_parent_path()) fs::create_directories(out.parent_path(), ec);
    fs::remove(out, ec);

    int in_pipe[2], err_pipe[2];
    if (::pipe(in_pipe) != 0) throw Error("cannot start gnuplot: pipe() failed: " + std::string(std::strerror(errno)));
    if (::pipe(err_pipe) != 0) {
        ::close(in_pipe[0]);
        ::close(in_pipe[1]);
        throw Error("cannot start gnuplot: pipe() failed: " + std::string(std::strerror(errno)));
    }
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, in_pipe[0], 0);
    posix_spawn_file_actions_adddup2(&fa, err_pipe[1], 2);
    posix_spawn_file_actions_adddup2(&fa, err_pipe[1], 1);
    posix_spawn_file_actions_addclose(&fa, in_pipe[1]);
    posix_spawn_file_actions_addclose(&fa, err_pipe[0]);
    std::string arg0 = "gnuplot";
    char* argv[] = {arg0.data(), nullptr};
    pid_t pid = 0;
    const int rc = ::posix_spawn(&pid, exe.c_str(), &fa, nullptr, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    ::close(in_pipe[0]);
    ::close(err_pipe[1]);
    if (rc != 0) {
        ::close(in_pipe[1]);
        ::close(err_pipe[0]);
        throw Error("cannot start gnuplot (" + exe + "): " + std::strerror(rc) + tail);
    }
    // The scripts are small (data stay in the CSV files), far below a pipe's buffer, so writing all of the
    // script before reading gnuplot's messages cannot dead-lock.
    std::size_t done = 0;
    while (done < script.size()) {
        const ssize_t n = ::write(in_pipe[1], script.data() + done, script.size() - done);
        if (n <= 0) break;
        done += std::size_t(n);
    }
    ::close(in_pipe[1]);
    std::string messages;
    char buf[4096];
    for (;;) {
        const ssize_t n = ::read(err_pipe[0], buf, sizeof buf);
        if (n <= 0) break;
        messages.append(buf, std::size_t(n));
    }
    ::close(err_pipe[0]);
    int status = 0;
    ::waitpid(pid, &status, 0);
    const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && fs::exists(out, ec) && fs::file_size(out, ec) > 0;
    if (!ok) {
        // gnuplot's messages: the line that names the problem, without the echo of the script.
        std::string first;
        std::istringstream lines(messages);
        std::string line;
        while (std::getline(lines, line)) {
            const auto at = line.find("line ");
            const bool located = at != std::string::npos && line.find(':', at) != std::string::npos;
            if (located || line.find("rror") != std::string::npos) {
                first = line.substr(line.find_first_not_of(' ') == std::string::npos ? 0 : line.find_first_not_of(' '));
                break;
            }
        }
        if (first.empty() && !messages.empty()) first = messages.substr(0, messages.find('\n'));
        throw Error("gnuplot could not draw '" + png + "'" + (first.empty() ? std::string() : ": " + first) + tail);
    }
}

}  // namespace shadelab::plot
