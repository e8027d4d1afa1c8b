// Image output: sRGB transfer, PNG and EXR round trips, atomic writes, refusal of NaN/Inf.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <limits>

#include "core/error.hpp"
#include "image/image.hpp"
#include "image/exr_writer.hpp"
#include "image/image_io.hpp"
#include "image/png_writer.hpp"
#include "support.hpp"

#include <png.h>

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

namespace {

// Every `step`-th pixel from `first` of a w x h image covered, composed twice: fragments in pixel order (the
// parallel path) and the same fragments in reverse order (the one-thread scatter). Colour of pixel p's fragment:
// channel c = (p % mod) / mod + c. Background (0.25, 0.5, 0.75, 0.125).
struct ComposedTwice {
    FragmentBuffer rev;
    std::vector<float> rgb_rev;
    Image in_order, reversed;
};
ComposedTwice compose_in_both_orders(int w, int h, int first, int step, int mod) {
    ComposedTwice r;
    FragmentBuffer fwd;
    fwd.width = r.rev.width = w;
    fwd.height = r.rev.height = h;
    std::vector<int> covered;
    for (int p = first; p < w * h; p += step) covered.push_back(p);
    for (int p : covered) fwd.push_back(0, 0, 0, 0, 0, 1, p, 1.0f);
    for (auto it = covered.rbegin(); it != covered.rend(); ++it) r.rev.push_back(0, 0, 0, 0, 0, 1, *it, 1.0f);
    const std::size_t n = covered.size();
    std::vector<float> rgb_fwd(3 * n);
    r.rgb_rev.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < 3; ++c) {
            rgb_fwd[c * n + i] = float(covered[i] % mod) / float(mod) + float(c);
            r.rgb_rev[c * n + (n - 1 - i)] = rgb_fwd[c * n + i];
        }
    r.in_order = compose_image(fwd, rgb_fwd, {0.25, 0.5, 0.75, 0.125});
    r.reversed = compose_image(r.rev, r.rgb_rev, {0.25, 0.5, 0.75, 0.125});
    return r;
}

// How many elements of a differ from b's (b as long as a).
template <class T>
std::size_t differing(const std::vector<T>& a, const std::vector<T>& b) {
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i) differ += a[i] != b[i];
    return differ;
}

std::size_t values_differing(const Image& a, const Image& b) { return differing(a.pixels, b.pixels); }

}  // namespace

TEST_CASE("compose_image in parallel (fragments in pixel order) equals the one-thread scatter on a large image", "[image]") {
    // 500 x 400 (3.2 MB: ordinary stores, on more than one thread) with every third pixel covered: the two paths
    // must give equal images value for value; then 1000 x 700 (11 MB, streamed stores, image.cpp's
    // kStreamImageBytes), where the checks below look at single pixels too.
    const ComposedTwice small = compose_in_both_orders(500, 400, 0, 3, 997);
    REQUIRE(small.in_order.pixels.size() == small.reversed.pixels.size());
    CHECK(values_differing(small.in_order, small.reversed) == 0);
    const ComposedTwice r = compose_in_both_orders(1000, 700, 0, 3, 997);
    const Image& a = r.in_order;
    REQUIRE(a.pixels.size() == r.reversed.pixels.size());
    CHECK(values_differing(a, r.reversed) == 0);
    CHECK(a.at(3, 0, 3) == 1.0f);     // pixel 3: covered
    CHECK(a.at(4, 0, 3) == 0.125f);   // pixel 4: background alpha
    CHECK(a.at(4, 0, 1) == 0.5f);
    // A fragment outside the image is an error, not a write out of bounds.
    FragmentBuffer bad = r.rev;
    bad.pixel[0] = 1000 * 700;
    CHECK_THROWS_WITH(compose_image(bad, r.rgb_rev, {0, 0, 0, 0}), Catch::Contains("outside the 1000x700 image"));
}

