// PNG files written with libpng itself (the PNG reference library), not through OpenImageIO: render and batch
// write PNG by default, and OpenImageIO costs a process about 0.2 s of loading (image/image_io.hpp). The file is
// the one OpenImageIO 2.4 wrote for shadelab before (tests/test_image.cpp compares the two byte for byte): 8 bits
// a channel (grey, grey + alpha, RGB or RGBA by channel count), straight alpha, the sRGB, gAMA and cHRM chunks of
// an sRGB image, oFFs 0 0, and the text chunks "oiio:ColorSpace" = "sRGB" and "Software" = "shadelab"; zlib level
// and row filter as ImageWriteOptions gives them, zlib's default strategy; zlib's memLevel as given (OpenImageIO
// leaves libpng's, 8: the same file only then). rows() hands the rows to libpng, which deflates them in one stream
// on one thread; image_in_pieces deflates them on several threads into another stream of the same pixels.
#pragma once
#include <cstddef>
#include <cstdio>
#include <functional>
#include <string>

namespace shadelab {

// Where PngWriter::image_in_pieces takes its rows: rows [y0, y1), width x channels bytes each, one after another,
// either a pointer into an image already coded or `scratch` (room for y1 - y0 rows) filled. nullptr stops the
// write (the caller says why: a value it refuses to code). Called from several threads at once.
using PngRowSource = std::function<const unsigned char*(int y0, int y1, unsigned char* scratch)>;

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
    // Whether image_in_pieces writes this row filter (libpng's flag: 8 none, 32 up, alone).
    static bool pieces_take_filter(int filter);
    // The whole image instead of rows(): its filtered rows deflated in pieces of about `piece_bytes` on up to
    // `threads` threads (0: all) and joined into the one zlib stream of the IDAT chunks, as pigz joins its
    // pieces. A piece but the last ends on a byte boundary (zlib's sync flush); a piece but the first starts
    // from the 32 KB of filtered rows before it as its dictionary, so its matches reach back as one stream's
    // do; the stream's Adler-32 is combined from the pieces'. One piece is libpng's own stream, byte for byte.
    // Then the end chunk: finish() only closes. False with error() when zlib or the file failed, or the
    // source stopped (error() "stopped").
    bool image_in_pieces(const PngRowSource& rows, int threads, std::size_t piece_bytes = std::size_t(1) << 20);
    // Finishes the file (the end chunk, the close); false with error() when anything failed.
    bool finish();
    // Gives the file up unfinished (its caller removes it): nothing more is written, nothing printed.
    void abandon();

private:
    std::FILE* file_ = nullptr;
    void* png_ = nullptr;    // png_structp
    void* info_ = nullptr;   // png_infop
    int width_ = 0, height_ = 0, channels_ = 0, level_ = 1, filter_ = 0, mem_level_ = 8;
    bool ended_ = false;   // image_in_pieces wrote the end chunk
    std::string error_;
    void close();
};

}  // namespace shadelab
