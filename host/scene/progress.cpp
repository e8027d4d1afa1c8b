#include "scene/progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <sstream>

#include "core/error.hpp"

namespace shadelab {

namespace {
int terminal_columns() {
    winsize ws{};
    if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col >= 20) return ws.ws_col;
    return 80;
}
}  // namespace

ProgressStyle parse_progress_style(const std::string& name) {
    if (name == "auto") return ProgressStyle::Auto;
    if (name == "bar") return ProgressStyle::Bar;
    if (name == "lines") return ProgressStyle::Lines;
    if (name == "quiet" || name == "none") return ProgressStyle::Quiet;
    throw Error("--progress '" + name + "': use auto, bar, lines or quiet");
}

Progress::Progress(std::size_t total, std::ostream& out, ProgressStyle style)
    : total_(total), out_(out), style_(style), t0_(std::chrono::steady_clock::now()) {
    if (style_ == ProgressStyle::Auto)
        style_ = (&out == &std::cerr && ::isatty(STDERR_FILENO)) ? ProgressStyle::Bar : ProgressStyle::Lines;
}

Progress::~Progress() { close(); }

std::string Progress::format_duration(double s) {
    if (!(s >= 0.0)) s = 0.0;
    const long t = long(s + 0.5);
    char buf[32];
    if (t >= 3600) std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
    else std::snprintf(buf, sizeof buf, "%ld:%02ld", t / 60, t % 60);
    return buf;
}

void Progress::clear_line() {
    if (drawn_) out_ << "\r\033[K";
    drawn_ = false;
}

void Progress::draw() {
    if (style_ != ProgressStyle::Bar || closed_) return;
    constexpr int kBar = 28;
    const double frac = total_ ? double(done_) / double(total_) : 1.0;
    const int filled = int(frac * kBar + 0.5);
    std::ostringstream s;
    s << '[' << std::string(std::size_t(filled), '#') << std::string(std::size_t(kBar - filled), '.') << "] " << done_
      << '/' << total_ << " ok " << ok_ << " skipped " << skipped_ << " failed " << failed_;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    s << " " << format_duration(elapsed);
    // ETA: the mean wall time per job that did work (up-to-date skips cost next to nothing), times the
    // jobs left. Wall time, not per-job stage times, because the stages of neighbouring jobs overlap.
    if (done_ < total_ && busy_jobs_ > 0)
        s << " ETA " << format_duration(elapsed / double(busy_jobs_) * double(total_ - done_));
    if (!label_.empty() && done_ < total_) s << " " << label_;
    std::string line = s.str();
    const std::size_t cols = std::size_t(terminal_columns()) - 1;
    if (line.size() > cols) line = line.substr(0, cols);
    out_ << "\r\033[K" << line << std::flush;
    drawn_ = true;
}

void Progress::start(const std::string& label) {
    label_ = label;
    draw();
}

void Progress::finish(bool ok, bool skipped, const std::string& line) {
    ++done_;
    if (!ok) ++failed_;
    else if (skipped) ++skipped_;
    else ++ok_;
    if (!skipped) ++busy_jobs_;
    // Lines: every job; Bar: failures only (the bar carries the rest); Quiet: failures only.
    if (!line.empty() && (style_ == ProgressStyle::Lines || !ok)) message(line);
    else draw();
}

void Progress::message(const std::string& line) {
    clear_line();
    out_ << line << "\n";
    draw();
    out_.flush();
}

void Progress::close() {
    if (closed_) return;
    if (style_ == ProgressStyle::Bar) {
        draw();              // the final state, then a newline so the summary starts on its own line
        if (drawn_) out_ << "\n";
        drawn_ = false;
    }
    closed_ = true;
    out_.flush();
}

}  // namespace shadelab
