// How much a command says on stderr. Results go to stdout; logs and progress to stderr, and only as much as
// the global -q / -v of the command line asks (host/app/main.cpp sets it once, after parsing).
#pragma once
#include <iostream>

namespace shadelab {

enum class LogLevel { Quiet, Normal, Verbose };

inline LogLevel& log_level_storage() {
    static LogLevel level = LogLevel::Normal;
    return level;
}
inline void set_log_level(LogLevel l) { log_level_storage() = l; }
inline LogLevel log_level() { return log_level_storage(); }

// The stream for log lines at `at` (Normal: everyday progress; Verbose: detail): std::cerr, or a stream that
// drops everything when the level asks for less.
inline std::ostream& log_out(LogLevel at = LogLevel::Normal) {
    static std::ostream null_stream(nullptr);
    return static_cast<int>(log_level()) >= static_cast<int>(at) ? std::cerr : null_stream;
}

}  // namespace shadelab
