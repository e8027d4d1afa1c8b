// Planetary rasters through GDAL (host/image/raster.hpp): ISIS3 cubes made here with GDAL's ISIS3 driver (a
// reflectance band and phase, incidence and emission backplanes, named in ISIS's BandBin), bands read by name and
// by index, ISIS's NULL pixels masked, a Lunar-Lambert law fitted from the cube's own backplanes; GeoTIFF bands by
// description; a missing band and backplanes of another size refused with one line.
#include <catch2/catch.hpp>

#include <gdal_priv.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "image/raster.hpp"
#include "moon/disc.hpp"
#include "moon/fit.hpp"
#include "photometry/fit.hpp"
#include "photometry/normalize.hpp"
#include "support.hpp"

using namespace shadelab;

namespace {

constexpr double kIsisNull = -3.4028226550889045e+38;   // ISIS's NULL special pixel (float)

// A cube of `bands` float planes (row 0 at the top, as GDAL stores it) with BandBin Name = names.
void write_cube(const std::string& path, int w, int h, const std::vector<std::vector<float>>& planes,
                const std::vector<std::string>& names) {
    GDALAllRegister();
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("ISIS3");
    REQUIRE(drv);
    GDALDataset* ds = drv->Create(path.c_str(), w, h, int(planes.size()), GDT_Float32, nullptr);
    REQUIRE(ds);
    std::string js = R"({"IsisCube":{"_type":"object","BandBin":{"_type":"group","Name":[)";
    for (std::size_t k = 0; k < names.size(); ++k) js += (k ? ",\"" : "\"") + names[k] + "\"";
    js += "]}}}";
    char* md[2] = {js.data(), nullptr};
    ds->SetMetadata(md, "json:ISIS3");
    for (std::size_t b = 0; b < planes.size(); ++b) {
        auto plane = planes[b];
        CHECK(ds->GetRasterBand(int(b) + 1)->RasterIO(GF_Write, 0, 0, w, h, plane.data(), w, h, GDT_Float32, 0, 0) ==
              CE_None);
    }
    GDALClose(ds);
}

}  // namespace

