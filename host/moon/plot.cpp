#include "moon/plot.hpp"

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

extern char** environ;

namespace fs = std::filesystem;

namespace shadelab::moon {

// ---------------------------------------------------------------------------------------------- CSV

CsvTable& CsvTable::row() {
    rows_.emplace_back();
    return *this;
}

CsvTable& CsvTable::add(double v, int digits) {
    if (!std::isfinite(v))
        throw Error("internal: a non-finite number reached the CSV column '" +
                    (rows_.back().size() < columns_.size() ? columns_[rows_.back().size()] : std::string("?")) + "'");
    std::ostringstream s;
    s << std::setprecision(digits) << v;
    rows_.back().push_back(s.str());
    return *this;
}

CsvTable& CsvTable::add(const std::string& word) {
    std::string w = word;
    for (char& c : w)
        if (c == ',' || c == '\n' || c == '"') c = ';';
    rows_.back().push_back(w);
    return *this;
}

CsvTable& CsvTable::blank() {
    rows_.back().push_back("");
    return *this;
}

void CsvTable::write(const std::string& path) const {
    std::ostringstream out;
    for (std::size_t c = 0; c < columns_.size(); ++c) out << (c ? "," : "") << columns_[c];
    out << "\n";
    for (const auto& r : rows_) {
        if (r.size() != columns_.size())
            throw Error("internal: CSV row with " + std::to_string(r.size()) + " fields for " +
                        std::to_string(columns_.size()) + " columns in '" + path + "'");
        for (std::size_t c = 0; c < r.size(); ++c) out << (c ? "," : "") << r[c];
        out << "\n";
    }
    write_text_atomically(path, "table", out.str());
}

// ------------------------------------------------------------------------------------------ gnuplot

namespace {
bool executable(const std::string& p) { return ::access(p.c_str(), X_OK) == 0 && !fs::is_directory(p); }

// The column of `col` where column "profile" equals `which`, else NaN (so one CSV feeds both panels).
std::string where_profile(const std::string& which, const std::string& col) {
    return "(strcol('profile') eq '" + which + "' ? column('" + col + "') : NaN)";
}
}  // namespace

std::string gp_number(double x, int digits) {
    std::ostringstream s;
    s << std::setprecision(digits) << x;
    return s.str();
}

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

// --------------------------------------------------------------------------------------------- charts

void plot_curves(const std::string& csv, const std::string& png, const std::vector<std::string>& value_columns,
                 const std::vector<std::string>& labels, const std::string& title) {
    std::ostringstream s;
    s << gnuplot_preamble(png, 900, 900);
    s << "set multiplot layout 2,1 title " << gp_string(title) << "\n"
      << "set key top left\nset yrange [0:*]\nset ylabel 'I/F'\n";
    const char* panels[2][2] = {{"equator", "position along the intensity equator (disc radii, + towards the sun)"},
                                {"across", "position across the disc, perpendicular to the equator (disc radii)"}};
    for (auto& p : panels) {
        s << "set title " << gp_string(std::string("profile: ") + p[0]) << "\nset xlabel " << gp_string(p[1]) << "\n";
        s << "set xrange [-1:1]\nplot ";
        for (std::size_t i = 0; i < value_columns.size(); ++i)
            s << (i ? ", " : "") << gp_string(csv) << " using 's':" << where_profile(p[0], value_columns[i])
              << " with lines lw 2 title " << gp_string(labels[i]);
        s << "\n";
    }
    s << "unset multiplot\n";
    run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
}

void plot_profiles(const std::string& csv, const std::string& png, bool has_model, const std::string& title) {
    std::ostringstream s;
    s << gnuplot_preamble(png, 1200, has_model ? 900 : 500);
    s << "set multiplot layout " << (has_model ? 2 : 1) << ",2 title " << gp_string(title) << "\n"
      << "set key top left\nset xrange [-1:1]\n";
    const char* names[2] = {"equator", "across"};
    for (const char* p : names) {
        s << "set title " << gp_string(std::string("profile: ") + p) << "\nset xlabel 'position (disc radii)'\n"
          << "set ylabel 'I/F'\nset yrange [0:*]\n";
        s << "plot " << gp_string(csv) << " using 's':" << where_profile(p, "I") << " with points pt 7 ps 0.4 title 'image'";
        if (has_model)
            s << ", " << gp_string(csv) << " using 's':" << where_profile(p, "model") << " with lines lw 2 title 'model'";
        s << "\n";
    }
    if (has_model) {
        for (const char* p : names) {
            s << "set title " << gp_string(std::string("relative error (image - model) / model: ") + p)
              << "\nset ylabel 'relative error'\nset yrange [*:*]\nset format y '%.1e'\n";
            s << "plot " << gp_string(csv) << " using 's':" << where_profile(p, "rel_err")
              << " with points pt 7 ps 0.4 title 'used (mu, mu0 above thresholds)'\nset format y '%g'\n";
        }
    }
    s << "unset multiplot\n";
    run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
}

void plot_minnaert(const std::string& csv, const std::string& png, const MinnaertFit& f, const std::string& title) {
    std::ostringstream s;
    s << gnuplot_preamble(png, 900, 700);
    s << "set title " << gp_string(title) << "\n"
      << "set xlabel 'ln(mu mu0)'\nset ylabel 'ln(mu I)'\nset key top left\n"
      << "f(x) = " << std::setprecision(12) << f.ln_B0 << " + " << f.k << " * x\n"
      << "set label 1 \"k = " << gp_number(f.k) << " +- " << gp_number(f.se_k, 2) << "\\nB0 = " << gp_number(f.B0) << " +- "
      << gp_number(f.se_B0, 2) << "\\nrms residual " << gp_number(f.rms, 3) << "\\n" << f.used << " pixels\""
      << " at graph 0.6, graph 0.25\n"
      << "plot " << gp_string(csv) << " using 'x':'y' with dots lc rgb '#3060c0' title 'pixels', "
      << "f(x) with lines lw 2 lc rgb '#c03030' title 'fit: ln B0 + k ln(mu mu0)'\n";
    run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
}

void plot_errorbars(const std::string& csv, const std::string& png, const std::string& x, const std::string& y,
                    const std::string& e, const std::string& xlabel, const std::string& ylabel, const std::string& title) {
    std::ostringstream s;
    s << gnuplot_preamble(png, 900, 600);
    s << "set title " << gp_string(title) << "\nset xlabel " << gp_string(xlabel) << "\nset ylabel "
      << gp_string(ylabel) << "\nset key top left\nset offsets graph 0.05, graph 0.05, graph 0.1, graph 0.1\n"
      << "plot " << gp_string(csv) << " using " << gp_string(x) << ":" << gp_string(y) << ":" << gp_string(e)
      << " with yerrorbars pt 7 title " << gp_string(ylabel + " +- 1 sigma") << "\n";
    run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
}

void plot_k_map(const std::string& csv, const std::string& png, int cells, const std::string& title) {
    std::ostringstream s;
    s << gnuplot_preamble(png, 800, 720);
    const double h = 1.0 / cells;   // half cell width in disc radii
    s << "set title " << gp_string(title) << "\n"
      << "set size ratio -1\nset xrange [-1.05:1.05]\nset yrange [-1.05:1.05]\n"
      << "set xlabel 'X (disc radii, image right)'\nset ylabel 'Y (disc radii, image up)'\n"
      << "set palette rgbformulae 33,13,10\nset cblabel 'Minnaert k'\n"
      << "set object 1 circle at 0,0 size 1 fs empty border lc rgb 'black' front\n"
      << "plot " << gp_string(csv) << " using 'X':'Y':(" << h << "):(" << h
      << "):'k' with boxxy fs solid 1.0 noborder lc palette notitle\n";
    run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
}

void plot_geometry(const std::string& png, const SunGeometry& sun, double across_offset) {
    // Everything in disc radii, x right and y up, as the image is displayed.
    auto P = [&](double a, double b) {   // point a u + b w
        const glm::dvec3 p = a * sun.u + b * sun.w;
        return gp_number(p.x) + "," + gp_number(p.y);
    };
    const double alpha = sun.phase_deg * kDeg;
    std::ostringstream s;
    s << gnuplot_preamble(png, 800, 800);
    s << "unset grid\nset size ratio -1\nset xrange [-1.6:1.6]\nset yrange [-1.6:1.6]\nunset xtics\nunset ytics\n"
      << "unset border\nunset key\n"
      << "set title " << gp_string("phase " + gp_number(sun.phase_deg) + " deg, position angle " + gp_number(sun.pa_deg) +
                                   " deg (from north towards east)") << "\n";
    // The lit part: the bright limb (the half of the rim towards the sun) closed by the terminator.
    s << "set object 1 polygon from ";
    const int n = 90;
    for (int j = 0; j <= n; ++j) {
        const double phi = -0.5 * kPi + kPi * j / n;
        s << (j ? " to " : "") << P(std::cos(phi), std::sin(phi));
    }
    for (int j = 0; j <= n; ++j) {
        const double tau = kPi * j / n;   // terminator: a = -sin(tau) cos(alpha), b = cos(tau)
        s << " to " << P(-std::sin(tau) * std::cos(alpha), std::cos(tau));
    }
    s << " fs solid 1.0 noborder fc rgb '#f3e6a6' behind\n";
    s << "set object 2 circle at 0,0 size 1 fs empty border lc rgb 'black' lw 2 front\n";
    // Equator, across line, sun direction, compass.
    s << "set arrow 1 from " << P(-1, 0) << " to " << P(1, 0) << " nohead lw 2 lc rgb '#c03030' front\n"
      << "set arrow 2 from " << P(across_offset, -std::sqrt(1 - across_offset * across_offset)) << " to "
      << P(across_offset, std::sqrt(1 - across_offset * across_offset)) << " nohead lw 2 dt 2 lc rgb '#3060c0' front\n"
      << "set arrow 3 from " << P(1.0, 0) << " to " << P(1.45, 0) << " head filled lw 2 lc rgb '#d08000' front\n"
      << "set label 1 'to the sun' at " << P(1.5, 0) << " center tc rgb '#d08000' front\n"
      << "set label 2 'intensity equator (u)' at " << P(0.55, -0.08) << " center tc rgb '#c03030' front\n"
      << "set label 3 'across (w)' at " << P(across_offset + 0.08, 0.75) << " left tc rgb '#3060c0' front\n"
      << "set arrow 4 from -1.1,1.1 to -1.1,1.5 head filled lw 1.5 front\n"
      << "set label 4 'N (up)' at -1.1,1.56 center front\n"
      << "set arrow 5 from -1.1,1.1 to -1.5,1.1 head filled lw 1.5 front\n"
      << "set label 5 'E (left)' at -1.5,1.02 left front\n";
    // Position angle: the arc from north to the sun direction, counter-clockwise.
    const double pa = std::fmod(std::fmod(sun.pa_deg, 360.0) + 360.0, 360.0);
    if (pa > 0.5)
        s << "set object 3 circle at 0,0 size 0.35 arc [90:" << 90.0 + pa << "] fs empty border lc rgb '#d08000' lw 1.5 front\n"
          << "set arrow 8 from 0,0 to 0,0.45 nohead dt 3 lc rgb 'black' front\n"
          << "set label 6 'pa' at " << gp_number(0.45 * std::cos((90.0 + 0.5 * pa) * kDeg)) << ","
          << gp_number(0.45 * std::sin((90.0 + 0.5 * pa) * kDeg)) << " center tc rgb '#d08000' front\n";
    // Sub-solar point (seen when phase <= 90) and the sub-observer point (the centre).
    if (sun.phase_deg <= 90.0)
        s << "set label 7 '' at " << P(std::sin(alpha), 0) << " point pt 3 ps 2 lc rgb '#d08000' front\n"
          << "set label 8 'sub-solar' at " << P(std::sin(alpha), 0.1) << " center front\n";
    s << "set label 9 '' at 0,0 point pt 7 ps 1 front\nset label 10 'sub-observer' at 0,-0.1 center front\n"
      << "set label 11 'terminator' at " << P(-std::sin(0.75 * kPi) * std::cos(alpha) - 0.2, std::cos(0.75 * kPi))
      << " center front\n"
      << "set label 12 'bright limb' at " << P(0.8, 0.85) << " center tc rgb '#806000' front\n"
      << "plot NaN notitle\n";
    run_gnuplot(s.str(), png, "");
}

}  // namespace shadelab::moon
