// Large frame buffers (a 4096 x 4096 RGBA float image is 256 MB): asks the kernel for transparent huge pages
// before the first touch, so that filling a fresh buffer takes one page fault per 2 MB instead of per 4 KB.
// Only advice: where the kernel has no such pages (or THP is off), nothing changes but the speed.
#pragma once
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <vector>

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

// v.resize(n) for an empty vector, with huge pages advised before the elements are first written.
template <class T>
void resize_fresh(std::vector<T>& v, std::size_t n) {
    v.reserve(n);
    advise_huge_pages(v.data(), n * sizeof(T));
    v.resize(n);
}

// n elements in v for this frame: the vector's own memory when it is large enough (a renderer reusing its
// buffers from frame to frame pays no page faults), else fresh memory with huge pages advised.
template <class T>
void size_for_frame(std::vector<T>& v, std::size_t n) {
    if (v.capacity() < n) {
        std::vector<T>().swap(v);
        resize_fresh(v, n);
    } else {
        v.resize(n);
    }
}

}  // namespace shadelab
