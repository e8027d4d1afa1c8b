// Whether a fit's standard errors are right, over several noisy fits: each fitted value within 3.5 standard errors
// of the true one (p = 5e-4 per parameter if the errors are right), and about 68% within one - a count the caller
// bounds from both sides, so that errors too small and too large both fail.
#pragma once
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <string>

#include "photometry/fit.hpp"

namespace shadelab::test {

struct StandardErrorTally {
    int within1 = 0, total = 0;

    // The parameter `p` of the fit of seed `seed`, whose true value is `truth`.
    void add(const photometry::FitParameter& p, double truth, std::uint64_t seed) {
        INFO("seed " << seed << " " << p.name);
        REQUIRE(p.stderr_ > 0.0);
        const double z = (p.value - truth) / p.stderr_;
        std::cout << "seed " << seed << " " << p.name << ": " << p.value << " +- " << p.stderr_ << " (true " << truth
                  << ", z " << z << ")\n";
        CHECK(std::abs(z) < 3.5);
        within1 += std::abs(z) < 1.0;
        ++total;
    }
};

}  // namespace shadelab::test