TEST_CASE("compose_image of an image past the streamed-store size (2048 x 2048, 64 MB) equals the one-thread scatter",
          "[image]") {
    // Images of 4 MB and more (64 MB until 2026-12-05) are written with non-temporal stores (image.cpp,
    // kStreamImageBytes): the same check as above at a size that takes that path too, every fifth pixel from
    // pixel 1 covered.
    const int npix = 2048 * 2048;
    const ComposedTwice r = compose_in_both_orders(2048, 2048, 1, 5, 1009);
    const Image& a = r.in_order;
    REQUIRE(a.pixels.size() == std::size_t(npix) * 4);
    REQUIRE(a.pixels.size() == r.reversed.pixels.size());
    CHECK(values_differing(a, r.reversed) == 0);
    CHECK(a.at(0, 0, 3) == 0.125f);   // pixel 0: background
    CHECK(a.at(0, 0, 2) == 0.75f);
    CHECK(a.at(1, 0, 3) == 1.0f);     // pixel 1: covered, its colour
    CHECK(a.at(1, 0, 1) == float(1 % 1009) / 1009.0f + 1.0f);
    CHECK(a.at(2047, 2047, 3) == ((npix - 1) % 5 == 1 ? 1.0f : 0.125f));
}

TEST_CASE("compose_image_into reusing an image of another size and content equals a fresh compose_image", "[image]") {
    // Fragments in pixel order on 1000 x 700 (every 5th pixel, plus a run of 300 adjacent ones and the last
    // pixel), composed into an image that held a larger frame, then a smaller one, then the same frame again:
    // every value must equal the fresh image's (no stale pixel survives, the background fills every gap).
    FragmentBuffer fb;
    fb.width = 1000;
    fb.height = 700;
    const int npix = 1000 * 700;
    std::vector<int> covered;
    for (int p = 0; p < npix; p += 5) covered.push_back(p);
    for (int p = 350001; p < 350301; ++p)
        if (p % 5 != 0) covered.push_back(p);
    covered.push_back(npix - 1);
    std::sort(covered.begin(), covered.end());
    for (int p : covered) fb.push_back(0, 0, 0, 0, 0, 1, p, 1.0f);
    const std::size_t n = covered.size();
    std::vector<float> rgb(3 * n);
    for (std::size_t i = 0; i < 3 * n; ++i) rgb[i] = float(i % 1009) / 1009.0f;
    const glm::dvec4 bg{0.25, 0.5, 0.75, 0.125};
    const Image fresh = compose_image(fb, rgb, bg);
    Image reused(1200, 800, 4);
    std::fill(reused.pixels.begin(), reused.pixels.end(), 9.0f);
    for (int round = 0; round < 3; ++round) {
        if (round == 1) {   // a smaller frame in between: one fragment on a 10 x 10 image
            FragmentBuffer small;
            small.width = small.height = 10;
            small.push_back(0, 0, 0, 0, 0, 1, 7, 1.0f);
            compose_image_into(small, {0.5f, 0.5f, 0.5f}, bg, reused);
            CHECK(reused.pixels.size() == 10u * 10u * 4u);
            CHECK(reused.at(7, 0, 3) == 1.0f);
            CHECK(reused.at(8, 0, 3) == 0.125f);
        }
        compose_image_into(fb, rgb, bg, reused);
        INFO("round " << round);
        REQUIRE(reused.width == 1000);
        REQUIRE(reused.height == 700);
        REQUIRE(reused.channels == 4);
        REQUIRE(reused.pixels.size() == fresh.pixels.size());
        CHECK(values_differing(reused, fresh) == 0);
    }
    CHECK(fresh.at(999, 699, 3) == 1.0f);   // the last pixel is covered
    CHECK(fresh.at(1, 0, 3) == 0.125f);
}

