#include "image/exr_header.hpp"

#include <algorithm>
#include <filesystem>

#include <OpenEXR/openexr.h>

#include "core/error.hpp"
#include "core/limits.hpp"
#include "image/image_io.hpp"

namespace shadelab {

namespace {

// The core library reports through a callback; keep the last message of this thread for the error line.
thread_local std::string g_exr_message;
void keep_message(exr_const_context_t, exr_result_t, const char* msg) { g_exr_message = msg ? msg : ""; }

struct ExrContext {
    exr_context_t ctx = nullptr;
    ~ExrContext() {
        if (ctx) exr_finish(&ctx);
    }
};

int stored_bytes(exr_pixel_type_t t) { return t == EXR_PIXEL_HALF ? 2 : 4; }   // UINT and FLOAT are 4

// OpenEXR's C++ reader keeps max(1, 2 x its global thread count) line or tile buffers (ScanLineInputFile,
// TiledInputFile); OpenImageIO sets that count from its "exr_threads" attribute (0: its "threads", -1: none),
// and reads the file (in the image plug-in, image/image_io.hpp) after this check.
int decode_buffers() { return std::max(1, 2 * std::max(image_io::plugin().exr_threads(), 0)); }

}  // namespace

ExrHeader check_exr_header(const std::string& path) {
    const std::string what = "image '" + path + "'";
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = keep_message;
    ExrContext c;
    g_exr_message.clear();
    if (exr_start_read(&c.ctx, path.c_str(), &init) != EXR_ERR_SUCCESS)
        throw Error(what + " is not a readable EXR file (" + g_exr_message + "): re-export it, or check the path");
    ExrHeader h;
    exr_get_count(c.ctx, &h.parts);
    for (int p = 0; p < h.parts; ++p) {
        exr_storage_t storage = EXR_STORAGE_SCANLINE;
        exr_get_storage(c.ctx, p, &storage);
        if (storage == EXR_STORAGE_DEEP_SCANLINE || storage == EXR_STORAGE_DEEP_TILED)
            throw Error(what + " holds deep data (several samples per pixel), which shadelab does not read: flatten it "
                        "first (e.g. oiiotool in.exr --flatten -o out.exr)");
        int32_t chunks = 0;
        std::uint64_t unpacked = 0;
        if (exr_get_chunk_count(c.ctx, p, &chunks) != EXR_ERR_SUCCESS ||
            exr_get_chunk_unpacked_size(c.ctx, p, &unpacked) != EXR_ERR_SUCCESS)
            throw Error(what + " has a header whose pixel layout cannot be worked out (" + g_exr_message +
                        "): re-export it");
        h.chunks += chunks;
        h.max_chunk_bytes = std::max(h.max_chunk_bytes, unpacked);
        if (p != 0) continue;
        exr_attr_box2i_t dw{};
        const exr_attr_chlist_t* chl = nullptr;
        exr_get_data_window(c.ctx, p, &dw);
        exr_get_channels(c.ctx, p, &chl);
        h.width = int(std::min<std::int64_t>(std::int64_t(dw.max.x) - dw.min.x + 1, INT32_MAX));
        h.height = int(std::min<std::int64_t>(std::int64_t(dw.max.y) - dw.min.y + 1, INT32_MAX));
        h.channels = chl ? chl->num_channels : 0;
        for (int i = 0; i < h.channels; ++i) h.bytes_per_pixel += stored_bytes(chl->entries[i].pixel_type);
    }
    // Every chunk has an 8-byte entry in the offset table and at least an 8-byte chunk header of its own.
    std::error_code ec;
    const double file_bytes = double(std::filesystem::file_size(path, ec));
    if (!ec && 16.0 * double(h.chunks) > file_bytes)
        throw Error(what + " is truncated or corrupt: its header says " + std::to_string(h.width) + "x" +
                    std::to_string(h.height) + " in " + std::to_string(h.chunks) + " chunks, whose offset table and chunk "
                    "headers alone need " + format_bytes(16.0 * double(h.chunks)) + ", more than the file's " +
                    format_bytes(file_bytes));
    // What reading it costs: the float image we keep, the native copy it is converted from, and OpenEXR's
    // decode buffers (each buffer: the unpacked chunk and the decompressor's two buffers of that size).
    const double pixels = double(h.width) * double(h.height);
    const double image = pixels * double(h.channels) * 4.0 + pixels * h.bytes_per_pixel;
    const double decode = double(decode_buffers()) * 3.0 * double(h.max_chunk_bytes);
    check_memory(what + " (" + std::to_string(h.width) + "x" + std::to_string(h.height) + ", decoded in chunks of " +
                     format_bytes(double(h.max_chunk_bytes)) + ")",
                 image + decode);
    return h;
}

}  // namespace shadelab
