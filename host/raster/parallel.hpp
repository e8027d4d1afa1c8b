// Fork-join over a few threads, for the rasteriser and the image paths (resolve, 8-bit encoding). Every user
// splits its work into contiguous ranges or pieces that depend only on the counts, each written by one thread
// alone, so results never depend on timing.
#pragma once
#include <algorithm>
#include <atomic>
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

// Runs fn(i) for every piece i in [0, pieces) on up to `threads` threads, each taking the next piece from a
// shared counter. Cut a stage into more pieces than threads when its threads must all finish before the next
// stage: with one contiguous range a thread, a thread the machine did not run for a while (a virtual machine
// whose host shares its cores with other guests: docs/speed.md, "core speed probe") kept the others waiting.
// Which thread takes which piece depends on timing, so fn(i) must write only what piece i owns.
template <class Fn>
void run_pieces(int threads, std::size_t pieces, const Fn& fn) {
    if (pieces == 0) return;
    const int n = int(std::min<std::size_t>(std::size_t(std::max(1, threads)), pieces));
    std::atomic<std::size_t> next{0};
    run_parallel(n, [&](int) {
        for (std::size_t i = next++; i < pieces; i = next++) fn(i);
    });
}

}  // namespace shadelab
