#include "image/fits.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/limits.hpp"

namespace fs = std::filesystem;

namespace shadelab {

namespace {

constexpr std::size_t kBlock = 2880;   // FITS logical record
constexpr std::size_t kCard = 80;

std::string lower_ext(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(' ');
    if (b == std::string::npos) return "";
    return s.substr(b, s.find_last_not_of(' ') - b + 1);
}

// "KEY     = value / comment" -> value text (quotes removed for strings).
std::string card_value(const std::string& card) {
    if (card.size() < 10 || card.compare(8, 2, "= ") != 0) return "";
    std::string v = card.substr(10);
    const auto q = v.find_first_not_of(' ');
    if (q != std::string::npos && v[q] == '\'') {
        std::string out;
        for (std::size_t i = q + 1; i < v.size(); ++i) {
            if (v[i] == '\'') {
                if (i + 1 < v.size() && v[i + 1] == '\'') { out += '\''; ++i; continue; }
                break;
            }
            out += v[i];
        }
        return trim(out);
    }
    const auto slash = v.find('/');
    return trim(slash == std::string::npos ? v : v.substr(0, slash));
}

long long card_int(const std::map<std::string, std::string>& kw, const std::string& key, const std::string& path) {
    auto it = kw.find(key);
    if (it == kw.end()) throw Error("FITS file '" + path + "' has no " + key + " keyword: not a valid FITS image");
    char* end = nullptr;
    const long long v = std::strtoll(it->second.c_str(), &end, 10);
    if (it->second.empty() || *end != '\0')
        throw Error("FITS file '" + path + "': " + key + " = '" + it->second + "' is not an integer");
    return v;
}

double card_double(const std::map<std::string, std::string>& kw, const std::string& key, double def) {
    auto it = kw.find(key);
    if (it == kw.end()) return def;
    std::string t = it->second;
    std::replace(t.begin(), t.end(), 'D', 'E');   // FITS allows Fortran exponents
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    return (!t.empty() && *end == '\0' && std::isfinite(v)) ? v : def;
}

template <typename T>
T load_be(const unsigned char* p) {
    unsigned char b[sizeof(T)];
    for (std::size_t i = 0; i < sizeof(T); ++i) b[i] = p[sizeof(T) - 1 - i];
    T v;
    std::memcpy(&v, b, sizeof(T));
    return v;
}

std::string card(const std::string& key, const std::string& value_field, const std::string& comment = "") {
    std::string c = key;
    c.resize(8, ' ');
    c += "= ";
    std::string v = value_field;
    if (v.size() < 20) v = std::string(20 - v.size(), ' ') + v;   // fixed format: right-justified in 11-30
    c += v;
    if (!comment.empty()) c += " / " + comment;
    c.resize(kCard, ' ');
    return c;
}

bool looks_numeric(const std::string& s) {
    if (s.empty()) return false;
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    return *end == '\0' && std::isfinite(v);
}

}  // namespace

bool is_fits_path(const std::string& path) {
    const std::string e = lower_ext(path);
    return e == ".fits" || e == ".fit" || e == ".fts";
}

Image read_fits(const std::string& path, std::map<std::string, std::string>* keywords) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw Error("image '" + path + "' not found: check the path");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot open FITS file '" + path + "' for reading");