namespace {

std::string file_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The message write_image(path, img) refuses with, or "" when it writes the file.
std::string write_refusal(const std::string& path, const Image& img) {
    try {
        write_image(path, img);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

// compose_image_srgb8_into codes each pixel as it composes (pipeline::resolve, when every colour output is 8-bit):
// the bytes must be encode_srgb8's of compose_image's float image, whatever the values (negative, -0, denormal,
// above 1, a colour equal to the background's), the background (zero, grey, -0 and above 1) and the order.
TEST_CASE("compose_image_srgb8_into equals encode_srgb8 of compose_image byte for byte, and writes the same files",
          "[image]") {
    const int w = 1000, h = 700, npix = w * h;
    FragmentBuffer fwd, rev;
    fwd.width = rev.width = w;
    fwd.height = rev.height = h;
    std::vector<int> covered;
    for (int p = 1; p < npix; p += 3) covered.push_back(p);
    for (int p : covered) fwd.push_back(0, 0, 0, 0, 0, 1, p, 1.0f);
    for (auto it = covered.rbegin(); it != covered.rend(); ++it) rev.push_back(0, 0, 0, 0, 0, 1, *it, 1.0f);
    const std::size_t n = covered.size();
    const float specials[] = {0.0f, -0.0f, -0.5f, 1e-40f, 0.0031308f, 0.5f, 1.0f, 1.5f, 0.25f, 0.75f};
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-0.1f, 1.1f);
    std::vector<float> rgb_fwd(3 * n), rgb_rev(3 * n);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < 3; ++c) {
            const float v = i % 7 == 0 ? specials[(i / 7 + c) % 10] : u(rng);
            rgb_fwd[c * n + i] = v;
            rgb_rev[c * n + (n - 1 - i)] = v;
        }
    const fs::path dir = test::scratch_dir("image_coded");
    Srgb8Image reused;
    reused.bytes.assign(1200u * 800u * 4u, 77);
    for (const glm::dvec4& bg : {glm::dvec4(0.0), glm::dvec4(0.25, 0.5, 0.75, 0.125), glm::dvec4(-0.0, 2.0, 0.5, 1.0)}) {
        const std::vector<unsigned char> want = encode_srgb8(compose_image(fwd, rgb_fwd, bg));
        compose_image_srgb8_into(fwd, rgb_fwd, bg, "x.png", reused);
        CAPTURE(bg[0], bg[1], bg[2], bg[3]);
        REQUIRE(reused.width == w);
        REQUIRE(reused.height == h);
        REQUIRE(reused.channels == 4);
        REQUIRE(reused.bytes.size() == want.size());
        CHECK(differing(reused.bytes, want) == 0);
        Srgb8Image any_order;
        compose_image_srgb8_into(rev, rgb_rev, bg, "x.png", any_order);
        REQUIRE(any_order.bytes.size() == want.size());
        CHECK(differing(any_order.bytes, want) == 0);
    }
    // The files: the same bytes as write_image of the float image, through libpng (.png) and OpenImageIO (.jpg).
    const glm::dvec4 bg(0.25, 0.5, 0.75, 0.125);
    const Image linear = compose_image(fwd, rgb_fwd, bg);
    compose_image_srgb8_into(fwd, rgb_fwd, bg, "x.png", reused);
    for (const char* ext : {".png", ".jpg"}) {
        write_image((dir / (std::string("coded") + ext)).string(), reused);
        write_image((dir / (std::string("linear") + ext)).string(), linear);
        const std::string a = file_bytes(dir / (std::string("coded") + ext));
        CAPTURE(ext);
        CHECK(a.size() > 1000);
        CHECK((a == file_bytes(dir / (std::string("linear") + ext))));   // (not printed: a whole file)
    }
    CHECK_THROWS_WITH(write_image((dir / "coded.exr").string(), reused), Catch::Contains("a format of linear floats"));
    // NaN and Inf: refused with write_image's message and count (a NaN background counts in every pixel it fills).
    std::vector<float> bad = rgb_fwd;
    bad[5] = std::nanf("");
    bad[2 * n + 9] = INFINITY;
    const std::string path = (dir / "bad.png").string();
    const std::string want_bad = write_refusal(path, compose_image(fwd, bad, bg));
    CHECK_THAT(want_bad, Catch::Contains("2 pixel values are NaN or Inf"));
    CHECK_THROWS_WITH(compose_image_srgb8_into(fwd, bad, bg, path, reused), want_bad);
    const glm::dvec4 nan_bg(0.1, std::nan(""), 0.1, 1.0);
    const std::string want_bg = write_refusal(path, compose_image(fwd, rgb_fwd, nan_bg));
    CHECK_THAT(want_bg, Catch::Contains(std::to_string(npix - int(n)) + " pixel values are NaN or Inf"));
    CHECK_THROWS_WITH(compose_image_srgb8_into(fwd, rgb_fwd, nan_bg, path, reused), want_bg);
    CHECK_THROWS_WITH(compose_image_srgb8_into(rev, rgb_rev, nan_bg, path, reused), want_bg);
    CHECK_FALSE(fs::exists(path));
    fs::remove_all(dir);
}

namespace {

// The message compose_image_srgb8_into refuses with for `path`, or "" when it composes.
std::string compose_refusal(const FragmentBuffer& fb, const std::vector<float>& rgb, const glm::dvec4& bg,
                            const std::string& path) {
    Srgb8Image img;
    try {
        compose_image_srgb8_into(fb, rgb, bg, path, img);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

// render writes its PNG with write_image_composed, which composes each deflate piece's rows inside the piece: the
// file must be write_image's of compose_image_srgb8_into's image, byte for byte, in pieces or not (1 thread, a
// .jpg, fragments out of pixel order), and NaN or Inf refused with compose_image_srgb8_into's message.
TEST_CASE("write_image_composed writes write_image's file of the composed image byte for byte, and refuses NaN as it", "[image]") {
    const int w = 1100, h = 900, npix = w * h;   // 4 MB of rows: four pieces
    FragmentBuffer fwd, rev;
    fwd.width = rev.width = w;
    fwd.height = rev.height = h;
    std::vector<int> covered;
    for (int p = 0; p < npix; p += (p / w) % 50 < 20 ? 1 : 3) covered.push_back(p);   // solid bands, sparse bands
    for (int p : covered) fwd.push_back(0, 0, 0, 0, 0, 1, p, 1.0f);
    for (auto it = covered.rbegin(); it != covered.rend(); ++it) rev.push_back(0, 0, 0, 0, 0, 1, *it, 1.0f);
    const std::size_t n = covered.size();
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-0.1f, 1.1f);
    std::vector<float> rgb(3 * n), rgb_rev(3 * n);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < 3; ++c) rgb_rev[c * n + (n - 1 - i)] = rgb[c * n + i] = u(rng);
    const fs::path dir = test::scratch_dir("image_composed");
    ImageWriteOptions one, two;
    one.png_threads = 1;
    two.png_threads = 2;
    CHECK(png_composed_in_pieces("a.png", w, h, two));
    CHECK_FALSE(png_composed_in_pieces("a.png", w, h, one));
    CHECK_FALSE(png_composed_in_pieces("a.jpg", w, h, two));
    CHECK_FALSE(png_composed_in_pieces("a.png", 700, 700, two));   // under 2 MB of rows: libpng's stream
    int cases = 0;
    for (const glm::dvec4& bg : {glm::dvec4(0.0), glm::dvec4(0.25, 0.5, 0.75, 0.125), glm::dvec4(-0.0, 2.0, 0.5, 1.0)}) {
        Srgb8Image coded;
        compose_image_srgb8_into(fwd, rgb, bg, "x.png", coded);
        for (const ImageWriteOptions& o : {two, one}) {
            for (const char* ext : {".png", ".jpg"}) {
                CAPTURE(bg[0], bg[1], bg[2], bg[3], o.png_threads, ext);
                const fs::path want = dir / (std::string("want") + ext), ours = dir / (std::string("ours") + ext);
                write_image(want.string(), coded, o);
                write_image_composed(ours.string(), fwd, rgb, bg, o);
                const std::string a = file_bytes(ours);
                CHECK(a.size() > 1000);
                CHECK((a == file_bytes(want)));   // (not printed: a whole file)
                write_image_composed(ours.string(), rev, rgb_rev, bg, o);   // any order: composed first
                CHECK((file_bytes(ours) == a));
                ++cases;
            }
        }
    }
    CHECK(cases == 12);
    // NaN and Inf: compose_image_srgb8_into's refusal (the full count), and no file
    std::vector<float> bad = rgb;
    bad[n - 5] = std::nanf("");    // in the last piece
    bad[2 * n + 9] = -INFINITY;    // in the first
    const glm::dvec4 bg(0.25, 0.5, 0.75, 1.0), nan_bg(0.1, std::nan(""), 0.1, 1.0);
    const std::string path = (dir / "bad.png").string();
    const std::string want_bad = compose_refusal(fwd, bad, bg, path), want_bg = compose_refusal(fwd, rgb, nan_bg, path);
    CHECK_THAT(want_bad, Catch::Contains("2 pixel values are NaN or Inf"));
    CHECK_THAT(want_bg, Catch::Contains(" pixel values are NaN or Inf"));
    for (const ImageWriteOptions& o : {two, one}) {
        CAPTURE(o.png_threads);
        CHECK_THROWS_WITH(write_image_composed(path, fwd, bad, bg, o), want_bad);
        CHECK_THROWS_WITH(write_image_composed(path, fwd, rgb, nan_bg, o), want_bg);
    }
    std::size_t left = 0;
    for (const auto& e : fs::directory_iterator(dir))   // (want.* and ours.* are the files written above)
        left += e.path().stem() != "want" && e.path().stem() != "ours" ? 1 : 0;
    CHECK(left == 0);
    fs::remove_all(dir);
}

TEST_CASE("8-bit writes count NaN and Inf while coding: refused in the last row block too, nothing left behind", "[image]") {
    // 8-bit formats find NaN/Inf while coding row blocks (about 1 MB each) as they are written: a bad value in
    // the first block, in the last one and on a 1-channel image must all be refused with the full count,
    // leaving neither the target nor a temporary file; a clean image of the same size is written.
    // PNG's pieces (2.4 MB of rows here: three pieces) stop all their threads at the first one: 2 threads, and
    // libpng's single stream (1 thread).
    const fs::path dir = test::scratch_dir("image_nan8");
    Image big(1024, 600, 4);   // 4 KB rows: 256 rows a block, so the last value lies in the third block
    for (float& v : big.pixels) v = 0.5f;
    for (int threads : {2, 1}) {
        INFO(threads << " PNG threads");
        ImageWriteOptions o;
        o.png_threads = threads;
        big.pixels.back() = std::nanf("");
        big.at(3, 0, 0) = -INFINITY;
        REQUIRE_THROWS_WITH(write_image((dir / "late.png").string(), big, o), Catch::Contains("2 pixel values are NaN or Inf"));
        big.at(3, 0, 0) = 0.5f;
        REQUIRE_THROWS_WITH(write_image((dir / "late.png").string(), big, o), Catch::Contains("1 pixel values are NaN or Inf"));
        REQUIRE_THROWS_WITH(write_image((dir / "late.jpg").string(), big, o), Catch::Contains("1 pixel values are NaN or Inf"));
    }
    Image grey(5, 3, 1);
    grey.at(4, 2, 0) = INFINITY;
    REQUIRE_THROWS_WITH(write_image((dir / "grey.png").string(), grey), Catch::Contains("1 pixel values are NaN or Inf"));
    std::size_t left = 0;
    for (const auto& e : fs::directory_iterator(dir)) left += e.is_regular_file() ? 1 : 0;
    CHECK(left == 0);
    big.pixels.back() = 0.25f;
    write_image((dir / "late.png").string(), big);
    const Image back = read_image((dir / "late.png").string());
    CHECK(back.at(1023, 599, 3) == Approx(64.0 / 255.0).margin(1e-6));   // alpha 0.25 -> code 64
    fs::remove_all(dir);
}

TEST_CASE("the 8-bit sRGB table gives lround(255 srgb_encode(v)) for every 97th float in [0, 1] and around each step", "[image]") {
    // The direct evaluation of the IEC 61966-2-1 curve, rounded as write_image always did.
    const auto direct = [](float v) { return int(std::lround(srgb_encode(double(v)) * 255.0)); };
    const auto of_bits = [](std::uint32_t b) {
        float f;
        std::memcpy(&f, &b, sizeof f);
        return f;
    };
    std::size_t checked = 0, wrong = 0;
    const std::uint32_t one = 0x3F800000u;
    for (std::uint32_t b = 0; b <= one; b += 97, ++checked) wrong += srgb8_code(of_bits(b)) != direct(of_bits(b));
    // Around every step of the code (found by bisection here, independently of the table): 64 floats each side.
    for (int k = 1; k <= 255; ++k) {
        std::uint32_t lo = 0, hi = one;
        while (hi - lo > 1) {
            const std::uint32_t mid = lo + (hi - lo) / 2;
            (direct(of_bits(mid)) >= k ? hi : lo) = mid;
        }
        for (std::uint32_t b = hi - 64; b <= hi + 64; ++b, ++checked) wrong += srgb8_code(of_bits(b)) != direct(of_bits(b));
    }
    INFO(checked << " floats checked, " << wrong << " wrong");
    CHECK(checked > 10000000);
    CHECK(wrong == 0);
    // Out of [0, 1], NaN and negative zero.
    CHECK(srgb8_code(-1.0f) == 0);
    CHECK(srgb8_code(-0.0f) == 0);
    CHECK(srgb8_code(std::nanf("")) == 0);
    CHECK(srgb8_code(1.0f) == 255);
    CHECK(srgb8_code(1e30f) == 255);
    CHECK(srgb8_code(std::numeric_limits<float>::infinity()) == 255);
}

namespace {

// The file OpenImageIO 2.4 writes for the same pixels and settings, through the image plug-in's writer: 8-bit
// sRGB codes (PNG) or floats (EXR).
void write_with_oiio(const fs::path& file, const Image& img, bool srgb8, const ImageWriteOptions& o) {
    const image_io::Plugin& io = image_io::plugin();
    std::string why;
    bool no_format = false;
    image_io::Writer* w = io.writer_open(file.string(), image_io::write_spec(img, srgb8, o), why, no_format);
    REQUIRE(w != nullptr);
    if (srgb8) {
        const std::vector<unsigned char> codes = encode_srgb8(img);
        REQUIRE(io.writer_rows8(w, 0, img.height, codes.data()));
    } else {
        REQUIRE(io.writer_float(w, img.pixels.data()));
    }
    REQUIRE(io.writer_close(w, why));
}

}  // namespace

TEST_CASE("PNG by libpng equals OpenImageIO's file byte for byte, 1-4 channels, zlib levels and filters", "[image]") {
    // write_image writes PNG without the image plug-in (image/png_writer.hpp); the file must be the one the
    // OpenImageIO writer it replaced gives for the same pixels and settings: chunks, metadata and compressed data.
    const fs::path dir = test::scratch_dir("image_png_direct");
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-0.1f, 1.2f);
    const ImageWriteOptions defaults;
    const ImageWriteOptions settings[] = {defaults, {6, 0, "zips"}, {9, 8, "zips"}, {0, 248, "zips"}, {1, 16, "zips"},
                                           {1, 128, "zips"}};
    int cases = 0;
    for (int channels = 1; channels <= 4; ++channels) {
        for (ImageWriteOptions o : settings) {
            o.png_mem_level = 8;   // OpenImageIO leaves zlib's memLevel at libpng's 8 (shadelab's default is 6)
            Image img(37 + channels, 300 + 11 * channels, channels);   // rows of odd widths
            for (float& v : img.pixels) v = u(rng);
            for (int x = 0; x < img.width; ++x) img.at(x, 5, 0) = 0.0f;   // a run of zeros (the background)
            const fs::path ours = dir / "ours.png", theirs = dir / "theirs.png";
            write_image(ours.string(), img, o);
            write_with_oiio(theirs, img, true, o);
            const std::string a = file_bytes(ours), b = file_bytes(theirs);
            INFO("channels " << channels << ", zlib level " << o.png_level << ", filter " << o.png_filter);
            REQUIRE(a.size() > 100);
            CHECK(a == b);
            ++cases;
        }
    }
    CHECK(cases == 24);
    // a large image: several of the pipeline's row blocks (about 1 MB each)
    Image big(1500, 700, 4);
    for (float& v : big.pixels) v = u(rng);
    ImageWriteOptions mem8;
    mem8.png_mem_level = 8;
    mem8.png_threads = 1;   // libpng's own stream (more threads deflate this image in pieces: the next test)
    write_image((dir / "big.png").string(), big, mem8);
    write_with_oiio(dir / "big_oiio.png", big, true, defaults);
    CHECK(file_bytes(dir / "big.png") == file_bytes(dir / "big_oiio.png"));
    // shadelab's default memLevel (6): another deflate stream, the same pixels
    ImageWriteOptions mem6;
    mem6.png_threads = 1;
    write_image((dir / "big6.png").string(), big, mem6);
    CHECK(file_bytes(dir / "big6.png") != file_bytes(dir / "big_oiio.png"));
    const Image a = read_image((dir / "big6.png").string()), b = read_image((dir / "big_oiio.png").string());
    REQUIRE(a.pixels.size() == b.pixels.size());
    CHECK(values_differing(a, b) == 0);
    fs::remove_all(dir);
}

namespace {

// A PNG's 8-bit samples as libpng decodes them (its simplified API, which checks every chunk's CRC and the zlib
// stream's Adler-32), in the file's own layout; empty when libpng refuses the file.
std::vector<unsigned char> png_samples(const fs::path& file, int& width, int& height, int& channels) {
    png_image im{};
    im.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&im, file.string().c_str())) return {};
    width = int(im.width);
    height = int(im.height);
    channels = int(PNG_IMAGE_SAMPLE_CHANNELS(im.format));
    std::vector<unsigned char> out(PNG_IMAGE_SIZE(im));
    if (!png_image_finish_read(&im, nullptr, out.data(), 0, nullptr)) return {};
    return out;
}

