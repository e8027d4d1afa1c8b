#include "image/image.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <thread>
#include <utility>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "core/limits.hpp"
#include "image/exr_header.hpp"
#include "image/exr_writer.hpp"
#include "image/fits.hpp"
#include "image/image_io.hpp"
#include "image/png_writer.hpp"
#include "image/raster.hpp"
#include "raster/big_buffer.hpp"
#include "raster/parallel.hpp"

namespace fs = std::filesystem;

namespace shadelab {

double srgb_encode(double x) {
    if (!(x > 0.0)) return 0.0;
    if (x >= 1.0) return 1.0;
    return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

double srgb_decode(double v) {
    if (!(v > 0.0)) return 0.0;
    if (v >= 1.0) return 1.0;
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

namespace {

// Whether fragments [b, e) have strictly increasing pixel indices, each in [0, npix).
bool strictly_increasing(const std::int32_t* pixel, std::size_t b, std::size_t e, std::size_t npix) {
    for (std::size_t i = b; i < e; ++i)
        if (pixel[i] < 0 || std::size_t(pixel[i]) >= npix || (i > b && pixel[i] <= pixel[i - 1])) return false;
    return true;
}

// What composing an image needs of the fragments: an image size, and three planes of their count.
void check_composable(const FragmentBuffer& fb, const std::vector<float>& rgb) {
    if (fb.width <= 0 || fb.height <= 0)
        throw Error("cannot make an image from surface samples (the fragment buffer has no image size)");
    if (rgb.size() != 3 * fb.size()) throw Error("internal: shaded colour count does not match the fragment count");
}

// Whether all the fragments are in pixel order (strictly_increasing over the image), checked on `threads` threads.
bool in_pixel_order(const FragmentBuffer& fb, int threads) {
    const std::size_t n = fb.size(), npix = std::size_t(fb.width) * std::size_t(fb.height);
    std::vector<char> sorted(std::size_t(threads), 0);
    run_parallel(threads, [&](int t) {
        const std::size_t b = split(n, threads, t), e = split(n, threads, t + 1);
        sorted[std::size_t(t)] = strictly_increasing(fb.pixel.data(), b == 0 ? 0 : b - 1, e, npix) ? 1 : 0;
    });
    return std::all_of(sorted.begin(), sorted.end(), [](char c) { return c != 0; });
}

}  // namespace

namespace {

// The background bg in pixels [from, to), through put(p, red, green, blue, alpha). (A Put with a faster way
// overloads it: PutCoded.)
template <class Put>
void put_background(const Put& put, std::size_t from, std::size_t to, const float bg[4]) {
    const float bg_r = bg[0], bg_g = bg[1], bg_b = bg[2], bg_a = bg[3];
    for (std::size_t p = from; p < to; ++p) put(p, bg_r, bg_g, bg_b, bg_a);
}

// Pixels [p0, p1) of an RGBA image: the fragments [f0, f1), whose pixel indices are strictly increasing and
// inside the range, with their colour and alpha 1, every other pixel the background. Each pixel is written
// once, in address order (no background pass under the fragments), by put(p, red, green, blue, alpha) and
// put_background.
template <class Put>
void compose_range(const std::int32_t* pixel, const float* r, const float* g, const float* b, const float bg[4],
                   std::size_t p0, std::size_t p1, std::size_t f0, std::size_t f1, const Put& put) {
    auto background = [&](std::size_t from, std::size_t to) { put_background(put, from, to, bg); };
    std::size_t p = p0;
    for (std::size_t i = f0; i < f1; ++i) {
        const std::size_t q = std::size_t(pixel[i]);
        background(p, q);
        put(q, r[i], g[i], b[i], 1.0f);
        p = q + 1;
    }
    background(p, p1);
}

// compose_range(..., put_of(t)) over each of `threads` ranges of pixels, the fragments (in pixel order) that land
// in a range found by binary search; each thread writes its own range.
// compose_range over pixels [p0, p1) of fb's image (fragments in pixel order), with the fragments that land
// there, found by binary search.
template <class Put>
void compose_pixels(const FragmentBuffer& fb, const std::vector<float>& rgb, const float bg[4], std::size_t p0,
                    std::size_t p1, const Put& put) {
    const std::size_t n = fb.size();
    const std::int32_t* const pixel = fb.pixel.data();
    const float *r = rgb.data(), *g = r + n, *b = g + n;
    const std::size_t f0 = std::size_t(std::lower_bound(pixel, pixel + n, std::int32_t(p0)) - pixel);
    const std::size_t f1 = std::size_t(std::lower_bound(pixel + f0, pixel + n, std::int32_t(p1)) - pixel);
    compose_range(pixel, r, g, b, bg, p0, p1, f0, f1, put);
}

template <class PutOf>
void compose_ranges(const FragmentBuffer& fb, const std::vector<float>& rgb, const float bg[4], int threads,
                    const PutOf& put_of) {
    const std::size_t npix = std::size_t(fb.width) * std::size_t(fb.height);
    run_parallel(threads, [&](int t) {
        const std::size_t p0 = split(npix, threads, t), p1 = split(npix, threads, t + 1);
        put_of(t, [&](const auto& put) { compose_pixels(fb, rgb, bg, p0, p1, put); });
    });
}

// compose_range's two ways to write a pixel of `out`: ordinary stores, or (SSE2, out 16-byte aligned) one
// non-temporal 16-byte store, which writes past the caches. An ordinary store first reads the line it writes
// into the cache ("read for ownership"), so an image far larger than the caches costs its size twice in memory
// traffic; streamed, once. The pixels go in address order, so the write-combining buffers fill whole lines;
// the caller fences after its range, so that the streamed stores are visible before it reports the range done.
struct PutPixel {
    float* out;
    void operator()(std::size_t p, float r, float g, float b, float a) const {
        out[p * 4 + 0] = r;
        out[p * 4 + 1] = g;
        out[p * 4 + 2] = b;
        out[p * 4 + 3] = a;
    }
};
#if defined(__SSE2__)
struct StreamPixel {
    float* out;
    void operator()(std::size_t p, float r, float g, float b, float a) const {
        _mm_stream_ps(out + p * 4, _mm_setr_ps(r, g, b, a));
    }
};
#endif

// Images of at least this many bytes (512 x 512 RGBA floats and larger) are written with streamed stores: an
// ordinary store first reads its line ("read for ownership"), and a renderer's image, kept from frame to frame,
// is not in the caches by the time the next frame writes it; below it, ordinary stores leave the image in the
// cache. Measured on a 2-core AMD EPYC (Zen 4) host, a disc covering half the image, best of 15, three
// alternating rounds: 4096 x 4096 13.6-15.0 ms streamed against 14.4-17.5 plain, 2048 x 2048 3.9-4.0 against
// 4.4-4.7 (the threshold was 64 MB then). On the 2-core Intel Xeon host (2026-12-05, bench_e2e, the three meshes,
// two alternating rounds, kept buffers): 1920 x 1080 (33 MB) 2.17-2.45 ms plain against 0.85-1.12 streamed,
// 512 x 512 (4 MB) 0.16-0.48 against 0.12-0.25.
constexpr std::size_t kStreamImageBytes = std::size_t(4) << 20;

// Any order, one thread: the background everywhere, then the fragments (later ones win), each checked.
void compose_unordered(const FragmentBuffer& fb, const std::vector<float>& rgb, const float bg[4], float* out) {
    const std::size_t n = fb.size(), npix = std::size_t(fb.width) * std::size_t(fb.height);
    for (std::size_t p = 0; p < npix; ++p)
        for (int c = 0; c < 4; ++c) out[p * 4 + std::size_t(c)] = bg[c];
    for (std::size_t i = 0; i < n; ++i) {
        const std::int32_t q = fb.pixel[i];
        if (q < 0 || std::size_t(q) >= npix)
            throw Error("internal: fragment " + std::to_string(i) + " has pixel index " + std::to_string(q) +
                        " outside the " + std::to_string(fb.width) + "x" + std::to_string(fb.height) + " image");
        for (std::size_t c = 0; c < 3; ++c) out[std::size_t(q) * 4 + c] = rgb[c * n + i];
        out[std::size_t(q) * 4 + 3] = 1.0f;
    }
}

// The background of `background` as compose_range takes it.
struct Background {
    float v[4];
    explicit Background(const glm::dvec4& b) : v{float(b[0]), float(b[1]), float(b[2]), float(b[3])} {}
};

}  // namespace

void compose_image_into(const FragmentBuffer& fb, const std::vector<float>& rgb, const glm::dvec4& background,
                        Image& img) {
    check_composable(fb, rgb);
    const std::size_t npix = std::size_t(fb.width) * std::size_t(fb.height);
    img.width = fb.width;
    img.height = fb.height;
    img.channels = 4;
    size_for_frame(img.pixels, npix * 4);
    const Background bg(background);
    float* const out = img.pixels.data();
    // Rows in parallel when the fragments come in pixel order (as the rasteriser emits them): each thread
    // writes its own pixel range, with the fragments that land in it, found by binary search.
    const int threads = thread_count(0, npix / 65536);
    if (!in_pixel_order(fb, threads)) return compose_unordered(fb, rgb, bg.v, out);
#if defined(__SSE2__)
    const bool stream = npix * 4 * sizeof(float) >= kStreamImageBytes && std::uintptr_t(out) % 16 == 0;
#endif
    compose_ranges(fb, rgb, bg.v, threads, [&](int, const auto& compose) {
#if defined(__SSE2__)
        if (stream) {
            compose(StreamPixel{out});
            _mm_sfence();
            return;
        }
#endif
        compose(PutPixel{out});
    });
}

Image compose_image(const FragmentBuffer& fb, const std::vector<float>& rgb, const glm::dvec4& background) {
    Image img;
    compose_image_into(fb, rgb, background, img);
    return img;
}

// The 8-bit code lround(255 srgb_encode(v)) of every float, from thresholds: srgb_encode and the rounding are
// monotonic, so code k is taken exactly by the floats v >= t[k], where t[k] is the least float whose code is
// >= k, found once by bisection on the float's bit pattern (positive floats order as their bits do). A table
// indexed by the top bits of v gives the code of the smallest float of its bucket; the thresholds inside
// the bucket (at most a few) are stepped over. Same codes as evaluating the curve, which tests/test_image.cpp
// checks on a sweep of every 97th float in [0, 1] and around every threshold.
struct Srgb8Table {
    static constexpr int kShift = 15;
    float t[257];                                 // t[0] = 0 (unused), t[256] = +inf
    std::vector<std::uint8_t> start;              // by bits >> kShift, for floats in [0, 1)

    static int direct(float v) { return int(std::lround(srgb_encode(double(v)) * 255.0)); }
    static float of_bits(std::uint32_t b) {
        float f;
        std::memcpy(&f, &b, sizeof f);
        return f;
    }
    Srgb8Table() {
        const std::uint32_t one = 0x3F800000u;   // 1.0f
        t[0] = 0.0f;
        t[256] = std::numeric_limits<float>::infinity();
        for (int k = 1; k <= 255; ++k) {
            std::uint32_t lo = 0, hi = one;       // code(lo) < k <= code(hi)
            while (hi - lo > 1) {
                const std::uint32_t mid = lo + (hi - lo) / 2;
                (direct(of_bits(mid)) >= k ? hi : lo) = mid;
            }
            t[k] = of_bits(hi);
        }
        start.resize(one >> kShift);
        for (std::uint32_t b = 0; b < (one >> kShift); ++b) start[b] = std::uint8_t(direct(of_bits(b << kShift)));
    }
    std::uint8_t code(float v) const {
        if (!(v > 0.0f)) return 0;
        if (v >= 1.0f) return 255;
        std::uint32_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        int k = start[bits >> kShift];
        while (v >= t[k + 1]) ++k;
        return std::uint8_t(k);
    }
};

const Srgb8Table& srgb8_table() {
    static const Srgb8Table table;
    return table;
}

std::uint8_t srgb8_code(float linear) { return srgb8_table().code(linear); }

namespace {

// One RGBA pixel v coded into o: colour channels through the table, alpha clamped and rounded,
// floor(255 v + 0.5), which is lround's value here (255 v is exact in double and non-negative). A pixel of four
// zeros (the background of most renders) is coded at once. Returns how many of the four are NaN or Inf (coded 0
// or 255; write_image refuses such images).
inline std::size_t code_pixel(const Srgb8Table& table, const float* v, unsigned char* o) {
    if (v[0] == 0.0f && v[1] == 0.0f && v[2] == 0.0f && v[3] == 0.0f) {
        o[0] = o[1] = o[2] = o[3] = 0;
        return 0;
    }
    std::size_t bad = 0;
    for (int c = 0; c < 4; ++c) bad += std::isfinite(v[c]) ? 0 : 1;
    for (int c = 0; c < 3; ++c) o[c] = table.code(v[c]);
    const double a = v[3] > 0.0f ? std::min(double(v[3]), 1.0) : 0.0;   // NaN: 0
    o[3] = static_cast<unsigned char>(int(a * 255.0 + 0.5));
    return bad;
}

// Values [b, e) of `img` (whole pixels) coded into out[0, e - b): code_pixel's codes (every value through the
// table when the image is not RGBA). Returns how many of the values are NaN or Inf.
std::size_t encode_srgb8_values(const Srgb8Table& table, const Image& img, std::size_t b, std::size_t e,
                                unsigned char* out) {
    const std::size_t channels = std::size_t(img.channels);
    const float* const in = img.pixels.data();
    std::size_t bad = 0;
    if (channels != 4) {
        for (std::size_t i = b; i < e; ++i) {
            bad += std::isfinite(in[i]) ? 0 : 1;
            out[i - b] = table.code(in[i]);
        }
        return bad;
    }
    for (std::size_t i = b; i < e; i += 4) bad += code_pixel(table, in + i, out + (i - b));
    return bad;
}

// The number of NaN or Inf values in `img`, counted on all threads (a pass over 256 MB at 4096 x 4096).
std::size_t count_non_finite(const Image& img) {
    const std::size_t nvalues = img.pixels.size();
    const int threads = thread_count(0, nvalues / (1 << 20));
    std::vector<std::size_t> bad_of(std::size_t(threads), 0);
    run_parallel(threads, [&](int t) {
        std::size_t b = 0;
        for (std::size_t i = split(nvalues, threads, t), e = split(nvalues, threads, t + 1); i < e; ++i)
            b += std::isfinite(img.pixels[i]) ? 0 : 1;
        bad_of[std::size_t(t)] = b;
    });
    std::size_t bad = 0;
    for (std::size_t b : bad_of) bad += b;
    return bad;
}

void refuse_non_finite(const std::string& path, std::size_t bad) {
    if (bad) throw Error("refusing to write '" + path + "': " + std::to_string(bad) + " pixel values are NaN or Inf");
}

}  // namespace

std::vector<unsigned char> encode_srgb8(const Image& img) {
    const Srgb8Table& table = srgb8_table();
    std::vector<unsigned char> px(img.pixels.size());
    const std::size_t channels = std::max<std::size_t>(1, std::size_t(img.channels)), pixels = px.size() / channels;
    const int threads = thread_count(0, pixels / 65536);
    run_parallel(threads, [&](int t) {
        const std::size_t b = split(pixels, threads, t) * channels, e = split(pixels, threads, t + 1) * channels;
        encode_srgb8_values(table, img, b, e, px.data() + b);
    });
    return px;
}

namespace {

// compose_range's way to write a pixel coded for an 8-bit output (code_pixel), counting NaN and Inf in `bad`;
// the background's code is worked out once, unless it holds a NaN or an Inf (then every pixel of it is coded
// and counted, as encode_srgb8 would).
struct PutCoded {
    const Srgb8Table& table;
    unsigned char* out;       // pixel `first`'s code
    bool bg_finite;
    std::uint32_t bg_code;
    std::size_t& bad;
    std::size_t first = 0;    // the image's first pixel in `out` (a block of rows: its first pixel)
    void operator()(std::size_t p, float r, float g, float b, float a) const {
        const float v[4] = {r, g, b, a};
        bad += code_pixel(table, v, out + (p - first) * 4);
    }
};

void put_background(const PutCoded& put, std::size_t from, std::size_t to, const float bg[4]) {
    if (!put.bg_finite) {
        for (std::size_t p = from; p < to; ++p) put(p, bg[0], bg[1], bg[2], bg[3]);
        return;
    }
    for (std::size_t p = from; p < to; ++p) std::memcpy(put.out + (p - put.first) * 4, &put.bg_code, 4);
}

// The background's code (PutCoded's bg_code), and whether it has one (false: it holds NaN or Inf).
bool background_code(const Srgb8Table& table, const float bg[4], std::uint32_t& word) {
    unsigned char code[4];
    const bool finite = code_pixel(table, bg, code) == 0;
    std::memcpy(&word, code, 4);
    return finite;
}

}  // namespace

void compose_image_srgb8_into(const FragmentBuffer& fb, const std::vector<float>& rgb, const glm::dvec4& background,
                              const std::string& path, Srgb8Image& img) {
    check_composable(fb, rgb);
    const std::size_t npix = std::size_t(fb.width) * std::size_t(fb.height);
    const int threads = thread_count(0, npix / 65536);
    const Background bg(background);
    img.width = fb.width;
    img.height = fb.height;
    img.channels = 4;
    if (!in_pixel_order(fb, threads)) {
        // Any order: through the float image, on one thread (compose_unordered), then coded.
        Image linear(fb.width, fb.height, 4);
        compose_unordered(fb, rgb, bg.v, linear.pixels.data());
        refuse_non_finite(path, count_non_finite(linear));
        img.bytes = encode_srgb8(linear);
        return;
    }
    size_for_frame(img.bytes, npix * 4);
    const Srgb8Table& table = srgb8_table();
    std::uint32_t bg_word;
    const bool bg_finite = background_code(table, bg.v, bg_word);
    std::vector<std::size_t> bad_of(std::size_t(threads), 0);
    compose_ranges(fb, rgb, bg.v, threads, [&](int t, const auto& compose) {
        std::size_t bad = 0;   // (a thread's own: counters side by side in bad_of would share a cache line)
        compose(PutCoded{table, img.bytes.data(), bg_finite, bg_word, bad});
        bad_of[std::size_t(t)] = bad;
    });
    std::size_t bad = 0;
    for (std::size_t k : bad_of) bad += k;
    refuse_non_finite(path, bad);
}

Encoding encoding_for(const std::string& path) {
    const std::string ext = lower_ext(path);
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".tga" || ext == ".webp")
        return Encoding::Srgb8;
    // No .pfm: Debian's OpenImageIO 2.4 reads PFM but has no PFM writer.
    if (ext == ".exr" || ext == ".hdr" || ext == ".tif" || ext == ".tiff" || ext == ".fits" || ext == ".fit" ||
        ext == ".fts")
        return Encoding::Linear;
    throw Error("output '" + path + "' has an unsupported extension: use " + std::string(kOutputFormats));
}

namespace {

// Where write_srgb8_pipelined sends its rows: OpenImageIO's writer (the image plug-in) or libpng's
// (image/png_writer.hpp). `abandon` is called before a refusal: it leaves the file so that its library has
// nothing to complain about on the terminal (libpng prints "No IDATs written" for a PNG abandoned half-way
// through OpenImageIO), after which the temporary file is removed.
struct Rows8Sink {
    std::function<bool(int y0, int y1, const unsigned char* rows)> write;
    std::function<void()> abandon;
};

// Rows a block of about 1 MB holds (at least one), for handing 8-bit rows to a Rows8Sink.
int rows_per_block(std::size_t row_bytes) {
    return std::max(1, int((std::size_t(1) << 20) / std::max<std::size_t>(1, row_bytes)));
}

// The 8-bit image written block by block of rows: a second thread codes block k + 1 while the writer
// compresses block k (PNG's deflate runs on one thread), so the coding costs almost no wall time on a
// machine with a free core, instead of a whole pass over the float image before the first byte is written.
// NaN and Inf are counted while coding: the first block holding one stops the write with write_image's
// refusal (the temporary file is then removed), so no separate pass over the float image is needed.
bool write_srgb8_pipelined(const Rows8Sink& sink, const Image& img, const std::string& path) {
    const Srgb8Table& table = srgb8_table();
    const std::size_t row = std::size_t(img.width) * std::size_t(img.channels);
    const int block = rows_per_block(row);
    const int blocks = (img.height + block - 1) / block;
    std::vector<unsigned char> buf[2];
    for (auto& b : buf) b.resize(std::size_t(block) * row);
    std::size_t bad[2] = {0, 0};
    auto code = [&](int k) {
        const std::size_t y0 = std::size_t(k) * std::size_t(block);
        const std::size_t y1 = std::min(std::size_t(img.height), y0 + std::size_t(block));
        bad[k % 2] = encode_srgb8_values(table, img, y0 * row, y1 * row, buf[k % 2].data());
    };
    code(0);
    bool ok = true;
    for (int k = 0; k < blocks && ok; ++k) {
        if (bad[k % 2]) {
            sink.abandon();
            refuse_non_finite(path, count_non_finite(img));
        }
        std::thread next;
        if (k + 1 < blocks) {
            try {
                next = std::thread(code, k + 1);
            } catch (...) {   // no thread: code it here after this block's write (same bytes)
            }
        }
        const int y0 = k * block, y1 = std::min(img.height, y0 + block);
        ok = sink.write(y0, y1, buf[k % 2].data());
        if (next.joinable()) next.join();
        else if (k + 1 < blocks) code(k + 1);
    }
    return ok;
}

// Rows of an image already coded (compose_image_srgb8), handed over in blocks of about 1 MB.
bool write_srgb8_rows(const Rows8Sink& sink, const Srgb8Image& img) {
    const std::size_t row = std::size_t(img.width) * std::size_t(img.channels);
    const int block = rows_per_block(row);
    for (int y0 = 0; y0 < img.height; y0 += block)
        if (!sink.write(y0, std::min(img.height, y0 + block), img.bytes.data() + std::size_t(y0) * row)) return false;
    return true;
}

// How an image's 8-bit rows reach a Rows8Sink: write_srgb8_pipelined for a float image, write_srgb8_rows for a
// coded one.
using Rows8Source = std::function<bool(const Rows8Sink&)>;

// Encodes an image of `spec`'s size into `file` with OpenImageIO, in the image plug-in: 8-bit sRGB rows from
// `rows8` when spec.srgb8, else the linear floats `floats`. Returns false with OpenImageIO's reason in `why` when
// writing failed; throws when no plug-in writes `path`'s format.
bool write_with_oiio(const std::string& file, const std::string& path, const image_io::WriteSpec& spec,
                     const Rows8Source& rows8, const float* floats, std::string& why) {
    const image_io::Plugin& io = image_io::plugin();
    bool no_format = false;
    image_io::Writer* out = io.writer_open(file, spec, why, no_format);
    if (no_format) throw Error("cannot write '" + path + "': " + why);
    if (!out) return false;   // the file could not be created: write_file_atomically says why and what to do
    bool ok = true;
    try {
        if (spec.srgb8) {
            int written = 0;   // rows [0, written) are in the file
            const Rows8Sink sink{[&](int y0, int y1, const unsigned char* rows) {
                                     written = y1;
                                     return io.writer_rows8(out, y0, y1, rows);
                                 },
                                 [&] {
                                     // the rows left as zeros, and the file closed (see Rows8Sink)
                                     const std::vector<unsigned char> zeros(std::size_t(spec.width) * std::size_t(spec.channels), 0);
                                     for (int y = written; y < spec.height; ++y) io.writer_rows8(out, y, y + 1, zeros.data());
                                     std::string ignored;
                                     io.writer_close(std::exchange(out, nullptr), ignored);
                                 }};
            ok = rows8(sink);
        } else {
            ok = io.writer_float(out, floats);
        }
    } catch (...) {
        std::string ignored;
        if (out) io.writer_close(out, ignored);
        throw;
    }
    std::string close_why;
    const bool closed = io.writer_close(out, close_why);
    if (!ok || !closed) why = close_why;
    return ok && closed;
}

// The filtered rows of a PNG deflated in one piece of this size a thread at a time (PngWriter::image_in_pieces).
constexpr std::size_t kPngPieceBytes = std::size_t(1) << 20;

// Whether write_png_direct deflates in pieces on several threads: the options' threads (0: all) are more than
// one, their filter is one the pieces take, and the image's filtered rows fill at least two pieces (a smaller
// image deflates in a few milliseconds).
bool png_in_pieces(int width, int height, int channels, const ImageWriteOptions& options) {
    const double filtered = double(height) * (double(width) * double(channels) + 1.0);
    return PngWriter::pieces_take_filter(options.png_filter) && filtered >= 2.0 * double(kPngPieceBytes) &&
           thread_count(options.png_threads, 2) > 1;
}

// A PNG of width x height x channels through libpng itself (image/png_writer.hpp): its rows from `pieces`,
// deflated on all threads, where png_in_pieces says so, else from `rows8` (null: only pieces are asked for) in
// libpng's own single stream.
bool write_png_direct(const std::string& file, int width, int height, int channels, const Rows8Source& rows8,
                      const PngRowSource& pieces, const ImageWriteOptions& options, std::string& why) {
    PngWriter png(file, width, height, channels, options.png_level, options.png_filter, options.png_mem_level);
    const Rows8Sink sink{[&](int y0, int y1, const unsigned char* rows) { return png.rows(y0, y1, rows); },
                         [&] { png.abandon(); }};
    const bool ok = png.ok() &&
                    (png_in_pieces(width, height, channels, options) || !rows8
                         ? png.image_in_pieces(pieces, options.png_threads, kPngPieceBytes)
                         : rows8(sink)) &&
                    png.finish();
    if (!ok) why = png.error();
    return ok;
}

}  // namespace

void write_image(const std::string& path, const Image& img, const ImageWriteOptions& options) {
    // OpenImageIO 2.4's FITS plug-in shifts rows and ignores BSCALE/BZERO (see image/fits.hpp).
    if (is_fits_path(path)) return write_fits(path, img);
    const Encoding enc = encoding_for(path);
    const std::string ext = lower_ext(path);
    if (ext == ".hdr" && img.channels != 3) {
        // Radiance HDR holds RGB only: the colour channels are written (grey as RGB), alpha is dropped.
        Image rgb(img.width, img.height, 3);
        for (std::size_t p = 0; p < std::size_t(img.width) * std::size_t(img.height); ++p)
            for (int c = 0; c < 3; ++c) rgb.pixels[p * 3 + c] = img.pixels[p * std::size_t(img.channels) + std::size_t(img.channels >= 3 ? c : 0)];
        return write_image(path, rgb, options);
    }
    // Float formats are checked first, in a pass of its own; 8-bit ones while coding (write_srgb8_pipelined).
    if (enc != Encoding::Srgb8) refuse_non_finite(path, count_non_finite(img));
    // PNG and EXR, what render and batch write, without the image plug-in (image/image_io.hpp says why); the
    // temporary file keeps the extension: OpenImageIO picks the format from it.
    const bool direct_png = ext == ".png" && img.channels >= 1 && img.channels <= 4;
    const bool direct_exr = ext == ".exr" && exr_direct(options.exr_compression, img.channels);
    write_file_atomically(
        path, "image",
        [&](const std::string& tmp, std::string& why) {
            const Rows8Source rows8 = [&](const Rows8Sink& sink) { return write_srgb8_pipelined(sink, img, path); };
            if (direct_png) {
                // each piece codes its own rows; the first NaN or Inf stops every piece, then the refusal
                const Srgb8Table& table = srgb8_table();
                const std::size_t row = std::size_t(img.width) * std::size_t(img.channels);
                std::atomic<bool> bad{false};
                const PngRowSource pieces = [&](int y0, int y1, unsigned char* scratch) -> const unsigned char* {
                    if (encode_srgb8_values(table, img, std::size_t(y0) * row, std::size_t(y1) * row, scratch) == 0)
                        return scratch;
                    bad = true;
                    return nullptr;
                };
                const bool ok = write_png_direct(tmp, img.width, img.height, img.channels, rows8, pieces, options, why);
                if (bad) refuse_non_finite(path, count_non_finite(img));
                return ok;
            }
            if (direct_exr) return write_exr(tmp, img, options.exr_compression, why);
            return write_with_oiio(tmp, path, image_io::write_spec(img, enc == Encoding::Srgb8, options), rows8,
                                   img.pixels.data(), why);
        },
        fs::path(path).extension().string());
}

void write_image(const std::string& path, const Srgb8Image& img, const ImageWriteOptions& options) {
    if (encoding_for(path) != Encoding::Srgb8)
        throw Error("internal: an 8-bit image given for '" + path + "', a format of linear floats");
    if (img.width < 1 || img.height < 1 || img.channels < 1 || img.channels > 4 ||
        img.bytes.size() != std::size_t(img.width) * std::size_t(img.height) * std::size_t(img.channels))
        throw Error("internal: the 8-bit image for '" + path + "' does not hold width x height x channels bytes");
    const std::string ext = lower_ext(path);
    const Rows8Source rows8 = [&](const Rows8Sink& sink) { return write_srgb8_rows(sink, img); };
    const image_io::WriteSpec spec = image_io::write_spec(img.width, img.height, img.channels, true, options);
    write_file_atomically(
        path, "image",
        [&](const std::string& tmp, std::string& why) {
            const std::size_t row = std::size_t(img.width) * std::size_t(img.channels);
            const PngRowSource pieces = [&](int y0, int, unsigned char*) {
                return img.bytes.data() + std::size_t(y0) * row;
            };
            if (ext == ".png")
                return write_png_direct(tmp, img.width, img.height, img.channels, rows8, pieces, options, why);
            return write_with_oiio(tmp, path, spec, rows8, nullptr, why);
        },
        fs::path(path).extension().string());
}

bool png_composed_in_pieces(const std::string& path, int width, int height, const ImageWriteOptions& options) {
    return lower_ext(path) == ".png" && png_in_pieces(width, height, 4, options);
}

void write_image_composed(const std::string& path, const FragmentBuffer& fb, const std::vector<float>& rgb,
                          const glm::dvec4& background, const ImageWriteOptions& options) {
    check_composable(fb, rgb);
    const std::size_t width = std::size_t(fb.width);
    if (!png_composed_in_pieces(path, fb.width, fb.height, options) ||
        !in_pixel_order(fb, thread_count(0, width * std::size_t(fb.height) / 65536))) {
        Srgb8Image img;
        compose_image_srgb8_into(fb, rgb, background, path, img);
        return write_image(path, img, options);
    }
    const Background bg(background);
    const Srgb8Table& table = srgb8_table();
    std::uint32_t bg_word;
    const bool bg_finite = background_code(table, bg.v, bg_word);
    std::atomic<bool> bad{false};
    // Each piece's rows composed and coded into its scratch.
    const PngRowSource rows = [&](int y0, int y1, unsigned char* scratch) -> const unsigned char* {
        const std::size_t p0 = std::size_t(y0) * width, p1 = std::size_t(y1) * width;
        std::size_t nbad = 0;
        compose_pixels(fb, rgb, bg.v, p0, p1, PutCoded{table, scratch, bg_finite, bg_word, nbad, p0});
        if (nbad == 0) return scratch;
        bad = true;
        return nullptr;
    };
    write_file_atomically(
        path, "image",
        [&](const std::string& tmp, std::string& why) {
            const bool ok = write_png_direct(tmp, fb.width, fb.height, 4, nullptr, rows, options, why);
            if (bad) {   // the refusal with compose_image_srgb8_into's message and count
                Srgb8Image counted;
                compose_image_srgb8_into(fb, rgb, background, path, counted);
                throw Error("internal: a non-finite value stopped the PNG of '" + path + "' but was not found again");
            }
            return ok;
        },
        ".png");
}

namespace {

// OpenEXR's magic number (the first four bytes of every EXR file, whatever its name).
bool is_exr_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    char magic[4] = {};
    return in.read(magic, 4) && magic[0] == 0x76 && magic[1] == 0x2f && magic[2] == 0x31 && magic[3] == 0x01;
}

// An open file of the image plug-in, closed when it goes out of scope.
struct OpenReader {
    const image_io::Plugin& io;
    image_io::Reader* r;
    ~OpenReader() { io.reader_close(r); }
};

}  // namespace

Image read_image(const std::string& path) {
    if (is_fits_path(path)) return read_fits(path);
    if (is_gdal_path(path)) return read_raster_band(path);   // ISIS3 cubes, PDS3/PDS4, GeoTIFF[band]
    std::error_code ec;
    if (!fs::exists(path, ec)) throw Error("image '" + path + "' not found: check the path");
    // An EXR header sizes OpenEXR's decode buffers, which are allocated when the file is opened: check it first.
    if (is_exr_file(path)) check_exr_header(path);
    const image_io::Plugin& io = image_io::plugin();
    std::string why;
    image_io::Reader* opened = io.reader_open(path, why);   // straight alpha kept as stored (PNG)
    if (!opened) throw Error("cannot read image '" + path + "': " + why);
    const OpenReader in{io, opened};
    const image_io::Info spec = io.reader_info(in.r);
    // The header's size is checked before the pixels are allocated: a header of a few bytes may ask for
    // gigabytes. Deflate (PNG) packs at most 1032:1, so a PNG smaller than its raw pixels / 1032 cannot
    // hold them; for every format the float image and its native copy must fit in the memory limit.
    const std::string dims = std::to_string(spec.width) + "x" + std::to_string(spec.height);
    if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1 || spec.nchannels > 64)
        throw Error("image '" + path + "': its header says " + dims + " with " + std::to_string(spec.nchannels) +
                    " channels: not an image that can be read");
    if (spec.depth != 1 || spec.deep)
        throw Error("image '" + path + "' is a " + (spec.deep ? std::string("deep") : "volume (depth " + std::to_string(spec.depth) + ")") +
                    " image, which shadelab does not read: flatten it to a 2D image first");
    const double raw = double(spec.width) * double(spec.height) * double(spec.native_pixel_bytes);
    std::error_code size_ec;
    const auto file_bytes = fs::file_size(path, size_ec);
    if (!size_ec && spec.format_name == "png" && double(file_bytes) * 1032.0 < raw)
        throw Error("image '" + path + "' is truncated or corrupt: its header says " + dims + " (" + format_bytes(raw) +
                    " of pixels), which a " + format_bytes(double(file_bytes)) + " PNG cannot hold");
    const double tile = spec.tiled ? double(spec.tile_width) * double(spec.tile_height) * double(std::max(spec.tile_depth, 1)) *
                                         double(spec.nchannels) * 4.0
                                   : 0.0;
    check_memory("image '" + path + "' (" + dims + ")",
                 double(spec.width) * double(spec.height) * double(spec.nchannels) * 4.0 + raw + tile);
    // A format with random access (EXR, TIFF) shows whether the file holds its last row (or tile) before
    // the whole image is allocated: a truncated file is refused for the cost of one row.
    if ((spec.format_name == "openexr" || spec.format_name == "tiff") && !io.reader_probe_last(in.r, why))
        throw Error("image '" + path + "' is truncated or corrupt: its header says " + dims +
                    " but its last row cannot be read (" + why + ")");
    Image img(spec.width, spec.height, spec.nchannels);
    if (!io.reader_read_float(in.r, img.pixels.data(), why)) throw Error("cannot decode image '" + path + "': " + why);
    const bool srgb = spec.color_space == "sRGB" || (spec.color_space.empty() && spec.format_bytes == 1);
    if (srgb) {
        for (std::size_t i = 0; i < img.pixels.size(); ++i) {
            const bool alpha = spec.alpha_channel >= 0 && int(i % std::size_t(spec.nchannels)) == spec.alpha_channel;
            if (!alpha) img.pixels[i] = float(srgb_decode(img.pixels[i]));
        }
    }
    return img;
}

}  // namespace shadelab
