// What the benchmarks share: what they print about the machine they ran on, and how many runs make a best-of.
#pragma once
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

namespace shadelab::bench {

// How many timed runs make a best-of: at least `at_least`, and more while the runs so far took under `min_ms`
// (at most `at_most`). On this shared machine a short best-of caught bursts of load: phong at 1M fragments ran
// 394-468 Mfrag/s with 3 runs and 712-734 with 30 in one sitting (bench_models), spot 512x512 swung 1.73-2.05x
// llvmpipe with 9 frames (bench_e2e). Every timed quantity of a row gets the same rule, so ratios compare like
// with like.
struct Repeats {
    int at_least = 3;
    double min_ms = 100.0;
    int at_most = 40;
    bool again(int done, double spent_ms) const { return done < at_least || (spent_ms < min_ms && done < at_most); }
    std::string describe() const {
        return min_ms > 0.0 ? "at least " + std::to_string(at_least) + " runs and " + std::to_string(int(min_ms)) +
                                  " ms (at most " + std::to_string(at_most) + " runs)"
                            : std::to_string(at_least) + " runs";
    }
};

// The CPU's model name from /proc/cpuinfo ("unknown CPU" where there is none).
inline std::string cpu_name() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown CPU";
}

// The load averages (/proc/loadavg's first three fields), printed with the figures: the machine may be shared.
inline std::string load_average() {
    std::ifstream in("/proc/loadavg");
    std::string a, b, c;
    return in >> a >> b >> c ? a + " " + b + " " + c : "unknown";
}

// The core speed probe: how fast a core runs a chain of dependent integer additions, one thread alone and then
// one a hardware thread all at once. Every x86-64 core of the last fifteen years adds one register to itself per
// cycle, and no faster (each addition waits for the last), so on an idle core the rate in G additions/s is its
// clock in GHz. On a virtual machine it is the clock a thread actually gets: the load average counts only this
// machine's own threads, and a host that shares its cores with other machines shows nowhere else. And the
// threads at once against one alone is the most any parallel code could gain at that moment (the rasteriser's
// 2-thread bar is for an idle machine). Seen on this project's 2-core machine at load average 0.3-0.9: 1.23 G/s
// alone and 0.70 + 0.77 at once (1.19x; single windows of 1 s), while the rasteriser ran 2.3-4x slower than two
// days before on the same kind of machine. Printed at the start and end of each bench (and by the core_probe
// program for scripts/speed_report.py). Elsewhere than x86-64 the chain is a plain loop the compiler may schedule
// differently: the figures are then relative ones (`cycle_calibrated` false).
struct CoreProbe {
    double alone = 0.0;             // G additions a second, one thread
    std::vector<double> at_once;    // per thread, all threads at once
    double seconds = 0.0;           // how long each thread added, each time
    int rounds = 0;                 // alone and at once in turn, this many times; the best of each is kept
    bool cycle_calibrated = false;

    double together() const { return std::accumulate(at_once.begin(), at_once.end(), 0.0); }
    // What the threads at once did together, in units of one thread alone.
    double scaling() const { return alone > 0.0 ? together() / alone : 0.0; }

    // "core speed probe: 1.23 alone, 0.70 0.77 at once G adds/s (...)": the numbers first, for scripts.
    std::string line() const {
        char buf[160];
        std::snprintf(buf, sizeof buf, "core speed probe: %.2f alone,", alone);
        std::string out = buf;
        for (double g : at_once) {
            std::snprintf(buf, sizeof buf, " %.2f", g);
            out += buf;
        }
        std::snprintf(buf, sizeof buf,
                      " at once G adds/s (%zu threads at once = %.2fx one alone; best of %d rounds of %.2f s; ",
                      at_once.size(), scaling(), rounds, seconds);
        out += buf;
        out += cycle_calibrated
                   ? "one dependent add a cycle: an idle core's clock in GHz, less where the host shares it)"
                   : "relative figures on this CPU)";
        return out;
    }
};

// G dependent additions a second on the calling thread, counted in blocks of 2^20 until `seconds` have passed.
inline double add_chain_rate(double seconds) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    std::uint64_t x = 0, blocks = 0;
    double elapsed = 0.0;
    do {
        for (int i = 0; i < (1 << 20); ++i) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
            __asm__ volatile("add $1, %0" : "+r"(x));   // the chain: each add waits for the one before
#else
            x = *static_cast<volatile std::uint64_t*>(&x) + 1;
#endif
        }
        ++blocks;
        elapsed = std::chrono::duration<double>(clock::now() - t0).count();
    } while (elapsed < seconds);
    return double(blocks) * double(1 << 20) / elapsed * 1e-9;
}

// The probe: one thread alone, then `threads` at once (0: one a hardware thread), `seconds` each time, `rounds`
// times in turn; the best of each is kept (the host's share of a core changes from one tenth of a second to the
// next: seen here, single 0.2 s windows gave 0.67 alone and 0.90 + 1.29 at once).
inline CoreProbe core_probe(unsigned threads = 0, double seconds = 0.05, int rounds = 4) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    CoreProbe p;
    p.seconds = seconds;
    p.rounds = rounds;
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    p.cycle_calibrated = true;
#endif
    p.at_once.assign(threads, 0.0);
    CoreProbe round;   // this round's threads at once
    round.at_once.assign(threads, 0.0);
    for (int r = 0; r < rounds; ++r) {
        p.alone = std::max(p.alone, add_chain_rate(seconds));
        std::vector<std::thread> pool;
        for (unsigned t = 0; t < threads; ++t)
            pool.emplace_back([&round, t, seconds] { round.at_once[t] = add_chain_rate(seconds); });
        for (std::thread& th : pool) th.join();
        if (round.together() > p.together()) p.at_once = round.at_once;   // the round whose threads did most
    }
    return p;
}

}  // namespace shadelab::bench
