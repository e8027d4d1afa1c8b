// libFuzzer target: the image readers (our FITS reader; PNG and EXR through OpenImageIO with the header
// checks in front). The first byte picks the format; the rest is the file.
#include <cstddef>
#include <cstdint>

#include "core/error.hpp"
#include "fuzz_common.hpp"
#include "image/image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static const char* const kExt[] = {".fits", ".png", ".exr"};
    const std::string path = shadelab::fuzz::scratch_path(std::string("image") + kExt[data[0] % 3]);
    shadelab::fuzz::write_file(path, data + 1, size - 1);
    try {
        const shadelab::Image img = shadelab::read_image(path);
        if (img.pixels.size() != std::size_t(img.width) * std::size_t(img.height) * std::size_t(img.channels)) __builtin_trap();
    } catch (const shadelab::Error&) {
    }
    return 0;
}
