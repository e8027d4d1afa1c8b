// What the benchmarks share: what they print about the machine they ran on, and how many runs make a best-of.
#pragma once
#include <fstream>
#include <string>

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

}  // namespace shadelab::bench
