// Fork-join over a few threads, for the rasteriser and the image paths (resolve, 8-bit encoding). Every user
// splits its work into contiguous ranges that depend only on the count, so results never depend on timing.
#pragma once
#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace shadelab {

// Threads to use for `requested` (0 = all hardware threads), at most `work_items`, at least 1.
inline int thread_count(int requested, std::size_t work_items) {
    int n = requested > 0 ? requested : int(std::max(1u, std::thread::hardware_concurrency()));
    if (std::size_t(n) > work_items) n = int(std::max<std::size_t>(1, work_items));
    return std::max(1, n);
}

// Runs fn(i) for i in [0, n): i = 0 on the calling thread, the others on their own threads. If a thread
// cannot be started, its share runs on the calling thread (same results, just slower).
template <class Fn>
void run_parallel(int n, const Fn& fn) {
    std::vector<std::thread> pool;
    int started = 1;
    try {
        pool.reserve(std::size_t(n > 1 ? n - 1 : 0));
        for (; started < n; ++started) pool.emplace_back([&fn, started] { fn(started); });
    } catch (...) {
    }
    fn(0);
    for (int i = started; i < n; ++i) fn(i);
    for (auto& t : pool) t.join();
}

// First index of part i when [0, n) is split into `parts` contiguous ranges (part i is [split(i), split(i+1))).
inline std::size_t split(std::size_t n, int parts, int i) { return n * std::size_t(i) / std::size_t(parts); }

}  // namespace shadelab
