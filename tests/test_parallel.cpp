// run_parallel (host/raster/parallel.hpp), the fork-join behind the rasteriser and the image paths, on its
// persistent pool: every part runs exactly once per call, whatever the part count, back to back or after the
// workers have gone to sleep; a call from inside a part and calls from two threads at once (the pool busy)
// still run every part; an exception from any part reaches the caller after every part has returned; a child
// made by fork() (whose parent's workers do not exist there) runs every part too.
// run_pieces, on top of it: every piece exactly once, none past the end, whatever the thread and piece counts.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

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
