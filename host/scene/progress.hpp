// Batch progress: a one-line bar with counts and ETA when stderr is a terminal, plain log lines otherwise.
// Debian 12 has no C++ progress-bar library (libindicators-dev is not in bookworm), so this is a minimal
// one: a carriage return, the bar, the counts, the ETA, and the line cleared before any message.
#pragma once
#include <chrono>
#include <cstddef>
#include <ostream>
#include <string>

namespace shadelab {

enum class ProgressStyle { Auto, Bar, Lines, Quiet };
ProgressStyle parse_progress_style(const std::string& name);   // auto | bar | lines | quiet

class Progress {
public:
    // Auto picks Bar when `out` is std::cerr and stderr is a terminal, else Lines.
    Progress(std::size_t total, std::ostream& out, ProgressStyle style = ProgressStyle::Auto);
    ~Progress();

    void start(const std::string& label);   // the job now running (shown on the bar: keep it short)
    // A finished job: `ok` false counts a failure; `skipped` an up-to-date job. `line` is printed as a
    // log line in Lines mode; a failure's line is printed in every mode (above the bar on a terminal).
    void finish(bool ok, bool skipped, const std::string& line);
    void message(const std::string& line);  // any other line, printed above the bar
    void close();                           // clears the bar, leaves the cursor on a fresh line

    bool is_bar() const { return style_ == ProgressStyle::Bar; }
    static std::string format_duration(double seconds);   // "1:05", "1:02:03"

private:
    void draw();
    void clear_line();

    std::size_t total_, done_ = 0, ok_ = 0, skipped_ = 0, failed_ = 0;
    std::ostream& out_;
    ProgressStyle style_;
    std::string label_;
    std::chrono::steady_clock::time_point t0_;
    std::size_t busy_jobs_ = 0;      // finished jobs that did work (skips are nearly free)
    bool drawn_ = false, closed_ = false;
};

}  // namespace shadelab