// `bytes` (width x height x channels) written by PngWriter: row by row through libpng (piece_bytes 0), or with
// image_in_pieces in pieces of piece_bytes on `threads` threads.
void write_png_bytes(const fs::path& file, const std::vector<unsigned char>& bytes, int width, int height,
                     int channels, int level, int filter, std::size_t piece_bytes, int threads) {
    PngWriter png(file.string(), width, height, channels, level, filter, 6);
    REQUIRE(png.ok());
    const std::size_t row = std::size_t(width) * std::size_t(channels);
    if (piece_bytes == 0) {
        REQUIRE(png.rows(0, height, bytes.data()));
    } else {
        const PngRowSource rows = [&](int y0, int y1, unsigned char* scratch) {   // copied, as a float image's
            std::copy(bytes.begin() + std::ptrdiff_t(std::size_t(y0) * row),
                      bytes.begin() + std::ptrdiff_t(std::size_t(y1) * row), scratch);
            return static_cast<const unsigned char*>(scratch);
        };
        REQUIRE(png.image_in_pieces(rows, threads, piece_bytes));
    }
    REQUIRE(png.finish());
}

}  // namespace

TEST_CASE("PNG deflated in pieces on several threads: one piece is libpng's file byte for byte, many decode to the same samples", "[image]") {
    // image_in_pieces joins raw deflate pieces into one zlib stream (sync flushes, each piece's dictionary the
    // 32 KB before it, the Adler-32s combined): with one piece it must be libpng's own file, byte for byte;
    // with many, on 1-3 threads, a file libpng reads back (CRCs and Adler-32 checked) to the same samples.
    const fs::path dir = test::scratch_dir("image_png_pieces");
    std::mt19937 rng(11);
    int cases = 0;
    struct Shape {
        int width, height, channels;
    };
    // rows of odd widths; a row longer than a piece (pieces of one row); one column. Each image more than 16 KB
    // of rows: libpng narrows the window of a smaller one, and its file is then another (valid) stream.
    for (const Shape& sh : {Shape{301, 220, 4}, Shape{157, 190, 3}, Shape{4000, 7, 1}, Shape{1, 9000, 2}}) {
        std::vector<unsigned char> bytes(std::size_t(sh.width) * std::size_t(sh.height) * std::size_t(sh.channels));
        // smooth ramps with noise and runs of zeros: matches near and far, across the pieces' boundaries
        for (std::size_t i = 0; i < bytes.size(); ++i)
            bytes[i] = (i / 97) % 5 == 0 ? 0 : static_cast<unsigned char>((i / 13) + (rng() % 7));
        for (int filter : {32, 8}) {
            for (int level : {1, 6, 0}) {
                INFO(sh.width << "x" << sh.height << "x" << sh.channels << ", filter " << filter << ", level " << level);
                write_png_bytes(dir / "rows.png", bytes, sh.width, sh.height, sh.channels, level, filter, 0, 1);
                write_png_bytes(dir / "one.png", bytes, sh.width, sh.height, sh.channels, level, filter,
                                std::size_t(1) << 30, 2);
                // (zlib's stored blocks, level 0, fall where libpng's output buffer fills, not where ours does)
                if (level > 0)
                    CHECK((file_bytes(dir / "one.png") == file_bytes(dir / "rows.png")));   // (not printed: a whole file)
                for (int threads : {1, 2, 3}) {
                    INFO(threads << " threads");
                    write_png_bytes(dir / "many.png", bytes, sh.width, sh.height, sh.channels, level, filter, 5000,
                                    threads);
                    int w = 0, h = 0, c = 0;
                    const std::vector<unsigned char> back = png_samples(dir / "many.png", w, h, c);
                    REQUIRE(back.size() == bytes.size());
                    CHECK((w == sh.width && h == sh.height && c == sh.channels));
                    CHECK(differing(back, bytes) == 0);
                    CHECK(file_bytes(dir / "many.png") != file_bytes(dir / "rows.png"));   // pieces, not one stream
                    ++cases;
                }
            }
        }
    }
    CHECK(cases == 72);
    // write_image: pieces on two threads by the options, the same samples as libpng's own stream
    Image img(1500, 800, 4);
    std::uniform_real_distribution<float> u(-0.1f, 1.2f);
    for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = (i / 4096) % 3 == 0 ? 0.2f : u(rng);
    ImageWriteOptions one, two;
    one.png_threads = 1;
    two.png_threads = 2;
    write_image((dir / "one.png").string(), img, one);
    write_image((dir / "two.png").string(), img, two);
    const std::string a = file_bytes(dir / "one.png"), b = file_bytes(dir / "two.png");
    CHECK(a != b);
    CHECK(double(b.size()) < 1.01 * double(a.size()));   // the dictionaries keep the pieces' matches
    int w = 0, h = 0, c = 0;
    const std::vector<unsigned char> sa = png_samples(dir / "one.png", w, h, c), sb = png_samples(dir / "two.png", w, h, c);
    REQUIRE(sa.size() == img.pixels.size());
    REQUIRE(sb.size() == sa.size());
    CHECK(differing(sa, sb) == 0);
    fs::remove_all(dir);
}

