// bench_e2e_process's contact-sheet rows (issue 13, "the whole process": the first cold run of the whole
// catalogue): `shadelab contact` (every model, default 128-pixel tiles) in a fresh process with PoCL's kernel
// cache in a new empty folder and shadelab's program cache off, each model in its own program (the way before)
// against the models sharing one program (ContactOptions::shared_programs, Shader::prepare_many), alternately,
// so both see the same load. Prints each run's wall and CPU time (the child's, from the kernel's accounting)
// and the ratios of the best runs.
#pragma once
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "bench_util.hpp"   // load_average
#include "core/error.hpp"
#include "scene/contact.hpp"

namespace shadelab::bench {

// The child: writes the sheet to `output`; prints "contact <ms> builds <ms> programs <n>".
inline int child_contact(const std::string& output, bool shared) {
    Runtime rt;
    ContactOptions o;
    o.output = output;
    o.shared_programs = shared;
    std::ostringstream log;
    o.log = &log;
    const ContactResult r = make_contact_sheet(o, rt);
    if (!r.failed.empty()) throw Error("contact sheet: " + r.failed.front());
    std::printf("contact %.1f builds %.1f programs %zu\n", r.ms, 1000.0 * rt.build_seconds(), rt.programs_built());
    return 0;
}

inline double children_cpu_s() {
    rusage u{};
    getrusage(RUSAGE_CHILDREN, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

template <class Run>
void bench_contact(Run run, const std::string& self, const std::filesystem::path& tmp, int reps) {
    std::printf("\n== cold contact sheet (every model, fresh process, PoCL cache empty, shadelab cache off), "
                "alternating; load average %s\n%-34s %10s %10s %10s %9s\n", load_average().c_str(), "case", "wall", "cpu", "builds",
                "programs");
    double best_wall[2] = {1e30, 1e30}, best_cpu[2] = {1e30, 1e30};
    for (int r = 0; r < reps; ++r)
        for (int shared = 0; shared < 2; ++shared) {
            const std::string pocl = (tmp / ("pocl-contact-" + std::to_string(r) + "-" + std::to_string(shared))).string();
            const double cpu0 = children_cpu_s();
            const auto t0 = std::chrono::steady_clock::now();
            const std::string out = run("POCL_CACHE_DIR='" + pocl + "' SHADELAB_PROGRAM_CACHE=off '" + self +
                                        "' --child-contact '" + (tmp / "contact.png").string() + "' --contact-shared " +
                                        std::to_string(shared));
            const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            const double cpu = 1000.0 * (children_cpu_s() - cpu0);
            double sheet_ms = 0, build_ms = 0;
            std::size_t programs = 0;
            if (std::sscanf(out.c_str(), "contact %lf builds %lf programs %zu", &sheet_ms, &build_ms, &programs) != 3)
                throw Error("unexpected output of the contact child: " + out.substr(0, 200));
            std::printf("%-34s %8.0fms %8.0fms %8.0fms %9zu\n",
                        shared ? "models share one program (new)" : "one program per model (before)", wall, cpu,
                        build_ms, programs);
            best_wall[shared] = std::min(best_wall[shared], wall);
            best_cpu[shared] = std::min(best_cpu[shared], cpu);
        }
    std::printf("cold contact sheet, best of %d: %.2fx faster in wall time, %.2fx less CPU time (target 3x); "
                "load average %s\n", reps, best_wall[0] / best_wall[1], best_cpu[0] / best_cpu[1], load_average().c_str());
}

}  // namespace shadelab::bench
