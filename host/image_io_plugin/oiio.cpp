// The image plug-in's OpenImageIO half (host/image/image_io.hpp says why it is a plug-in): writers, readers
// and text, as thin as OpenImageIO allows; what to check and what to refuse stays in host/image/image.cpp.
#include "image_io_plugin/plugin.hpp"

#include <algorithm>
#include <memory>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

namespace shadelab::image_io {

struct Writer {
    std::unique_ptr<OIIO::ImageOutput> out;
};

struct Reader {
    std::unique_ptr<OIIO::ImageInput> in;
};

namespace oiio {

Writer* writer_open(const std::string& file, const WriteSpec& w, std::string& why, bool& no_format) {
    auto out = OIIO::ImageOutput::create(file);
    no_format = !out;
    if (!out) {
        why = OIIO::geterror();
        return nullptr;
    }
    OIIO::ImageSpec spec(w.width, w.height, w.channels, w.srgb8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    if (w.channels == 4) spec.alpha_channel = 3;
    spec.attribute("oiio:ColorSpace", w.srgb8 ? "sRGB" : "Linear");
    spec.attribute("Software", "shadelab");
    // Colours are stored unassociated (straight) with alpha = coverage; tell the 8-bit writers not to
    // divide by alpha (EXR keeps OpenImageIO's associated convention; covered pixels have alpha 1 anyway).
    if (w.srgb8) spec.attribute("oiio:UnassociatedAlpha", 1);
    spec.attribute("png:compressionLevel", std::clamp(w.png_level, 0, 9));
    spec.attribute("png:filter", std::clamp(w.png_filter, 0, 248));
    if (std::string(out->format_name()) == "openexr") spec.attribute("compression", w.exr_compression);
    if (!out->open(file, spec)) {
        why = out->geterror();
        return nullptr;
    }
    return new Writer{std::move(out)};
}

bool writer_rows8(Writer* w, int y0, int y1, const unsigned char* rows) {
    return w->out->write_scanlines(y0, y1, 0, OIIO::TypeDesc::UINT8, rows);
}

bool writer_float(Writer* w, const float* pixels) { return w->out->write_image(OIIO::TypeDesc::FLOAT, pixels); }

bool writer_close(Writer* w, std::string& why) {
    std::unique_ptr<Writer> owned(w);
    const bool ok = w->out->close();
    if (!ok) why = w->out->geterror();
    return ok;
}

Reader* reader_open(const std::string& path, std::string& why) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);   // keep straight alpha as stored (PNG): no premultiply
    auto in = OIIO::ImageInput::open(path, &config);
    if (!in) {
        why = OIIO::geterror();
        return nullptr;
    }
    return new Reader{std::move(in)};
}

Info reader_info(const Reader* r) {
    const OIIO::ImageSpec& s = r->in->spec();
    return Info{s.width, s.height, s.nchannels, s.depth, s.deep, s.tile_width > 0 && s.tile_height > 0, s.x, s.y, s.z,
                s.tile_width, s.tile_height, s.tile_depth, s.pixel_bytes(true), s.format.size(), s.alpha_channel,
                r->in->format_name(), s.get_string_attribute("oiio:ColorSpace")};
}

bool reader_probe_last(Reader* r, std::string& why) {
    const Info i = reader_info(r);
    const double tile = i.tiled ? double(i.tile_width) * double(i.tile_height) * double(std::max(i.tile_depth, 1)) *
                                      double(i.nchannels)
                                : double(i.width) * double(i.nchannels);
    std::vector<float> probe(static_cast<std::size_t>(tile));
    const bool ok = i.tiled ? r->in->read_tile(i.x + (i.width - 1) / i.tile_width * i.tile_width,
                                               i.y + (i.height - 1) / i.tile_height * i.tile_height, i.z,
                                               OIIO::TypeDesc::FLOAT, probe.data())
                            : r->in->read_scanline(i.y + i.height - 1, i.z, OIIO::TypeDesc::FLOAT, probe.data());
    if (!ok) why = r->in->geterror();
    return ok;
}

// The image in its stored formats, converted here channel by channel to float. Never ask OpenImageIO 2.4 for
// the conversion: its read_scanlines then allocates a native buffer of max(256, 64 MB / row) rows whatever the
// image's height (ImageInput::read_scanlines, "oiio_read_chunk"), so a 6-row EXR 2097160 pixels wide cost
// 3.2 GB there. A native read goes straight into our buffer.
bool reader_read_float(Reader* r, float* out, std::string& why) {
    const OIIO::ImageSpec& spec = r->in->spec();
    const std::size_t w = std::size_t(spec.width), h = std::size_t(spec.height), n = std::size_t(spec.nchannels);
    const std::size_t pixel_bytes = spec.pixel_bytes(true);
    std::vector<unsigned char> raw(w * h * pixel_bytes);
    bool ok = r->in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeUnknown, raw.data());
    std::size_t offset = 0;
    for (int c = 0; ok && c < spec.nchannels; ++c) {
        const OIIO::TypeDesc t = spec.channelformat(c);
        ok = OIIO::convert_image(1, spec.width, spec.height, 1, raw.data() + offset, t, OIIO::stride_t(pixel_bytes),
                                 OIIO::stride_t(w * pixel_bytes), OIIO::AutoStride, out + c, OIIO::TypeFloat,
                                 OIIO::stride_t(n * sizeof(float)), OIIO::stride_t(w * n * sizeof(float)),
                                 OIIO::AutoStride);
        offset += t.size();
    }
    if (!ok) why = r->in->geterror();
    return ok;
}

void reader_close(Reader* r) {
    std::unique_ptr<Reader> owned(r);
    r->in->close();
}

// OpenEXR's C++ reader keeps max(1, 2 x its global thread count) line or tile buffers; OpenImageIO sets that
// count from its "exr_threads" attribute (0: its "threads", -1: none).
int exr_threads() {
    int threads = 0;
    OIIO::getattribute("exr_threads", threads);
    if (threads == 0) OIIO::getattribute("threads", threads);
    return threads;
}

bool text_width(const std::string& text, int size, const std::string& font, int& width) {
    const OIIO::ROI box = OIIO::ImageBufAlgo::text_size(text, size, font);
    if (!box.defined()) return false;
    width = box.width();
    return true;
}

bool render_text(float* rgba, int width, int height, int cx, int cy, const std::string& text, int size,
                 const std::string& font, const float colour[4], std::string& why) {
    OIIO::ImageBuf buf(OIIO::ImageSpec(width, height, 4, OIIO::TypeDesc::FLOAT), rgba);
    const bool ok = OIIO::ImageBufAlgo::render_text(buf, cx, cy, text, size, font, OIIO::cspan<float>(colour, 4),
                                                    OIIO::ImageBufAlgo::TextAlignX::Center,
                                                    OIIO::ImageBufAlgo::TextAlignY::Center);
    if (!ok) why = buf.geterror();
    return ok;
}

}  // namespace oiio

}  // namespace shadelab::image_io