    std::map<std::string, std::string> kw;
    std::size_t header_bytes = 0;
    bool ended = false;
    std::vector<char> block(kBlock);
    while (!ended) {
        if (!in.read(block.data(), std::streamsize(kBlock)))
            throw Error("FITS file '" + path + "' ends inside its header (no END card): the file is truncated");
        header_bytes += kBlock;
        for (std::size_t c = 0; c < kBlock / kCard; ++c) {
            const std::string cd(block.data() + c * kCard, kCard);
            const std::string key = trim(cd.substr(0, 8));
            if (header_bytes == kBlock && c == 0 && key != "SIMPLE")
                throw Error("'" + path + "' is not a FITS file (it does not start with SIMPLE)");
            if (key == "END") { ended = true; break; }
            if (!key.empty() && key != "COMMENT" && key != "HISTORY" && !kw.count(key)) kw[key] = card_value(cd);
        }
        if (header_bytes > 1000 * kBlock) throw Error("FITS file '" + path + "' has no END card in 1000 header blocks");
    }
    if (kw["SIMPLE"] != "T") throw Error("FITS file '" + path + "' says SIMPLE = F: it does not conform to FITS");
    const long long bitpix = card_int(kw, "BITPIX", path);
    const long long naxis = card_int(kw, "NAXIS", path);
    if (naxis == 0)
        throw Error("FITS file '" + path + "' has no image in its primary HDU (NAXIS = 0); images in extensions "
                    "are not read: copy the image HDU to a primary HDU first");
    if (naxis != 2 && naxis != 3)
        throw Error("FITS file '" + path + "' has NAXIS = " + std::to_string(naxis) + ": only 2-D images (or 3 colour planes) are read");
    const long long w = card_int(kw, "NAXIS1", path), h = card_int(kw, "NAXIS2", path);
    const long long planes = naxis == 3 ? card_int(kw, "NAXIS3", path) : 1;
    if (w < 1 || h < 1 || w > 65536 || h > 65536)
        throw Error("FITS file '" + path + "': image size " + std::to_string(w) + "x" + std::to_string(h) + " is not supported");
    if (planes != 1 && planes != 3)
        throw Error("FITS file '" + path + "' has " + std::to_string(planes) + " planes: only 1 (grey) or 3 (RGB) are read");
    std::size_t bytes = 0;
    switch (bitpix) {
        case 8: bytes = 1; break;
        case 16: bytes = 2; break;
        case 32: bytes = 4; break;
        case 64: bytes = 8; break;
        case -32: bytes = 4; break;
        case -64: bytes = 8; break;
        default: throw Error("FITS file '" + path + "': BITPIX = " + std::to_string(bitpix) + " is not a FITS data type");
    }
    const double bscale = card_double(kw, "BSCALE", 1.0), bzero = card_double(kw, "BZERO", 0.0);
    const bool has_blank = bitpix > 0 && kw.count("BLANK");
    const long long blank = has_blank ? card_int(kw, "BLANK", path) : 0;

    const std::size_t n = std::size_t(w) * std::size_t(h) * std::size_t(planes);
    // The header's sizes are checked against the file and the memory limit before anything is allocated:
    // a header of a few bytes may ask for gigabytes.
    const std::string dims = std::to_string(w) + "x" + std::to_string(h) + (planes > 1 ? "x" + std::to_string(planes) : "");
    const auto file_bytes = fs::file_size(path, ec);
    if (!ec && double(file_bytes) < double(header_bytes) + double(n) * double(bytes))
        throw Error("FITS file '" + path + "' is truncated: its header says " + dims + " values of " +
                    std::to_string(bytes) + " bytes (" + format_bytes(double(n) * double(bytes)) + "), the file holds " +
                    format_bytes(double(file_bytes) - double(header_bytes)) + " after the header");
    // Raw data, the float image (grey + alpha or RGBA) and the caller's copy.
    check_memory("FITS image '" + path + "' (" + dims + ")",
                 double(n) * double(bytes) + 2.0 * double(w) * double(h) * (planes == 1 ? 2.0 : 4.0) * 4.0);
    std::vector<unsigned char> raw(n * bytes);
    if (!in.read(reinterpret_cast<char*>(raw.data()), std::streamsize(raw.size())))
        throw Error("FITS file '" + path + "' is truncated: its data are shorter than NAXIS1 x NAXIS2 x BITPIX say");

