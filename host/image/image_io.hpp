// OpenImageIO and GDAL, loaded when first needed: the image plug-in.
//
// Debian's OpenImageIO 2.4 links some 250 shared libraries (its readers' FFmpeg, HEIF, OpenVDB, DCMTK, ...) and
// GDAL a hundred more; a process that links them spends about 0.2 s in the dynamic loader before main (measured
// 2026-12-06: an empty program linking OpenImageIO 0.22-0.23 s, GDAL 0.06 s, neither 0.00 s), more than
// `shadelab render` of a 512 x 512 image spends on everything else. So neither is linked into the program: their
// code is the plug-in host/image_io_plugin/ (libshadelab_imageio.so), which image_io::plugin() loads with dlopen
// the first time a format needs it. PNG and EXR, what render and batch write, are written without it (libpng and
// OpenEXR: image/png_writer.hpp, image/exr_writer.hpp); FITS never needed it (image/fits.hpp).
//
// The plug-in is built from this tree by the same compiler as the program, so the interface is plain C++.
// Its functions report failures by returning false with the reason, or by throwing shadelab::Error (a
// header-only class, matched across the boundary by its type name); the memory limit they check is the
// program's (Host).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "image/image.hpp"

namespace shadelab::image_io {

// Raised whenever the interface below changes: a plug-in of another version is refused by name.
constexpr int kAbi = 1;

// What the plug-in calls back in the program that loaded it.
struct Host {
    void (*check_memory)(const std::string& what, double bytes);   // core/limits.hpp
};

// A file's header as OpenImageIO reads it (the first subimage).
struct Info {
    int width = 0, height = 0, nchannels = 0, depth = 1;
    bool deep = false, tiled = false;
    int x = 0, y = 0, z = 0, tile_width = 0, tile_height = 0, tile_depth = 0;
    std::size_t native_pixel_bytes = 0;   // one pixel in the file's own channel formats
    std::size_t format_bytes = 0;         // bytes of one value of the image's main format
    int alpha_channel = -1;
    std::string format_name;              // "png", "openexr", "tiff", ...
    std::string color_space;              // OpenImageIO's "oiio:ColorSpace" ("" when the file says nothing)
};

// How write_image asks for a file: 8-bit sRGB codes (rows handed over in blocks) or linear floats.
struct WriteSpec {
    int width = 0, height = 0, channels = 4;
    bool srgb8 = false;
    int png_level = 6, png_filter = 0;
    std::string exr_compression;
};

// The WriteSpec of an image of width x height x channels, or of `img`, under `options`.
inline WriteSpec write_spec(int width, int height, int channels, bool srgb8, const ImageWriteOptions& options) {
    WriteSpec spec;
    spec.width = width;
    spec.height = height;
    spec.channels = channels;
    spec.srgb8 = srgb8;
    spec.png_level = options.png_level;
    spec.png_filter = options.png_filter;
    spec.exr_compression = options.exr_compression;
    return spec;
}
inline WriteSpec write_spec(const Image& img, bool srgb8, const ImageWriteOptions& options) {
    return write_spec(img.width, img.height, img.channels, srgb8, options);
}

struct Reader;   // an open image file
struct Writer;   // an image file being written

struct Plugin {
    int abi;
    // ---- OpenImageIO: writing. open: nullptr and `why` when no plug-in of OpenImageIO writes the format
    // (`no_format` set) or the file cannot be created; rows8 takes rows [y0, y1) of 8-bit codes; close finishes
    // the file (false and `why` when anything failed) and frees the writer in every case.
    Writer* (*writer_open)(const std::string& file, const WriteSpec& spec, std::string& why, bool& no_format);
    bool (*writer_rows8)(Writer* w, int y0, int y1, const unsigned char* rows);
    bool (*writer_float)(Writer* w, const float* pixels);
    bool (*writer_close)(Writer* w, std::string& why);
    // ---- OpenImageIO: reading (straight alpha kept as stored). open: nullptr and `why` on failure.
    Reader* (*reader_open)(const std::string& path, std::string& why);
    Info (*reader_info)(const Reader* r);
    bool (*reader_probe_last)(Reader* r, std::string& why);      // the last row or tile, as float
    bool (*reader_read_float)(Reader* r, float* out, std::string& why);   // every channel, interleaved float
    void (*reader_close)(Reader* r);
    int (*exr_threads)();   // the thread count OpenImageIO gives OpenEXR's decoders
    // ---- OpenImageIO: text on an RGBA float image (FreeType). text_width: false when the font cannot be used.
    bool (*text_width)(const std::string& text, int size, const std::string& font, int& width);
    bool (*render_text)(float* rgba, int width, int height, int cx, int cy, const std::string& text, int size,
                        const std::string& font, const float colour[4], std::string& why);
    // ---- GDAL (image/raster.hpp says what they do; they throw shadelab::Error)
    Image (*read_raster_band)(const std::string& path);
    std::vector<std::string> (*raster_band_names)(const std::string& file);
};

// The plug-in's entry point, looked up by name.
using EntryPoint = const Plugin* (*)(const Host* host);
constexpr const char* kEntryPoint = "shadelab_image_io_plugin";
constexpr const char* kFileName = "libshadelab_imageio.so";

// The plug-in, loaded on the first call (thread-safe). Throws one line naming where it was looked for when it
// cannot be loaded. Looked up: $SHADELAB_IMAGEIO_PLUGIN (a file), then beside the code that calls this (the
// program, libshadelab.so or the Python module) and in its shadelab/ subfolder, then the folders a build or
// an install puts it in relative to that (../, ../lib*/shadelab/, ../../shadelab/).
const Plugin& plugin();

}  // namespace shadelab::image_io
