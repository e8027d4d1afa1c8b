#include "image/png_writer.hpp"

#include "raster/parallel.hpp"

#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <csetjmp>
#include <cstring>
#include <memory>
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

// PNG's filter of one row (PNG specification, 9.2): the filter-type byte, then for "none" the row's bytes, for
// "up" each byte minus the byte above it (0 above the first row, as libpng's zeroed previous row).
void filter_row(bool up, const unsigned char* row, const unsigned char* above, std::size_t n, unsigned char* out) {
    out[0] = up ? PNG_FILTER_VALUE_UP : PNG_FILTER_VALUE_NONE;
    if (up && above) {
        for (std::size_t i = 0; i < n; ++i) out[1 + i] = static_cast<unsigned char>(row[i] - above[i]);
    } else {
        std::memcpy(out + 1, row, n);
    }
}

// What every piece of image_in_pieces shares.
struct PieceSettings {
    int level, mem_level;
    bool up;              // the "up" filter, else "none"
    std::size_t row;      // bytes of a row (before its filter byte)
    int batch_rows;       // rows filtered and deflated at a time
    int dictionary_rows;  // rows whose filtered bytes hold the 32 KB dictionary (<= batch_rows)
};

// One piece of the stream: its compressed bytes, the Adler-32 and length of its filtered rows.
struct Piece {
    std::unique_ptr<unsigned char[]> out;   // not initialised: only the bytes deflate writes are touched
    std::size_t size = 0;
    uLong adler = 1, in = 0;                 // adler32's start value
    std::string error;
};

// Rows [y0, y1) of the image filtered into `out`, one after another: `src` holds rows [from, y1), from = y0 - 1
// (the row above y0) or from = y0 = 0.
void filter_rows(const PieceSettings& s, const unsigned char* src, int from, int y0, int y1, unsigned char* out) {
    for (int y = y0; y < y1; ++y) {
        const unsigned char* row = src + std::size_t(y - from) * s.row;
        filter_row(s.up, row, y > 0 ? row - s.row : nullptr, s.row, out + std::size_t(y - y0) * (s.row + 1));
    }
}

constexpr std::size_t kWindow = 32768;       // deflate's window: how far back a match reaches

// The last min(32 KB, what there is) filtered bytes before row y0, set as the dictionary of a raw stream that
// starts at y0: the matches of its first rows reach back as those of one stream do. False if the source stopped.
bool set_dictionary(z_stream& zs, const PngRowSource& rows, const PieceSettings& s, int y0, unsigned char* scratch,
                    unsigned char* filtered) {
    const int d = std::min(y0, s.dictionary_rows), from = std::max(0, y0 - d - 1);
    const unsigned char* src = rows(from, y0, scratch);
    if (!src) return false;
    filter_rows(s, src, from, y0 - d, y0, filtered);
    const std::size_t have = std::size_t(d) * (s.row + 1), n = std::min(have, kWindow);
    return deflateSetDictionary(&zs, filtered + have - n, uInt(n)) == Z_OK;
}

// Rows [y0, y1) filtered and deflated into piece.out: a zlib stream's start (header) when y0 is 0, else raw
// deflate; ended by Z_FINISH when `last` (the trailer too when also y0 is 0), else by a sync flush (the
// stream continues on a byte boundary). False when the source stopped (piece.error empty) or zlib failed.
bool deflate_piece(const PngRowSource& rows, const PieceSettings& s, int y0, int y1, bool last, Piece& piece) {
    const std::size_t frow = s.row + 1;
    z_stream zs{};
    if (deflateInit2(&zs, s.level, Z_DEFLATED, y0 == 0 ? 15 : -15, s.mem_level, Z_DEFAULT_STRATEGY) != Z_OK) {
        piece.error = "zlib could not start a stream (out of memory?)";
        return false;
    }
    struct End {
        z_stream* z;
        ~End() { deflateEnd(z); }
    } end{&zs};
    const std::unique_ptr<unsigned char[]> scratch(new unsigned char[std::size_t(s.batch_rows + 1) * s.row]);
    const std::unique_ptr<unsigned char[]> filtered(new unsigned char[std::size_t(s.batch_rows) * frow]);
    if (y0 > 0 && !set_dictionary(zs, rows, s, y0, scratch.get(), filtered.get())) return false;
    piece.in = uLong(std::size_t(y1 - y0) * frow);
    const std::size_t cap = deflateBound(&zs, piece.in) + 64;   // and the sync flush's marker, the trailer
    piece.out.reset(new unsigned char[cap]);
    zs.next_out = piece.out.get();
    zs.avail_out = uInt(cap);
    for (int y = y0; y < y1; y += s.batch_rows) {
        const int e = std::min(y1, y + s.batch_rows), from = std::max(0, y - 1);
        const unsigned char* src = rows(from, e, scratch.get());
        if (!src) return false;
        filter_rows(s, src, from, y, e, filtered.get());
        const std::size_t n = std::size_t(e - y) * frow;
        piece.adler = adler32(piece.adler, filtered.get(), uInt(n));
        zs.next_in = filtered.get();
        zs.avail_in = uInt(n);
        const int flush = e < y1 ? Z_NO_FLUSH : (last ? Z_FINISH : Z_SYNC_FLUSH);
        const int r = deflate(&zs, flush);
        if (zs.avail_in != 0 || r != (flush == Z_FINISH ? Z_STREAM_END : Z_OK)) {
            piece.error = "zlib could not deflate the rows";
            return false;
        }
    }
    piece.size = cap - zs.avail_out;
    return true;
}

}  // namespace