    const int ch = planes == 1 ? 2 : 4;
    Image img(int(w), int(h), ch);
    std::size_t blanks = 0;
    for (long long p = 0; p < planes; ++p)
        for (long long j = 0; j < h; ++j)
            for (long long i = 0; i < w; ++i) {
                const std::size_t k = (std::size_t(p) * std::size_t(h) + std::size_t(j)) * std::size_t(w) + std::size_t(i);
                const unsigned char* q = raw.data() + k * bytes;
                double v = 0.0;
                bool bad = false;
                switch (bitpix) {
                    case 8: v = double(q[0]); bad = has_blank && (long long)q[0] == blank; break;
                    case 16: { const auto x = load_be<std::int16_t>(q); v = double(x); bad = has_blank && x == blank; break; }
                    case 32: { const auto x = load_be<std::int32_t>(q); v = double(x); bad = has_blank && x == blank; break; }
                    case 64: { const auto x = load_be<std::int64_t>(q); v = double(x); bad = has_blank && x == blank; break; }
                    case -32: v = double(load_be<float>(q)); break;
                    default: v = load_be<double>(q); break;
                }
                v = bzero + bscale * v;
                bad = bad || !std::isfinite(v) || std::abs(v) > 3.0e38;
                const int y = int(h - 1 - j);   // bottom row stored first
                const int c = planes == 1 ? 0 : int(p);
                img.at(int(i), y, c) = bad ? 0.0f : float(v);
                if (bad) {
                    ++blanks;
                    img.at(int(i), y, ch - 1) = 0.0f;
                } else if (p == 0) {
                    img.at(int(i), y, ch - 1) = 1.0f;
                }
            }
    (void)blanks;
    if (keywords) *keywords = kw;
    return img;
}

void write_fits(const std::string& path, const Image& img, const std::map<std::string, std::string>& keywords) {
    if (img.width < 1 || img.height < 1 || img.channels < 1) throw Error("cannot write an empty image to '" + path + "'");
    const int colour = img.channels >= 3 ? 3 : 1;
    std::vector<float> plane(std::size_t(img.width) * img.height);
    std::size_t bad = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            double s = 0.0;
            for (int c = 0; c < colour; ++c) s += img.at(x, y, c);
            const double v = s / colour;
            if (!std::isfinite(v)) ++bad;
            plane[std::size_t(img.height - 1 - y) * img.width + x] = float(v);   // bottom row first
        }
    if (bad) throw Error("refusing to write '" + path + "': " + std::to_string(bad) + " pixel values are NaN or Inf");

    std::string header;
    header += card("SIMPLE", "T", "conforms to FITS Standard 4.0");
    header += card("BITPIX", "-32", "IEEE single precision");
    header += card("NAXIS", "2");
    header += card("NAXIS1", std::to_string(img.width), "columns, left to right");
    header += card("NAXIS2", std::to_string(img.height), "rows, stored bottom row first");
    for (const auto& [k, v] : keywords) {
        std::string key = k;
        std::transform(key.begin(), key.end(), key.begin(), [](unsigned char c) { return char(std::toupper(c)); });
        if (key.empty() || key.size() > 8) throw Error("internal: FITS keyword '" + k + "' must have 1 to 8 characters");
        if (looks_numeric(v)) {
            header += card(key, v);
        } else {
            std::string q = "'";
            for (char c : v) q += (c == '\'') ? std::string("''") : std::string(1, c);
            q += "'";
            if (q.size() > 70) q = q.substr(0, 69) + "'";
            std::string c = key;
            c.resize(8, ' ');
            c += "= " + q;
            c.resize(kCard, ' ');
            header += c;
        }
    }
    std::string end = "END";
    end.resize(kCard, ' ');
    header += end;
    header.resize((header.size() + kBlock - 1) / kBlock * kBlock, ' ');

    std::vector<unsigned char> data(plane.size() * 4);
    for (std::size_t i = 0; i < plane.size(); ++i) {
        unsigned char b[4];
        std::memcpy(b, &plane[i], 4);
        for (int j = 0; j < 4; ++j) data[i * 4 + std::size_t(j)] = b[3 - j];   // big-endian
    }
    data.resize((data.size() + kBlock - 1) / kBlock * kBlock, 0);

    write_file_atomically(path, "image", [&](const std::string& tmp, std::string&) {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out.write(header.data(), std::streamsize(header.size()));
        out.write(reinterpret_cast<const char*>(data.data()), std::streamsize(data.size()));
        out.close();
        return bool(out);
    });
}

Image read_any_image(const std::string& path, std::map<std::string, std::string>* fits_keywords) {
    if (is_fits_path(path)) return read_fits(path, fits_keywords);
    return read_image(path);
}


void write_any_image(const std::string& path, const Image& img, const std::map<std::string, std::string>& fits_keywords) {
    if (is_fits_path(path)) return write_fits(path, img, fits_keywords);
    write_image(path, img);
}

}  // namespace shadelab
