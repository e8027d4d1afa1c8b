// libFuzzer target: the planetary rasters read through GDAL (host/image/raster.hpp): ISIS3 cubes with attached
// labels, PDS3 images with attached labels, PDS4 labels and GeoTIFF bands. The first byte picks the format (the
// file name's extension, which is how read_image chooses GDAL); the rest is the file.
#include <cstddef>
#include <cstdint>

#include "fuzz_common.hpp"
#include "image/image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static const char* const kName[] = {"raster.cub", "raster.lbl", "raster.xml", "raster.img", "raster.tif"};
    static const char* const kBand[] = {"", "", "", "", "[1]"};
    const int f = data[0] % 5;
    const auto img = shadelab::fuzz::load_input(data + 1, size - 1, kName[f], [f](const std::string& path) {
        return shadelab::read_image(path + kBand[f]);
    });
    if (!img) return 0;
    if (img->pixels.size() != std::size_t(img->width) * std::size_t(img->height) * std::size_t(img->channels))
        __builtin_trap();
    for (const float v : img->pixels)
        if (!(v == v) || v - v != 0.0f) __builtin_trap();   // no NaN or Inf reaches the caller
    return 0;
}
