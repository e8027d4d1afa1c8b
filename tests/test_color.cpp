// Colour science: CIEDE2000 against the published test data, Lab round trips, known white points.
#include <catch2/catch.hpp>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>

#include "cl/runtime.hpp"
#include "color/color.hpp"
#include "color/color_kernel.hpp"
#include "support.hpp"

using namespace shadelab;

TEST_CASE("CIEDE2000 matches Sharma, Wu & Dalal (2005) Table 1 to 1e-4, both orders", "[color]") {
    std::ifstream in(test::kData + "/ciede2000_sharma2005.csv");
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

TEST_CASE("Lab of the sRGB primaries and white are the textbook values - round trips are exact", "[color]") {
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

TEST_CASE("the device CIEDE2000 matches the published pairs and the host double version", "[color][kernel]") {
    Runtime& rt = test::runtime();
    std::ifstream in(test::kData + "/ciede2000_sharma2005.csv");
    REQUIRE(in);
    std::vector<float> a, b;
    std::vector<double> expected;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream s(line);
        double v[7];
        for (double& x : v) s >> x;
        for (int k = 0; k < 3; ++k) {
            a.push_back(float(v[k]));
            b.push_back(float(v[3 + k]));
        }
        expected.push_back(v[6]);
    }
    const auto de = delta_e2000_lab_device(rt, a, b);
    REQUIRE(de.size() == 34);
    double worst = 0.0;
    for (std::size_t i = 0; i < de.size(); ++i) {
        worst = std::max(worst, std::abs(de[i] - expected[i]));
        INFO("pair " << i + 1 << ": device " << de[i] << ", published " << expected[i]);
        CHECK(std::abs(de[i] - expected[i]) < 1e-3);   // float: ~1e-6 relative on Lab values of ~100
    }
    std::cout << "device CIEDE2000 on Sharma's pairs: max |difference| " << worst << "\n";

    // Random linear colours, including near-black and near-neutral ones, against the host double path.
    std::mt19937_64 g(11);
    std::vector<float> ra, rb;
    std::vector<double> host;
    for (int i = 0; i < 50000; ++i) {
        glm::dvec3 x, y;
        for (int c = 0; c < 3; ++c) {
            x[c] = double(g() % 1000001) / 1e6;
            y[c] = std::clamp(x[c] * (1.0 + (double(g() % 2001) - 1000.0) / 20000.0), 0.0, 1.0);
            ra.push_back(float(x[c]));
            rb.push_back(float(y[c]));
        }
        host.push_back(delta_e2000(lab_from_linear_srgb(glm::dvec3(ra[3 * std::size_t(i)], ra[3 * std::size_t(i) + 1], ra[3 * std::size_t(i) + 2])),
                                   lab_from_linear_srgb(glm::dvec3(rb[3 * std::size_t(i)], rb[3 * std::size_t(i) + 1], rb[3 * std::size_t(i) + 2]))));
    }
    const auto dev = delta_e2000_device(rt, ra, rb);
    double max_abs = 0.0;
    for (std::size_t i = 0; i < host.size(); ++i) max_abs = std::max(max_abs, std::abs(dev[i] - host[i]));
    std::cout << "device vs host CIEDE2000 on 50k random colour pairs: max |difference| " << max_abs << "\n";
    CHECK(max_abs < 5e-4);   // measured 8.8e-5
}
