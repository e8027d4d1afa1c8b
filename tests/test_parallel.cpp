// run_parallel (host/raster/parallel.hpp), the fork-join behind the rasteriser and the image paths, on its
// persistent pool: every part runs exactly once per call, whatever the part count, back to back or after the
// workers have gone to sleep; a call from inside a part and calls from two threads at once (the pool busy)
// still run every part; an exception from any part reaches the caller after every part has returned; a child
// made by fork() (whose parent's workers do not exist there) runs every part too.
// run_pieces, on top of it: every piece exactly once, none past the end, whatever the thread and piece counts.
// populate_in_parallel (host/raster/big_buffer.hpp), which faults a fresh buffer's pages in on several threads:
// every page of its range resident afterwards and none outside it touched, and size_for_frame's fresh buffers
// still all zeros.
#include <catch2/catch.hpp>

#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "raster/big_buffer.hpp"
#include "raster/parallel.hpp"

using namespace shadelab;

namespace {

// Runs n parts that count their own runs; true if each of the n ran exactly once.
bool each_part_once(int n) {
    std::vector<std::atomic<int>> runs(std::size_t(std::max(n, 1)));
    for (auto& r : runs) r = 0;
    run_parallel(n, [&](int i) { runs[std::size_t(i)]++; });
    for (const auto& r : runs)
        if (r != 1) return false;
    return true;
}

}  // namespace

TEST_CASE("run_parallel: every part exactly once, for 1 to 9 parts, many calls in a row", "[parallel]") {
    int good = 0, calls = 0;
    for (int rep = 0; rep < 200; ++rep)
        for (int n = 1; n <= 9; ++n, ++calls) good += each_part_once(n) ? 1 : 0;
    CHECK(good == calls);
}

TEST_CASE("run_parallel: parts run after the pool's workers have gone to sleep", "[parallel]") {
    for (int rep = 0; rep < 3; ++rep) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));   // far past the workers' spin
        CHECK(each_part_once(2));
        CHECK(each_part_once(4));
    }
}

TEST_CASE("run_parallel: part i of a call sees the data the caller wrote before it", "[parallel]") {
    std::vector<int> in(4096), out(4096, 0);
    for (int rep = 0; rep < 50; ++rep) {
        for (std::size_t k = 0; k < in.size(); ++k) in[k] = int(k) + rep;
        run_parallel(3, [&](int t) {
            for (std::size_t k = split(in.size(), 3, t); k < split(in.size(), 3, t + 1); ++k) out[k] = 2 * in[k];
        });
        int wrong = 0;
        for (std::size_t k = 0; k < in.size(); ++k) wrong += out[k] == 2 * (int(k) + rep) ? 0 : 1;
        REQUIRE(wrong == 0);
    }
}

TEST_CASE("run_parallel: a call from inside a part runs on threads of its own", "[parallel]") {
    std::atomic<int> inner{0}, outer{0};
    run_parallel(2, [&](int) {
        outer++;
        run_parallel(3, [&](int) { inner++; });
    });
    CHECK(outer == 2);
    CHECK(inner == 6);
    CHECK(each_part_once(2));   // the pool still works afterwards
}

TEST_CASE("run_parallel: calls from two threads at once each run all their parts", "[parallel]") {
    std::atomic<int> a{0}, b{0};
    auto many = [](std::atomic<int>& count) {
        for (int rep = 0; rep < 300; ++rep) run_parallel(2, [&](int) { count++; });
    };
    std::thread other([&] { many(b); });
    many(a);
    other.join();
    CHECK(a == 600);
    CHECK(b == 600);
}

TEST_CASE("run_parallel: an exception from a part reaches the caller after every part returned", "[parallel]") {
    for (int thrower = 0; thrower < 3; ++thrower) {
        std::atomic<int> finished{0};
        auto job = [&](int i) {
            if (i == thrower) throw std::runtime_error("part " + std::to_string(i) + " failed");
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
            finished++;
        };
        CHECK_THROWS_WITH(run_parallel(3, job), "part " + std::to_string(thrower) + " failed");
        CHECK(finished == 2);
    }
    CHECK(each_part_once(3));
}

TEST_CASE("run_parallel: a child made by fork() runs every part on a pool of its own", "[parallel]") {
    REQUIRE(each_part_once(2));   // the parent's pool exists, with its workers
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        ::alarm(20);   // a child waiting for the parent's workers would hang: end it instead
        const bool ok = each_part_once(2) && each_part_once(3);
        ::_exit(ok ? 0 : 1);
    }
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    INFO("child status " << status);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
}