namespace {

// The file with the value of its capDate attribute (the second it was written) blanked.
std::string without_capture_date(std::string bytes) {
    const std::string key("capDate\0string\0", 15);
    const std::size_t at = bytes.find(key);
    if (at != std::string::npos && at + 15 + 4 <= bytes.size()) {
        std::uint32_t n = 0;
        std::memcpy(&n, bytes.data() + at + 15, 4);   // EXR is little-endian, as this host
        for (std::size_t i = at + 19; i < at + 19 + n && i < bytes.size(); ++i) bytes[i] = '-';
    }
    return bytes;
}

}  // namespace

TEST_CASE("EXR by OpenEXR equals OpenImageIO's file but for the capture date, 1-4 channels, every compression",
          "[image]") {
    // write_image writes EXR without the image plug-in (image/exr_writer.hpp) for these compressions; the file
    // must be the one the OpenImageIO writer it replaced gives for the same floats: header, offsets, chunks.
    const fs::path dir = test::scratch_dir("image_exr_direct");
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-2.0f, 40.0f);
    int cases = 0;
    // (dwaa and dwab are written by OpenImageIO itself, image/exr_writer.cpp says why: the same writer on both sides)
    for (const char* compression : {"zips", "zip", "none", "rle", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"}) {
        for (int channels = 1; channels <= 4; ++channels) {
            Image img(45 + channels, 70 + 3 * channels, channels);
            for (float& v : img.pixels) v = u(rng);
            ImageWriteOptions o;
            o.exr_compression = compression;
            write_image((dir / "ours.exr").string(), img, o);
            write_with_oiio(dir / "theirs.exr", img, false, o);
            INFO("compression " << compression << ", channels " << channels);
            const std::string a = without_capture_date(file_bytes(dir / "ours.exr"));
            const std::string b = without_capture_date(file_bytes(dir / "theirs.exr"));
            REQUIRE(a.size() > 300);
            CHECK(a.find("capDate") != std::string::npos);
            CHECK(a == b);
            const std::string name = compression;
            if (name == "none" || name == "rle" || name == "zips" || name == "zip" || name == "piz")   // lossless
                CHECK(read_image((dir / "ours.exr").string()).pixels == img.pixels);
            ++cases;
        }
    }
    CHECK(cases == 40);
    CHECK(exr_direct("zips", 4));
    CHECK_FALSE(exr_direct("dwaa", 4));
    CHECK_FALSE(exr_direct("zip:4", 4));
    CHECK_FALSE(exr_direct("zips", 5));
    fs::remove_all(dir);
}
