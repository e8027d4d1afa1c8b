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
    static Plugin table = [] {
        Plugin p{};
        p.abi = kAbi;
        fill_oiio(p);
        fill_gdal(p);
        return p;
    }();
    g_host = host;
    return &table;
}
