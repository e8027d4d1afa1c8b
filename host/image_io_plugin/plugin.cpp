// The image plug-in's entry point (host/image/image_io.hpp): the table of its functions, filled once.
#include "image_io_plugin/plugin.hpp"

namespace shadelab::image_io {

namespace {
const Host* g_host = nullptr;
}

const Host& host() { return *g_host; }

}  // namespace shadelab::image_io

extern "C" __attribute__((visibility("default"))) const shadelab::image_io::Plugin* shadelab_image_io_plugin(
    const shadelab::image_io::Host* host) {
    using namespace shadelab::image_io;
    static const Plugin table{kAbi,
                              &oiio::writer_open,
                              &oiio::writer_rows8,
                              &oiio::writer_float,
                              &oiio::writer_close,
                              &oiio::reader_open,
                              &oiio::reader_info,
                              &oiio::reader_probe_last,
                              &oiio::reader_read_float,
                              &oiio::reader_close,
                              &oiio::exr_threads,
                              &oiio::text_width,
                              &oiio::render_text,
                              &gdal::read_raster_band,
                              &gdal::raster_band_names};
    g_host = host;
    return &table;
}
