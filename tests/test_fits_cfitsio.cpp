// The FITS reader through cfitsio (host/image/fits.hpp): files written here with cfitsio's own writer - an empty
// primary HDU with images in extensions, BSCALE/BZERO on 16-bit data, a tile-compressed (Rice) .fz image - read
// back by index, by EXTNAME and by default, every pixel compared with what was written; a missing HDU named.
#include <catch2/catch.hpp>

#include <fitsio.h>

#include <string>
#include <vector>

#include "core/error.hpp"
#include "image/fits.hpp"
#include "support.hpp"

using namespace shadelab;

namespace {

constexpr int kW = 7, kH = 5;

// The stored value of pixel (i, j), j the stored row (FITS: bottom row first).
double stored(int i, int j) { return 3.0 * i + 100.0 * j - 250.0; }

void check(int st, const char* what) {
    if (st) {
        char text[FLEN_STATUS];
        fits_get_errstatus(st, text);
        FAIL(what << ": cfitsio " << text);
    }
}

// An image extension of kW x kH: float values stored(i, j), or int16 raw values with BSCALE 0.5, BZERO 100.
void add_image(fitsfile* f, const char* extname, bool scaled_int16) {
    int st = 0;
    long naxes[2] = {kW, kH};
    fits_create_img(f, scaled_int16 ? SHORT_IMG : FLOAT_IMG, 2, naxes, &st);
    char name[FLEN_VALUE];
    std::snprintf(name, sizeof name, "%s", extname);
    fits_update_key(f, TSTRING, "EXTNAME", name, nullptr, &st);
    std::vector<double> v;
    for (int j = 0; j < kH; ++j)
        for (int i = 0; i < kW; ++i) v.push_back(stored(i, j));
    if (scaled_int16) {
        double bscale = 0.5, bzero = 100.0;
        fits_update_key(f, TDOUBLE, "BSCALE", &bscale, nullptr, &st);
        fits_update_key(f, TDOUBLE, "BZERO", &bzero, nullptr, &st);
        fits_set_bscale(f, 1.0, 0.0, &st);   // write the raw integers as they are
        std::vector<short> raw(v.begin(), v.end());
        fits_write_img(f, TSHORT, 1, raw.size(), raw.data(), &st);
    } else {
        std::vector<float> fl(v.begin(), v.end());
        fits_write_img(f, TFLOAT, 1, fl.size(), fl.data(), &st);
    }
    check(st, extname);
}

// Every pixel of `img` equals a * stored(i, j) + b, rows flipped (row 0 in memory is the top row).
void check_pixels(const Image& img, double a, double b) {
    REQUIRE(img.width == kW);
    REQUIRE(img.height == kH);
    int wrong = 0;
    for (int j = 0; j < kH; ++j)
        for (int i = 0; i < kW; ++i) {
            const double want = a * stored(i, j) + b;
            if (img.at(i, kH - 1 - j, 0) != Approx(want).margin(1e-6) || img.at(i, kH - 1 - j, 1) != 1.0f) ++wrong;
        }
    CHECK(wrong == 0);
}

}  // namespace

TEST_CASE("FITS via cfitsio: extension HDUs by index, by name and by default, BSCALE/BZERO, tile-compressed .fz",
          "[fits]") {
    const auto dir = test::scratch_dir("fits-cfitsio");
    const std::string ext = (dir / "ext.fits").string(), fz = (dir / "comp.fz").string();
    {
        fitsfile* f = nullptr;
        int st = 0;
        fits_create_file(&f, ("!" + ext).c_str(), &st);
        fits_create_img(f, FLOAT_IMG, 0, nullptr, &st);   // empty primary HDU
        check(st, "primary");
        add_image(f, "SCI", false);
        add_image(f, "ERR", true);
        fits_close_file(f, &st);
        check(st, "close");
    }
    std::map<std::string, std::string> kw;
    check_pixels(read_any_image(ext, &kw), 1.0, 0.0);   // the first image extension
    CHECK(kw["EXTNAME"] == "SCI");
    check_pixels(read_any_image(ext + "[SCI]"), 1.0, 0.0);
    check_pixels(read_any_image(ext + "[ERR]"), 0.5, 100.0);   // BZERO + BSCALE * raw
    check_pixels(read_any_image(ext + "[2]"), 0.5, 100.0);
    CHECK(is_fits_path(ext + "[ERR]"));
    CHECK(is_fits_path(fz));
    CHECK_THROWS_WITH(read_any_image(ext + "[NOPE]"), Catch::Contains("ext.fits[NOPE]") && Catch::Contains("not there"));
    CHECK_THROWS_WITH(read_any_image((dir / "gone.fits").string() + "[1]"), Catch::Contains("not found"));
    {
        fitsfile* f = nullptr;
        int st = 0;
        fits_create_file(&f, ("!" + fz).c_str(), &st);
        fits_set_compression_type(f, RICE_1, &st);
        check(st, "compression");
        long naxes[2] = {kW, kH};
        fits_create_img(f, LONG_IMG, 2, naxes, &st);
        std::vector<int> v;
        for (int j = 0; j < kH; ++j)
            for (int i = 0; i < kW; ++i) v.push_back(int(stored(i, j)));
        fits_write_img(f, TINT, 1, v.size(), v.data(), &st);
        int compressed = fits_is_compressed_image(f, &st);
        fits_close_file(f, &st);
        check(st, "fz");
        REQUIRE(compressed == 1);   // a tile-compressed HDU (a binary table holding the tiles)
    }
    check_pixels(read_any_image(fz), 1.0, 0.0);
}
