// Colour science: CIEDE2000 against the published test data, Lab round trips, known white points.
#include <catch2/catch.hpp>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>

#include "color/color.hpp"

using namespace shadelab;

TEST_CASE("CIEDE2000 matches Sharma, Wu & Dalal (2005) Table 1 to 1e-4, both orders", "[color]") {
    std::ifstream in(SHADELAB_TEST_DATA_DIR "/ciede2000_sharma2005.csv");
    REQUIRE(in);
    std::string line;
    int pairs = 0;
    double worst = 0.0;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream s(line);
        glm::dvec3 a, b;
        double expected = 0;
        s >> a.x >> a.y >> a.z >> b.x >> b.y >> b.z >> expected;
        REQUIRE(s);
        ++pairs;
        const double d1 = delta_e2000(a, b), d2 = delta_e2000(b, a);
        worst = std::max({worst, std::abs(d1 - expected), std::abs(d2 - expected)});
        INFO("pair " << pairs << ": got " << d1 << " / " << d2 << ", published " << expected);
        CHECK(std::abs(d1 - expected) < 1e-4 + 1e-12);   // published to 4 decimals: within rounding
        CHECK(std::abs(d2 - expected) < 1e-4 + 1e-12);
    }
    CHECK(pairs == 34);
    std::cout << "CIEDE2000: 34 Sharma pairs, max |difference| from the published 4-decimal values " << worst << "\n";
}

TEST_CASE("Lab of the sRGB primaries and white are the textbook values; round trips are exact", "[color]") {
    const glm::dvec3 white = lab_from_linear_srgb({1, 1, 1});
    CHECK(white.x == Approx(100.0).margin(1e-4));
    CHECK(white.y == Approx(0.0).margin(1e-3));
    CHECK(white.z == Approx(0.0).margin(1e-3));
    const glm::dvec3 black = lab_from_linear_srgb({0, 0, 0});
    CHECK(black.x == Approx(0.0).margin(1e-12));
    // sRGB red in L*a*b* (D65): (53.24, 80.09, 67.20), e.g. Lindbloom's calculator.
    const glm::dvec3 red = lab_from_linear_srgb({1, 0, 0});
    CHECK(red.x == Approx(53.24).margin(0.01));
    CHECK(red.y == Approx(80.09).margin(0.01));
    CHECK(red.z == Approx(67.20).margin(0.01));
    // Mid grey 18%: L* = 49.5.
    CHECK(lab_from_linear_srgb({0.18, 0.18, 0.18}).x == Approx(49.496).margin(0.01));

    std::mt19937_64 g(5);
    double worst = 0.0;
    for (int i = 0; i < 100000; ++i) {
        const glm::dvec3 rgb{double(g() % 100001) / 1e5, double(g() % 100001) / 1e5, double(g() % 100001) / 1e5};
        const glm::dvec3 back = linear_srgb_from_xyz(xyz_from_lab(lab_from_linear_srgb(rgb)));
        worst = std::max(worst, glm::length(back - rgb));
    }
    INFO("worst rgb -> Lab -> rgb round trip error " << worst);
    CHECK(worst < 1e-6);   // limited by the 7-digit published matrices, not the Lab step
}

TEST_CASE("Delta E is zero for equal colours, symmetric, and 76 equals the Euclidean distance", "[color]") {
    const glm::dvec3 a{50, 10, -20}, b{55, 12, -18};
    CHECK(delta_e2000(a, a) == 0.0);
    CHECK(delta_e2000(a, b) == Approx(delta_e2000(b, a)).epsilon(1e-12));
    CHECK(delta_e76(a, b) == Approx(std::sqrt(25.0 + 4.0 + 4.0)).epsilon(1e-12));
    CHECK(delta_e2000(a, b) > 0.0);
}
