// The fidelity atlas (docs/fidelity.md): the seeds' claims about which model looks like which, answered with
// fits over the default hemisphere domain, and residual plots for the interesting pairs. One call writes the
// page, its CSV tables (docs/data/fidelity/) and its pictures (docs/images/fidelity/).
#pragma once
#include <iosfwd>
#include <string>

#include "cl/runtime.hpp"

namespace shadelab::fit {

struct AtlasOptions {
    std::string docs_dir = "docs";   // fidelity.md goes here; data/fidelity and images/fidelity below it
    std::size_t samples = 65536;
    std::uint64_t seed = 1;
    std::size_t timed_fragments = std::size_t(1) << 20;
};

// Writes everything; returns the files written. Progress goes to `log`.
std::vector<std::string> write_atlas(Runtime& rt, const AtlasOptions& o, std::ostream& log);

}  // namespace shadelab::fit
