// EXR files written with OpenEXR itself (the EXR reference library), not through OpenImageIO, which costs a
// process about 0.2 s of loading (image/image_io.hpp). The file is the one OpenImageIO 2.4 wrote for shadelab
// before (tests/test_image.cpp compares the two byte for byte, the capture date aside): 32-bit float channels
// named Y (1 channel), R G (2), R G B (3) or R G B A (4), scanlines in increasing y, the header OpenEXR gives
// an image of that size, "Software" = "shadelab" and the capture date; compression as ImageWriteOptions
// names it, on all hardware threads (OpenImageIO's default).
#pragma once
#include <string>

#include "image/image.hpp"

namespace shadelab {

// Whether write_exr takes this compression name: none, rle, zips, zip, piz, pxr24, b44, b44a (dwaa, dwab and
// OpenImageIO's forms with a level, such as "zip:4", go through the image plug-in); and 1 to 4 channels.
bool exr_direct(const std::string& compression, int channels);

// Writes `img` to `file`; false with the reason in `why` when OpenEXR failed.
bool write_exr(const std::string& file, const Image& img, const std::string& compression, std::string& why);

}  // namespace shadelab
