// PNG files written with libpng itself (the PNG reference library), not through OpenImageIO: render and batch
// write PNG by default, and OpenImageIO costs a process about 0.2 s of loading (image/image_io.hpp). The file is
// the one OpenImageIO 2.4 wrote for shadelab before (tests/test_image.cpp compares the two byte for byte): 8 bits
// a channel (grey, grey + alpha, RGB or RGBA by channel count), straight alpha, the sRGB, gAMA and cHRM chunks of
// an sRGB image, oFFs 0 0, and the text chunks "oiio:ColorSpace" = "sRGB" and "Software" = "shadelab"; zlib level
// and row filter as ImageWriteOptions gives them, zlib's default strategy; zlib's memLevel as given (OpenImageIO
// leaves libpng's, 8: the same file only then).
#pragma once
#include <cstdio>
#include <string>

namespace shadelab {

class PngWriter {
public:
    // Opens `file` and writes the header; ok() says whether that worked (error() why).
    PngWriter(const std::string& file, int width, int height, int channels, int zlib_level, int filter,
              int zlib_mem_level = 8);
    ~PngWriter();
    PngWriter(const PngWriter&) = delete;
    PngWriter& operator=(const PngWriter&) = delete;

    bool ok() const { return error_.empty(); }
    const std::string& error() const { return error_; }
    // Rows [y0, y1), in order, each width x channels bytes.
    bool rows(int y0, int y1, const unsigned char* data);
    // Finishes the file (the end chunk, the close); false with error() when anything failed.
    bool finish();
    // Gives the file up unfinished (its caller removes it): nothing more is written, nothing printed.
    void abandon();

private:
    std::FILE* file_ = nullptr;
    void* png_ = nullptr;    // png_structp
    void* info_ = nullptr;   // png_infop
    int width_ = 0, channels_ = 0;
    std::string error_;
    void close();
};

}  // namespace shadelab
