// Large frame buffers (a 4096 x 4096 RGBA float image is 256 MB): asks the kernel for transparent huge pages
// before the first touch, so that filling a fresh buffer takes one page fault per 2 MB instead of per 4 KB, and
// has the pages faulted in by all hardware threads at once, each its own part. Only advice: where the kernel has
// no such pages (or THP is off, or it predates MADV_POPULATE_WRITE), nothing changes but the speed.
#pragma once
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/fragment_buffer.hpp"
#include "raster/parallel.hpp"

namespace shadelab {

// madvise(MADV_HUGEPAGE) on the whole pages inside [p, p + bytes).
inline void advise_huge_pages(const void* p, std::size_t bytes) {
#ifdef MADV_HUGEPAGE
    const std::uintptr_t page = std::uintptr_t(::sysconf(_SC_PAGESIZE));
    const std::uintptr_t b = (std::uintptr_t(p) + page - 1) / page * page, e = (std::uintptr_t(p) + bytes) / page * page;
    if (bytes >= (std::size_t(4) << 20) && e > b) ::madvise(reinterpret_cast<void*>(b), e - b, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

// Buffers from this size on are faulted in on several threads.
constexpr std::size_t kPopulateInParallelBytes = std::size_t(16) << 20;

// Faults in the whole pages inside [p, p + bytes) as writes would (MADV_POPULATE_WRITE, Linux 5.14), on up to
// `threads` threads (0 = all hardware threads), each a contiguous part cut at 2 MB (a huge page's) boundaries.
// Why: the kernel zero-fills every fresh page in the thread that first touches it, and on a virtual machine that
// is also where the host backs the page; filling a fresh 4096 x 4096 image on one thread (the vector's own zero-
// fill) took 45-60 ms when its pages were warm on the host and 190-480 ms when they were not (`shadelab render`'s
// resolve; docs/speed.md, "fresh-pages"). Two threads about halve the faults' time. Errors are ignored: the
// first writes then fault the pages in as before.
inline void populate_in_parallel(const void* p, std::size_t bytes, int threads) {
#ifdef MADV_POPULATE_WRITE
    if (bytes < kPopulateInParallelBytes) return;
    const std::uintptr_t page = std::uintptr_t(::sysconf(_SC_PAGESIZE)), huge = std::uintptr_t(2) << 20;
    const std::uintptr_t b = (std::uintptr_t(p) + page - 1) / page * page, e = (std::uintptr_t(p) + bytes) / page * page;
    if (e <= b) return;
    const int n = thread_count(threads, (e - b) / huge);
    if (n <= 1) return;   // one thread: the first writes fault the pages in, at the same cost
    run_parallel(n, [&](int t) {
        const auto cut = [&](int i) {
            return i == 0 ? b : (i == n ? e : std::min(e, std::max(b, (b + split(e - b, n, i)) / huge * huge)));
        };
        const std::uintptr_t lo = cut(t), hi = cut(t + 1);
        if (hi > lo) ::madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_POPULATE_WRITE);
    });
#else
    (void)p;
    (void)bytes;
    (void)threads;
#endif
}

// v.resize(n) for an empty vector, with huge pages advised before the elements are first written, and its pages
// faulted in on `populate_threads` threads (0 = all hardware threads; 1 when the caller already sizes several
// buffers in parallel).
template <class T>
void resize_fresh(std::vector<T>& v, std::size_t n, int populate_threads = 0) {
    v.reserve(n);
    advise_huge_pages(v.data(), n * sizeof(T));
    populate_in_parallel(v.data(), n * sizeof(T), populate_threads);
    v.resize(n);
}

// n elements in v for this frame: the vector's own memory when it is large enough (a renderer reusing its
// buffers from frame to frame pays no page faults), else fresh memory with huge pages advised and faulted in on
// `populate_threads` threads (resize_fresh).
template <class T>
void size_for_frame(std::vector<T>& v, std::size_t n, int populate_threads = 0) {
    if (v.capacity() < n) {
        std::vector<T>().swap(v);
        resize_fresh(v, n, populate_threads);
    } else {
        v.resize(n);
    }
}

// The eleven fragment arrays sized for n fragments (eight, and triangle, b1 and b2 emptied, without
// `triangle_ids`). Growing an array value-initialises its new elements (and faults in fresh pages): a pass over
// 44 bytes per fragment that, on one thread, kept the other idle, so the threads take every threads-th array
// (each vector is one thread's alone).
inline void size_fragments(FragmentBuffer& fb, std::size_t n, bool triangle_ids, int threads) {
    std::vector<std::vector<float>*> f = {&fb.px, &fb.py, &fb.pz, &fb.nx, &fb.ny, &fb.nz, &fb.depth};
    std::vector<std::vector<std::int32_t>*> i = {&fb.pixel};
    if (triangle_ids) {
        f.insert(f.end(), {&fb.b1, &fb.b2});
        i.push_back(&fb.triangle);
    } else {
        fb.triangle.clear();
        fb.b1.clear();
        fb.b2.clear();
    }
    const std::size_t floats = f.size(), arrays = f.size() + i.size();
    bool grows = false;
    for (const std::vector<float>* v : f) grows = grows || v->size() < n;
    for (const std::vector<std::int32_t>* v : i) grows = grows || v->size() < n;
    const int workers = grows ? std::min(threads, int(arrays)) : 1;
    run_parallel(workers, [&](int t) {
        for (std::size_t k = std::size_t(t); k < arrays; k += std::size_t(workers))
            k < floats ? size_for_frame(*f[k], n, 1) : size_for_frame(*i[k - floats], n, 1);
    });
}

}  // namespace shadelab