TEST_CASE("run_pieces: every piece exactly once, for 0 to 40 pieces on 1 to 4 threads", "[parallel]") {
    for (int threads = 1; threads <= 4; ++threads)
        for (std::size_t pieces : {std::size_t(0), std::size_t(1), std::size_t(2), std::size_t(3), std::size_t(17),
                                   std::size_t(40)})
            for (int call = 0; call < 20; ++call) {
                std::vector<std::atomic<int>> runs(pieces + 1);
                for (auto& r : runs) r = 0;
                run_pieces(threads, pieces, [&](std::size_t i) { runs[std::min(i, pieces)]++; });
                INFO(threads << " threads, " << pieces << " pieces, call " << call);
                for (std::size_t i = 0; i < pieces; ++i) REQUIRE(runs[i] == 1);
                REQUIRE(runs[pieces] == 0);   // no index past the end
            }
}

#ifdef MADV_POPULATE_WRITE
namespace {

// Pages of [p, p + bytes) (p page-aligned) that are resident, from mincore.
std::vector<unsigned char> resident_pages(const char* p, std::size_t bytes) {
    const std::size_t page = std::size_t(::sysconf(_SC_PAGESIZE));
    std::vector<unsigned char> in((bytes + page - 1) / page);
    REQUIRE(::mincore(const_cast<char*>(p), bytes, in.data()) == 0);
    for (unsigned char& c : in) c &= 1;
    return in;
}

}  // namespace

TEST_CASE("populate_in_parallel: every page of the range resident, none beside it, on 1 to 4 threads",
          "[parallel]") {
    const std::size_t page = std::size_t(::sysconf(_SC_PAGESIZE)), mb = std::size_t(1) << 20;
    // A mapping with 4 MB on each side of the range, in 4 KB pages (no huge page may spill over the range's ends).
    const std::size_t guard = 4 * mb, most = 40 * mb, total = guard + most + guard;
    void* const map = ::mmap(nullptr, total, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    REQUIRE(map != MAP_FAILED);
    char* const base = static_cast<char*>(map);
    ::madvise(base, total, MADV_NOHUGEPAGE);
    if (::madvise(base, page, MADV_POPULATE_WRITE) != 0) {
        ::munmap(map, total);
        WARN("this kernel has no MADV_POPULATE_WRITE (Linux 5.14): populate_in_parallel does nothing here");
        return;
    }
    ::madvise(base, page, MADV_DONTNEED);   // the probe's page is not resident again
    // (offset into the range, bytes): from the first size populated in parallel on, whole and partial pages at
    // both ends, ranges that are not a multiple of the 2 MB cut
    const std::pair<std::size_t, std::size_t> cases[] = {{0, kPopulateInParallelBytes},
                                                         {100, kPopulateInParallelBytes + 3 * page + 17},
                                                         {page, 37 * mb + 5 * page},
                                                         {3 * page + 1, most - 4 * page - 1}};
    for (int threads = 1; threads <= 4; ++threads)
        for (const auto& [offset, bytes] : cases) {
            INFO(threads << " threads, offset " << offset << ", " << bytes << " bytes");
            ::madvise(base, total, MADV_DONTNEED);   // every page fresh again
            const std::vector<unsigned char> before = resident_pages(base, total);
            REQUIRE(std::count(before.begin(), before.end(), 1) == 0);
            char* const p = base + guard + offset;
            populate_in_parallel(p, bytes, threads);
            const std::vector<unsigned char> in = resident_pages(base, total);
            const std::size_t first = (guard + offset + page - 1) / page, end = (guard + offset + bytes) / page;
            std::size_t inside = 0, outside = 0;
            for (std::size_t i = 0; i < in.size(); ++i) (i >= first && i < end ? inside : outside) += in[i];
            if (threads == 1) {
                CHECK(inside == 0);   // one thread: left to the first writes
            } else {
                CHECK(inside == end - first);
            }
            CHECK(outside == 0);
        }
    ::munmap(map, total);
}
#endif

TEST_CASE("size_for_frame: a fresh buffer populated on several threads holds n zeros, and a reused one keeps its memory",
          "[parallel]") {
    for (const std::size_t n : {std::size_t(1000), (kPopulateInParallelBytes / sizeof(float)) + 12345}) {
        std::vector<float> v;
        size_for_frame(v, n);
        REQUIRE(v.size() == n);
        CHECK(std::count(v.begin(), v.end(), 0.0f) == std::ptrdiff_t(n));
        std::fill(v.begin(), v.end(), 2.0f);
        const float* const mem = v.data();
        size_for_frame(v, n / 2);
        CHECK(v.data() == mem);
        CHECK(v.size() == n / 2);
    }
}
