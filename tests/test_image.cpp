// Image output: sRGB transfer, PNG and EXR round trips, atomic writes, refusal of NaN/Inf.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

#include "core/error.hpp"
#include "image/image.hpp"
#include "support.hpp"

using namespace shadelab;
namespace fs = std::filesystem;

TEST_CASE("sRGB transfer is the IEC 61966-2-1 piecewise curve, not gamma 2.2", "[image]") {
    CHECK(srgb_encode(0.0) == 0.0);
    CHECK(srgb_encode(1.0) == 1.0);
    CHECK(srgb_encode(0.0031308) == Approx(0.04045).epsilon(1e-4));   // the knee
    CHECK(srgb_encode(0.001) == Approx(0.01292).epsilon(1e-12));      // linear segment
    CHECK(srgb_encode(0.5) == Approx(0.735356983052449).epsilon(1e-12));
    CHECK(std::abs(srgb_encode(0.5) - std::pow(0.5, 1 / 2.2)) > 1e-3);  // differs from gamma 2.2
    for (int i = 0; i <= 1000; ++i) {
        const double x = i / 1000.0;
        CHECK(srgb_decode(srgb_encode(x)) == Approx(x).margin(1e-12));
    }
    CHECK(srgb_encode(std::nan("")) == 0.0);
    CHECK(srgb_encode(-1.0) == 0.0);
    CHECK(srgb_encode(7.0) == 1.0);
}

TEST_CASE("EXR round trip is exact linear float - PNG round trip is within 8-bit sRGB quantisation", "[image]") {
    const fs::path dir = test::scratch_dir("image");
    Image img(37, 23, 4);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            img.at(x, y, 0) = float(x) / 36.0f;
            img.at(x, y, 1) = float(y) / 22.0f;
            img.at(x, y, 2) = 0.25f;
            img.at(x, y, 3) = (x + y) % 2 ? 1.0f : 0.0f;
        }
    write_image((dir / "a.exr").string(), img);
    const Image e = read_image((dir / "a.exr").string());
    REQUIRE(e.width == 37);
    REQUIRE(e.height == 23);
    REQUIRE(e.channels == 4);
    CHECK(e.pixels == img.pixels);

    write_image((dir / "a.png").string(), img);
    const Image p = read_image((dir / "a.png").string());
    REQUIRE(p.width == 37);
    double max_err = 0.0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c) {
                // Quantisation error in encoded space is at most half a step; map it back to linear.
                const double enc = srgb_encode(img.at(x, y, c));
                const double tol = srgb_decode(std::min(1.0, enc + 0.5 / 255)) - srgb_decode(std::max(0.0, enc - 0.5 / 255));
                max_err = std::max(max_err, std::abs(p.at(x, y, c) - img.at(x, y, c)) - tol);
                CHECK(std::abs(p.at(x, y, c) - img.at(x, y, c)) <= tol + 1e-6);
            }
    CHECK(p.at(0, 0, 3) == 0.0f);
    CHECK(p.at(1, 0, 3) == 1.0f);
    // No temporary files left behind.
    for (const auto& entry : fs::directory_iterator(dir))
        CHECK(entry.path().filename().string().find(".tmp") == std::string::npos);
    fs::remove_all(dir);
}

TEST_CASE("images with NaN or Inf are refused, bad extensions named", "[image]") {
    const fs::path dir = test::scratch_dir("image");
    Image img(4, 4, 4);
    img.at(1, 1, 1) = std::nanf("");
    img.at(2, 2, 2) = INFINITY;
    REQUIRE_THROWS_WITH(write_image((dir / "bad.exr").string(), img), Catch::Contains("2 pixel values are NaN or Inf"));
    CHECK_FALSE(fs::exists(dir / "bad.exr"));
    REQUIRE_THROWS_WITH(write_image((dir / "bad.xyz").string(), Image(2, 2, 4)),
                        Catch::Contains("unsupported extension") && Catch::Contains(".png"));
    REQUIRE_THROWS_WITH(read_image((dir / "missing.png").string()), Catch::Contains("not found"));
    fs::remove_all(dir);
}

TEST_CASE("compose_image puts fragments at their pixels, background elsewhere, alpha from coverage", "[image]") {
    FragmentBuffer fb;
    fb.width = 3;
    fb.height = 2;
    fb.push_back(0, 0, 0, 0, 0, 1, 4, 1.0f);   // pixel (1, 1)
    fb.push_back(0, 0, 0, 0, 0, 1, 0, 1.0f);   // pixel (0, 0)
    const std::vector<float> rgb = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f};   // planes: r r g g b b
    const Image img = compose_image(fb, rgb, {0.05, 0.06, 0.07, 0.0});
    CHECK(img.at(1, 1, 0) == 0.1f);
    CHECK(img.at(1, 1, 1) == 0.3f);
    CHECK(img.at(1, 1, 2) == 0.5f);
    CHECK(img.at(1, 1, 3) == 1.0f);
    CHECK(img.at(0, 0, 0) == 0.2f);
    CHECK(img.at(2, 1, 0) == 0.05f);
    CHECK(img.at(2, 1, 3) == 0.0f);
}