TEST_CASE("ISIS3 cube through GDAL: bands by name and index, NULL pixels masked, a law fitted from its backplanes",
          "[cube][photometry]") {
    const auto dir = test::scratch_dir("raster-gdal");
    // A Lunar-Lambert disc (L 0.4, albedo 0.2) at phase 50, and its geometry per pixel, as a 4-band cube.
    moon::DiscRenderOptions o;
    o.width = 48;
    o.height = 40;
    o.disc = moon::Disc{24.0, 20.0, 17.0};
    o.material.model = "lunar_lambert";
    o.material.params = {{"l", 0.4}};
    o.material.albedo = glm::dvec3(0.2);
    o.sun = moon::sun_geometry(50.0, 30.0);
    const Image disc = moon::render_disc(test::runtime(), o);
    std::vector<std::vector<float>> planes(4, std::vector<float>(std::size_t(o.width * o.height), float(kIsisNull)));
    std::size_t on_disc = 0;
    for (const auto& p : moon::disc_pixels(disc, o.disc, o.sun)) {
        const std::size_t k = std::size_t(p.y * o.width + p.x);
        planes[0][k] = float(p.I);
        planes[1][k] = float(p.a.g_deg);
        planes[2][k] = float(p.a.i_deg);
        planes[3][k] = float(p.a.e_deg);
        ++on_disc;
    }
    const std::string cube = (dir / "disc.cub").string();
    write_cube(cube, o.width, o.height, planes, {"Reflectance", "Phase", "Incidence", "Emission"});

    CHECK(is_gdal_path(cube));
    CHECK(is_gdal_path(cube + "[phase]"));
    CHECK_FALSE(is_gdal_path((dir / "plain.tif").string()));
    const Image refl = read_image(cube + "[reflectance]");   // case-insensitive
    const Image refl1 = read_image(cube);                     // band 1 by default
    const Image inc3 = read_image(cube + "[3]");
    REQUIRE(refl.width == o.width);
    REQUIRE(refl.height == o.height);
    std::size_t valid = 0, wrong = 0;
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x) {
            const std::size_t k = std::size_t(y * o.width + x);
            const bool on = planes[0][k] > -1e30f;
            valid += refl.at(x, y, 1) == 1.0f;
            if ((refl.at(x, y, 1) == 1.0f) != on) ++wrong;   // NULL -> alpha 0
            if (on && (refl.at(x, y, 0) != planes[0][k] || refl1.at(x, y, 0) != planes[0][k] ||
                       inc3.at(x, y, 0) != planes[2][k]))
                ++wrong;
        }
    CHECK(valid == on_disc);
    CHECK(wrong == 0);

    // The law fitted from the cube's own backplanes gives back L and the albedo.
    const photometry::PixelGeometry pg =
        photometry::geometry_from_backplanes(refl, cube, {cube + "[phase]", cube + "[incidence]", cube + "[emission]"});
    REQUIRE(pg.dn.size() == on_disc);
    photometry::FitData d;
    d.images = 1;
    for (std::size_t k = 0; k < pg.dn.size(); ++k)
        if (pg.geometry[k].incidence < 89.0 && pg.geometry[k].emission < 89.0) {
            d.geometry.push_back(pg.geometry[k]);
            d.value.push_back(pg.dn[k]);
            d.image.push_back(0);
        }
    const photometry::FitResult r = photometry::fit_law(test::runtime(), d, {"lunar_lambert", {}, {}});
    CHECK(r.params[0].value == Approx(0.4).margin(1e-4));
    CHECK(r.params[1].value == Approx(0.2).epsilon(1e-4));

    // Bad input: a band the cube does not have; backplanes of another size (from another cube).
    CHECK_THROWS_WITH(read_image(cube + "[albedo]"),
                      Catch::Contains("disc.cub has no band 'albedo': its bands are 1 'Reflectance', 2 'Phase'") &&
                          Catch::Contains("give a name or an index 1 to 4"));
    CHECK_THROWS_WITH(read_image(cube + "[5]"), Catch::Contains("has no band '5'"));
    const std::string small = (dir / "small.cub").string();
    write_cube(small, 20, 10, std::vector<std::vector<float>>(3, std::vector<float>(200, 30.0f)),
               {"Phase", "Incidence", "Emission"});
    CHECK_THROWS_WITH(
        photometry::geometry_from_backplanes(refl, cube, {small + "[phase]", small + "[incidence]", small + "[emission]"}),
        Catch::Contains("small.cub[phase] is 20x10 but") && Catch::Contains("backplanes must have the image's size"));
    CHECK_THROWS_WITH(read_image((dir / "none.cub").string()), Catch::Contains("not found"));
}

TEST_CASE("GeoTIFF bands through GDAL by description and index", "[cube]") {
    const auto dir = test::scratch_dir("raster-gtiff");
    const std::string tif = (dir / "bp.tif").string();
    GDALAllRegister();
    GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create(tif.c_str(), 5, 4, 2, GDT_Float32, nullptr);
    REQUIRE(ds);
    for (int b = 1; b <= 2; ++b) {
        std::vector<float> v(20);
        for (int k = 0; k < 20; ++k) v[std::size_t(k)] = float(10 * b + k);
        ds->GetRasterBand(b)->SetDescription(b == 1 ? "incidence" : "emission");
        CHECK(ds->GetRasterBand(b)->RasterIO(GF_Write, 0, 0, 5, 4, v.data(), 5, 4, GDT_Float32, 0, 0) == CE_None);
    }
    GDALClose(ds);
    const Image e = read_image(tif + "[emission]"), e2 = read_image(tif + "[2]");
    REQUIRE(e.width == 5);
    for (int k = 0; k < 20; ++k) {
        CHECK(e.at(k % 5, k / 5, 0) == float(20 + k));
        CHECK(e2.at(k % 5, k / 5, 0) == float(20 + k));
    }
}
