// libFuzzer target: ISIS3 photometric parameter files (PVL). The input is the file: the PVL reader (blocks,
// quoted strings with '-' continuations, lists, units, comments), then the law it names with every parameter's
// range check and the empirical tables. A law that is accepted must evaluate to a finite value at every
// geometry of a small grid: the photometry promise is no NaN/Inf from valid input. An empirical law's tables are
// splines that ISIS continues beyond their last phase, where they may run away: every evaluation refuses such a
// row with one line (check_empirical_finite), so for those laws a refused grid is the promised outcome, and a
// grid it lets through must be finite.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/error.hpp"
#include "fuzz_common.hpp"
#include "photometry/isis.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace shadelab::photometry;
    const auto law = shadelab::fuzz::load_input(data, size, "params.pvl", law_from_pvl_file);
    if (!law) return 0;
    std::vector<Geometry> grid;
    for (double g : {0.0, 30.0, 90.0, 150.0, 180.0})
        for (double i : {0.0, 45.0, 89.0, 90.0})
            for (double e : {0.0, 60.0, 90.0}) grid.push_back(Geometry{g, i, e});
    if (law->empirical) {
        try {
            check_empirical_finite(*law, grid);
        } catch (const shadelab::Error&) {
            return 0;
        }
    }
    for (const Geometry& geo : grid)
        if (!std::isfinite(evaluate_reference(*law, geo))) __builtin_trap();
    return 0;
}
