// libFuzzer target: the image readers (our FITS reader; PNG and EXR through OpenImageIO with the header
// checks in front). The first byte picks the format; the rest is the file. An EXR may hold NaN/Inf pixels: the
// reader hands them on and each caller refuses or counts them (compare, moon fit), so only the shape is checked.
#include <cstddef>
#include <cstdint>

#include "fuzz_common.hpp"
#include "image/image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static const char* const kName[] = {"image.fits", "image.png", "image.exr"};
    const auto img = shadelab::fuzz::load_input(data + 1, size - 1, kName[data[0] % 3],
                                                [](const std::string& path) { return shadelab::read_image(path); });
    if (img && img->pixels.size() != std::size_t(img->width) * std::size_t(img->height) * std::size_t(img->channels))
        __builtin_trap();
    return 0;
}
