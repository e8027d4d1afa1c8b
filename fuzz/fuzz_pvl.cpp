// libFuzzer target: ISIS3 photometric parameter files (PVL). The input is the file: the PVL reader (blocks,
// quoted strings with '-' continuations, lists, units, comments), then the law it names with every parameter's
// range check and the empirical tables. A law that is accepted must evaluate to a finite value at every
// geometry of a small grid: the photometry promise is no NaN/Inf from valid input.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "fuzz_common.hpp"
#include "photometry/isis.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace shadelab::photometry;
    const auto law = shadelab::fuzz::load_input(data, size, "params.pvl", law_from_pvl_file);
    if (!law) return 0;
    for (double g : {0.0, 30.0, 90.0, 150.0, 180.0})
        for (double i : {0.0, 45.0, 89.0, 90.0})
            for (double e : {0.0, 60.0, 90.0})
                if (!std::isfinite(evaluate_reference(*law, Geometry{g, i, e}))) __builtin_trap();
    return 0;
}