PngWriter::PngWriter(const std::string& file, int width, int height, int channels, int zlib_level, int filter,
                     int zlib_mem_level)
    : width_(width), height_(height), channels_(channels), level_(std::clamp(zlib_level, 0, 9)), filter_(filter),
      mem_level_(std::clamp(zlib_mem_level, 1, 9)) {
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
        png_set_compression_level(png, level_);
        png_set_compression_strategy(png, Z_DEFAULT_STRATEGY);   // as OpenImageIO sets it (libpng's own: Z_FILTERED)
        png_set_compression_mem_level(png, mem_level_);
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

bool PngWriter::pieces_take_filter(int filter) { return filter == PNG_FILTER_NONE || filter == PNG_FILTER_UP; }

bool PngWriter::image_in_pieces(const PngRowSource& rows, int threads, std::size_t piece_bytes) {
    if (!ok()) return false;
    if (!pieces_take_filter(filter_)) {
        error_ = "internal: image_in_pieces called for row filter " + std::to_string(filter_);
        return false;
    }
    PieceSettings s{};
    s.level = level_;
    s.mem_level = mem_level_;
    s.up = filter_ == PNG_FILTER_UP;
    s.row = std::size_t(width_) * std::size_t(channels_);
    const std::size_t frow = s.row + 1;
    s.dictionary_rows = int((kWindow + frow - 1) / frow);
    s.batch_rows = std::max(s.dictionary_rows, int(std::max<std::size_t>(1, (std::size_t(1) << 18) / frow)));
    const int piece_rows = int(std::clamp<std::size_t>(piece_bytes / frow, 1, std::size_t(height_)));
    const int pieces = (height_ + piece_rows - 1) / piece_rows;
    std::vector<Piece> out(static_cast<std::size_t>(pieces));
    std::atomic<int> next{0};
    std::atomic<bool> stop{false};
    run_parallel(thread_count(threads, std::size_t(pieces)), [&](int) {
        for (int i = next++; i < pieces && !stop; i = next++) {
            const int y0 = i * piece_rows, y1 = std::min(height_, y0 + piece_rows);
            if (!deflate_piece(rows, s, y0, y1, i == pieces - 1, out[std::size_t(i)])) stop = true;
        }
    });
    for (const Piece& p : out)
        if (!p.error.empty()) error_ = p.error;
    if (stop && error_.empty()) error_ = "stopped";
    if (!ok()) return false;
    if (pieces > 1) {   // the stream's trailer: the Adler-32 of all filtered rows, big-endian, after the last piece
        uLong adler = out[0].adler;
        for (std::size_t i = 1; i < out.size(); ++i) adler = adler32_combine(adler, out[i].adler, z_off_t(out[i].in));
        Piece& last = out.back();
        for (int k = 3; k >= 0; --k) last.out[last.size++] = static_cast<unsigned char>(adler >> (8 * k));
    }
    // The stream in IDAT chunks of libpng's size (its compression buffer), each chunk across pieces as it falls.
    auto* png = static_cast<png_structp>(png_);
    std::size_t total = 0;
    for (const Piece& p : out) total += p.size;
    const std::size_t chunk = std::max<std::size_t>(1, png_get_compression_buffer_size(png));
    static const png_byte idat[5] = "IDAT", iend[5] = "IEND";
    guarded(png, error_, [&] {
        std::size_t piece = 0, at = 0;   // the next byte to write: out[piece].out[at]
        for (std::size_t done = 0; done < total;) {
            const std::size_t len = std::min(chunk, total - done);
            png_write_chunk_start(png, idat, png_uint_32(len));
            for (std::size_t left = len; left > 0;) {
                const std::size_t n = std::min(left, out[piece].size - at);
                png_write_chunk_data(png, out[piece].out.get() + at, n);
                left -= n;
                at += n;
                if (at == out[piece].size) ++piece, at = 0;
            }
            png_write_chunk_end(png);
            done += len;
        }
        png_write_chunk(png, iend, nullptr, 0);
    });
    ended_ = ok();
    return ok();
}

bool PngWriter::finish() {
    if (ok() && !ended_) {
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
