#include "core/limits.hpp"

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/error.hpp"

namespace shadelab {

namespace {

std::atomic<std::uint64_t> g_override{0};

std::uint64_t physical_memory() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0) return std::uint64_t(8) << 30;   // unknown: assume a small 8 GiB machine
    return std::uint64_t(pages) * std::uint64_t(page);
}

}  // namespace

std::string format_bytes(double b) {
    const char* units[] = {"bytes", "kB", "MB", "GB", "TB", "PB", "EB"};
    int u = 0;
    while (b >= 1000.0 && u < 6) {
        b /= 1000.0;
        ++u;
    }
    char buf[64];
    std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.1f %s", b, units[u]);
    return buf;
}

std::uint64_t parse_bytes(const std::string& text, const std::string& what) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    double scale = 1.0;
    std::string unit = end ? std::string(end) : std::string();
    if (unit == "k" || unit == "K") scale = 1e3;
    else if (unit == "M" || unit == "m") scale = 1e6;
    else if (unit == "G" || unit == "g") scale = 1e9;
    else if (unit == "T" || unit == "t") scale = 1e12;
    else if (!unit.empty()) scale = -1.0;
    const double bytes = v * scale;
    if (text.empty() || end == text.c_str() || scale < 0.0 || !std::isfinite(bytes) || !(bytes >= 1.0) || bytes > 1.8e19)
        throw Error(what + ": '" + text + "' is not a memory size: give bytes with an optional k, M, G or T (e.g. 16G)");
    return std::uint64_t(bytes);
}

std::uint64_t memory_limit() {
    if (const std::uint64_t o = g_override.load()) return o;
    if (const char* env = std::getenv("SHADELAB_MAX_MEMORY"); env && *env) return parse_bytes(env, "SHADELAB_MAX_MEMORY");
    return physical_memory();
}

void set_memory_limit(std::uint64_t bytes) { g_override.store(bytes); }

void check_memory(const std::string& what, double bytes) {
    const std::uint64_t limit = memory_limit();
    if (!(bytes <= double(limit)))
        throw Error(what + " would need " + format_bytes(bytes) + " of memory, more than the limit of " +
                    format_bytes(double(limit)) +
                    ": make it smaller, or raise the limit with --max-memory or SHADELAB_MAX_MEMORY (e.g. 64G)");
}

}  // namespace shadelab
