#include "image/png_writer.hpp"

#include <png.h>
#include <zlib.h>

#include <csetjmp>
#include <vector>

namespace shadelab {

namespace {

// libpng reports an error by longjmp to the setjmp of the call that failed: each libpng call below runs inside
// its own guarded() frame, which holds no object with a destructor, and the message is kept for error().
struct Jump {
    std::jmp_buf env;
    std::string message;
};

void on_error(png_structp png, png_const_charp msg) {
    auto* j = static_cast<Jump*>(png_get_error_ptr(png));
    j->message = msg ? msg : "libpng error";
    std::longjmp(j->env, 1);
}
void on_warning(png_structp, png_const_charp) {}   // nothing on the terminal: errors are reported by shadelab

// f() with libpng's error caught: false, and its message in `error`, when libpng reported one.
template <class F>
bool guarded(png_structp png, std::string& error, const F& f) {
    auto* j = static_cast<Jump*>(png_get_error_ptr(png));
    if (setjmp(j->env) != 0) {
        error = j->message;
        return false;
    }
    f();
    return true;
}

int colour_type(int channels) {
    switch (channels) {
        case 1: return PNG_COLOR_TYPE_GRAY;
        case 2: return PNG_COLOR_TYPE_GRAY_ALPHA;
        case 3: return PNG_COLOR_TYPE_RGB;
        default: return PNG_COLOR_TYPE_RGB_ALPHA;
    }
}

}  // namespace

PngWriter::PngWriter(const std::string& file, int width, int height, int channels, int zlib_level, int filter,
                     int zlib_mem_level)
    : width_(width), channels_(channels) {
    file_ = std::fopen(file.c_str(), "wb");
    if (!file_) {
        error_ = "cannot create the file";
        return;
    }
    auto* jump = new Jump();
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, jump, on_error, on_warning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    png_ = png;
    info_ = info;
    if (!png) delete jump;   // (else close() frees it with the struct)
    if (!png || !info) {
        error_ = "libpng could not start a PNG";
        return;
    }
    guarded(png, error_, [&] {
        png_init_io(png, file_);
        png_set_compression_level(png, zlib_level < 0 ? 0 : (zlib_level > 9 ? 9 : zlib_level));
        png_set_compression_strategy(png, Z_DEFAULT_STRATEGY);   // as OpenImageIO sets it (libpng's own: Z_FILTERED)
        png_set_compression_mem_level(png, zlib_mem_level < 1 ? 1 : (zlib_mem_level > 9 ? 9 : zlib_mem_level));
        if (filter != 0) png_set_filter(png, PNG_FILTER_TYPE_BASE, filter);
        png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, colour_type(channels), PNG_INTERLACE_NONE,
                     PNG_COMPRESSION_TYPE_BASE, PNG_FILTER_TYPE_BASE);
        png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_ABSOLUTE);
        png_set_oFFs(png, info, 0, 0, PNG_OFFSET_PIXEL);
        static char key_cs[] = "oiio:ColorSpace", value_cs[] = "sRGB", key_sw[] = "Software", value_sw[] = "shadelab";
        png_text text[2] = {};
        text[0].compression = PNG_TEXT_COMPRESSION_NONE;
        text[0].key = key_cs;
        text[0].text = value_cs;
        text[1].compression = PNG_TEXT_COMPRESSION_NONE;
        text[1].key = key_sw;
        text[1].text = value_sw;
        png_set_text(png, info, text, 2);
        png_write_info(png, info);
    });
}

PngWriter::~PngWriter() { close(); }

bool PngWriter::rows(int y0, int y1, const unsigned char* data) {
    if (!ok()) return false;
    auto* png = static_cast<png_structp>(png_);
    std::vector<png_bytep> pointers(std::size_t(y1 - y0));
    const std::size_t row = std::size_t(width_) * std::size_t(channels_);
    for (std::size_t i = 0; i < pointers.size(); ++i) pointers[i] = const_cast<png_bytep>(data + i * row);
    png_bytepp rows = pointers.data();
    const png_uint_32 n = png_uint_32(pointers.size());
    guarded(png, error_, [&] { png_write_rows(png, rows, n); });
    return ok();
}

bool PngWriter::finish() {
    if (ok()) {
        auto* png = static_cast<png_structp>(png_);
        auto* info = static_cast<png_infop>(info_);
        guarded(png, error_, [&] { png_write_end(png, info); });
    }
    std::FILE* f = file_;
    file_ = nullptr;
    if (f && (std::fflush(f) != 0 || std::ferror(f) != 0) && ok()) error_ = "the file could not be written";
    if (f && std::fclose(f) != 0 && ok()) error_ = "the file could not be closed";
    close();
    return ok();
}

void PngWriter::abandon() {
    if (error_.empty()) error_ = "abandoned";
    close();
}

void PngWriter::close() {
    if (png_) {
        auto* png = static_cast<png_structp>(png_);
        auto* jump = static_cast<Jump*>(png_get_error_ptr(png));
        png_structp p = png;
        png_infop i = static_cast<png_infop>(info_);
        png_destroy_write_struct(&p, i ? &i : nullptr);
        delete jump;
        png_ = nullptr;
        info_ = nullptr;
    }
    if (file_) {
        std::fclose(file_);
        file_ = nullptr;
    }
}

}  // namespace shadelab
