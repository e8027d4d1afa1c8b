// The image plug-in's functions (host/image/image_io.hpp says what each does), which plugin.cpp puts in the table.
#pragma once
#include "image/image_io.hpp"

namespace shadelab::image_io {

namespace oiio {   // oiio.cpp
Writer* writer_open(const std::string& file, const WriteSpec& spec, std::string& why, bool& no_format);
bool writer_rows8(Writer* w, int y0, int y1, const unsigned char* rows);
bool writer_float(Writer* w, const float* pixels);
bool writer_close(Writer* w, std::string& why);
Reader* reader_open(const std::string& path, std::string& why);
Info reader_info(const Reader* r);
bool reader_probe_last(Reader* r, std::string& why);
bool reader_read_float(Reader* r, float* out, std::string& why);
void reader_close(Reader* r);
int exr_threads();
bool text_width(const std::string& text, int size, const std::string& font, int& width);
bool render_text(float* rgba, int width, int height, int cx, int cy, const std::string& text, int size,
                 const std::string& font, const float colour[4], std::string& why);
}  // namespace oiio

namespace gdal {   // gdal.cpp
Image read_raster_band(const std::string& path);
std::vector<std::string> raster_band_names(const std::string& file);
}  // namespace gdal

// The program's services (plugin.cpp keeps the pointer the entry point was given).
const Host& host();

}  // namespace shadelab::image_io
