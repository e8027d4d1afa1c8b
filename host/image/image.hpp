// Images: linear float RGBA in memory; PNG written with libpng (image/png_writer.hpp), EXR with OpenEXR
// (image/exr_writer.hpp), FITS with cfitsio (image/fits.hpp), every other format written and read with
// OpenImageIO in the image plug-in (image/image_io.hpp).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/fragment_buffer.hpp"

namespace shadelab {

struct Image {
    int width = 0;
    int height = 0;
    int channels = 4;
    std::vector<float> pixels;   // linear, row-major, row 0 is the top row, channels interleaved

    Image() = default;
    Image(int w, int h, int c) : width(w), height(h), channels(c), pixels(std::size_t(w) * h * c, 0.0f) {}
    float& at(int x, int y, int c) { return pixels[(std::size_t(y) * width + x) * channels + c]; }
    float at(int x, int y, int c) const { return pixels[(std::size_t(y) * width + x) * channels + c]; }
};

// IEC 61966-2-1 sRGB transfer functions (the piecewise curve, not a 2.2 gamma).
double srgb_encode(double linear);   // linear [0,1] -> encoded [0,1]
double srgb_decode(double encoded);  // encoded [0,1] -> linear

// Scatters shaded fragments (three planes of n floats, as Shader::shade returns) into an RGBA image of
// fb.width x fb.height. Covered pixels get alpha 1; the rest get `background` (rgb linear, a alpha).
// Done in parallel when the fragments are in pixel order (as the rasteriser emits them), else on one thread.
Image compose_image(const FragmentBuffer& fb, const std::vector<float>& rgb_planes, const glm::dvec4& background);
// The same into `out`, reusing its pixel memory when it is large enough (a renderer drawing frame after frame
// keeps one image and pays no fresh-page faults); whatever `out` held is replaced.
void compose_image_into(const FragmentBuffer& fb, const std::vector<float>& rgb_planes, const glm::dvec4& background,
                        Image& out);

// An image coded for an 8-bit output (.png .jpg ...): srgb8_code's bytes, row-major, channels interleaved.
struct Srgb8Image {
    int width = 0;
    int height = 0;
    int channels = 4;
    std::vector<unsigned char> bytes;
};

// compose_image's image coded as encode_srgb8 codes it, the same bytes, made without the float image: in
// parallel when the fragments are in pixel order, coding each pixel as it is composed (a quarter of the float
// image's memory, and no pass over it). Refuses, as write_image(path, ...) would, an image holding NaN or Inf
// (`path` names the output in the message). `out`'s memory is reused when it is large enough.
void compose_image_srgb8_into(const FragmentBuffer& fb, const std::vector<float>& rgb_planes,
                              const glm::dvec4& background, const std::string& path, Srgb8Image& out);

// The 8-bit sRGB code of a linear value, lround(255 srgb_encode(v)) (0 for NaN and v <= 0, 255 for v >= 1),
// from a table of the curve's exact thresholds. encode_srgb8 codes every value of an image so (alpha, the
// 4th of 4 channels, is clamped to [0, 1] and scaled, not encoded), on all hardware threads.
std::uint8_t srgb8_code(float linear);
std::vector<unsigned char> encode_srgb8(const Image& img);

enum class Encoding { Linear, Srgb8 };
// .png .jpg .jpeg .bmp .tga .webp: 8-bit sRGB; .exr .hdr .tif .tiff .fits: linear float (.hdr without alpha).
Encoding encoding_for(const std::string& path);

// Writer settings. The defaults are the fastest settings measured to keep files reasonable (docs/speed.md,
// "Image writes"; bench/bench_e2e_process.cpp prints them against oiiotool): PNG zlib level and EXR compression.
// OpenImageIO's own thread count is left at its default (all hardware threads; it is what EXR compression uses).
struct ImageWriteOptions {
    int png_level = 1;                    // zlib 0 (none) .. 9 (smallest); OpenImageIO's default is 6
    // libpng's row filters (OpenImageIO's "png:filter": 8 none, 16 sub, 32 up, 64 average, 128 Paeth, or-ed;
    // 0 = libpng's default, which tries all five on every row and keeps the best). Up alone: on renders 1.2-1.5x
    // faster than Paeth alone (the default until 2026-12-07), files from 4% larger to 2% smaller; Paeth alone was
    // about twice as fast as all five, for files within 1% (docs/speed.md, "Image write defaults").
    int png_filter = 32;
    std::string exr_compression = "zips"; // OpenEXR: none, rle, zips, zip, piz, pxr24, b44, dwaa, ...; OIIO's is zip
    // zlib's memLevel for PNG (1..9: its hash table of 2^(memLevel + 7) entries and its symbol buffer): 6 deflated
    // renders 1.02-1.2x faster than zlib's default 8, which OpenImageIO uses, for files within 0.3%
    // (docs/speed.md, "png-mem-level").
    int png_mem_level = 6;
    // Threads deflating a PNG (0: all hardware threads): an image of 2 MB of rows or more is deflated in pieces
    // of 1 MB on these threads and the pieces joined into one zlib stream (image/png_writer.hpp), with the
    // filters "up" (the default) and "none". 1: libpng's own stream, the file OpenImageIO writes byte for byte.
    int png_threads = 0;
};

// FITS goes through image/fits.hpp (one grey plane). Writes atomically (a temporary file in the same folder, then rename), so an interrupted run never
// leaves a truncated image. Refuses (shadelab::Error) images holding NaN or Inf: they are bugs upstream.
void write_image(const std::string& path, const Image& img, const ImageWriteOptions& options = {});
// An image already coded (compose_image_srgb8_into) to an 8-bit format (encoding_for(path) is Srgb8): the same
// file as write_image of the float image it was coded from.
void write_image(const std::string& path, const Srgb8Image& img, const ImageWriteOptions& options = {});
// The colour image of compose_image_srgb8_into written to `path` (an 8-bit format) as write_image would write it
// (the same pixels; for PNG the same file as write_image with the same options), without holding the image where
// it need not: a PNG that png_composed_in_pieces takes is composed row block by row block inside the deflate's
// pieces, on all threads (no image of its own: 64 MB at 4096 x 4096, and no pass over it). Refuses NaN or Inf
// with compose_image_srgb8_into's message and count, leaving no file.
void write_image_composed(const std::string& path, const FragmentBuffer& fb, const std::vector<float>& rgb_planes,
                          const glm::dvec4& background, const ImageWriteOptions& options = {});
// Whether write_image_composed composes inside the deflate: a .png whose rows PNG deflates in pieces (2 MB of
// rows or more, options.png_threads not 1, filter Up or none).
bool png_composed_in_pieces(const std::string& path, int width, int height, const ImageWriteOptions& options = {});
// The formats write_image takes, for --help texts and errors: one list, so no command's help can drift from it.
constexpr const char* kOutputFormats = ".png .jpg .bmp .tga .webp (sRGB 8-bit) or .exr .hdr .tif .fits (linear float)";

// Reads any format OpenImageIO reads (FITS by image/fits.hpp, planetary rasters by image/raster.hpp), in the image
// plug-in; 8-bit sRGB-encoded formats are decoded to linear.
Image read_image(const std::string& path);

}  // namespace shadelab
