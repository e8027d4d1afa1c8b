// Fork-join over a few threads, for the rasteriser and the image paths (resolve, 8-bit encoding). Every user
// splits its work into contiguous ranges that depend only on the count, so results never depend on timing.
#pragma once
#include <algorithm>
#include <cstddef>
#include <thread>

namespace shadelab {

// Threads to use for `requested` (0 = all hardware threads), at most `work_items`, at least 1.
inline int thread_count(int requested, std::size_t work_items) {
    int n = requested > 0 ? requested : int(std::max(1u, std::thread::hardware_concurrency()));
    if (std::size_t(n) > work_items) n = int(std::max<std::size_t>(1, work_items));
    return std::max(1, n);
}

namespace detail {
// fn(i) for i in [0, n) through a type-erased call: `call(fn, i)` runs the caller's function object.
using ParallelCall = void (*)(const void* fn, int i);
void run_parallel_erased(int n, ParallelCall call, const void* fn);
}  // namespace detail

// Runs fn(i) for i in [0, n): i = 0 on the calling thread, the others on the threads of a pool that lives as
// long as the process (a frame forks and joins 6-8 times, and starting and joining two threads cost ~50 us
// each time: ~0.4 ms of a 2.5 ms frame at 512 x 512). A call made while the pool is busy (from another thread,
// or from inside fn) starts threads of its own instead; if a thread cannot be started, its share runs on the
// calling thread (same results, just slower). The first exception thrown by any fn(i) is rethrown here,
// after every fn(i) has returned.
template <class Fn>
void run_parallel(int n, const Fn& fn) {
    if (n <= 1) {
        fn(0);
        return;
    }
    detail::run_parallel_erased(
        n, [](const void* f, int i) { (*static_cast<const Fn*>(f))(i); }, &fn);
}

// First index of part i when [0, n) is split into `parts` contiguous ranges (part i is [split(i), split(i+1))).
inline std::size_t split(std::size_t n, int parts, int i) { return n * std::size_t(i) / std::size_t(parts); }

}  // namespace shadelab
