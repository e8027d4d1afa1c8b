// core_probe: the core speed probe of bench_util.hpp on its own, for scripts/speed_report.py, which runs it
// before and after every bench so that docs/speed.md says how fast the cores really were (the load average
// cannot see a host that shares them with other machines).
//
// usage: core_probe [--threads N] [--seconds S] [--rounds R]
// Prints one line: "core speed probe: <G adds/s alone> alone, <of each thread at once> at once G adds/s (...)".
// Exit 0; 2 for a bad option.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>

#include "bench_util.hpp"

int main(int argc, char** argv) {
    unsigned threads = 0;
    double seconds = 0.05;
    int rounds = 4;
    CLI::App app{"core_probe: how fast each core runs a chain of dependent additions, all at once (on an idle core: "
                 "its clock in GHz); docs/speed.md"};
    app.add_option("--threads", threads, "Threads at once (0: one a hardware thread)")
        ->capture_default_str()->check(CLI::Range(0u, 1024u));
    app.add_option("--seconds", seconds, "How long each thread adds, each time")
        ->capture_default_str()->check(CLI::Range(0.001, 60.0));
    app.add_option("--rounds", rounds, "Alone and at once in turn, this many times (the best of each is kept)")
        ->capture_default_str()->check(CLI::Range(1, 1000));
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);
        std::cerr << "core_probe: error: " << e.what() << " (see core_probe --help)\n";
        return 2;
    }
    std::printf("%s\n", shadelab::bench::core_probe(threads, seconds, rounds).line().c_str());
    return 0;
}
