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

#include <fitsio.h>
#include <memory>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "core/limits.hpp"

namespace fs = std::filesystem;

namespace shadelab {

namespace {

constexpr std::size_t kBlock = 2880;   // FITS logical record
constexpr std::size_t kCard = 80;

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(' ');
    if (b == std::string::npos) return "";
    return s.substr(b, s.find_last_not_of(' ') - b + 1);
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

// The file part of a cfitsio name: "img.fits[SCI]" -> "img.fits" (cfitsio's extended file name syntax selects
// an HDU in brackets).
std::string fits_file_part(const std::string& path) {
    if (!path.empty() && path.back() == ']') {
        const auto open = path.rfind('[');
        if (open != std::string::npos && open > 0) return path.substr(0, open);
    }
    return path;
}

bool is_fits_path(const std::string& path) {
    const std::string e = lower_ext(fits_file_part(path));
    return e == ".fits" || e == ".fit" || e == ".fts" || e == ".fz";
}

namespace {

// cfitsio's status as text, for one error line.
std::string fits_status_text(int status) {
    char text[FLEN_STATUS] = {0};
    fits_get_errstatus(status, text);
    return text;
}

struct FitsCloser {
    void operator()(fitsfile* f) const {
        int st = 0;
        if (f) fits_close_file(f, &st);
    }
};

// A keyword's value as text: quotes removed (and '' undoubled) for strings, the comment dropped.
std::string keyword_value(const char* value) {
    const std::string v = trim(value);
    if (v.empty() || v[0] != '\'') return v;
    std::string out;
    for (std::size_t i = 1; i < v.size(); ++i) {
        if (v[i] == '\'') {
            if (i + 1 < v.size() && v[i + 1] == '\'') { out += '\''; ++i; continue; }
            break;
        }
        out += v[i];
    }
    return trim(out);
}

using FitsHandle = std::unique_ptr<fitsfile, FitsCloser>;

// The image's axes as the header gives them.
struct FitsShape {
    long long w = 0, h = 0, planes = 1;
    int bitpix = 0;
};

// Opens path (its HDU, when one is named in brackets) with cfitsio once the file exists and holds one block.
FitsHandle open_fits(const std::string& path, const std::string& file) {
    std::error_code ec;
    if (!fs::exists(file, ec)) throw Error("image '" + path + "' not found: check the path");
    const auto size = fs::file_size(file, ec);
    if (!ec && size < kBlock)
        throw Error("FITS file '" + path + "' is truncated: " + std::to_string(size) +
                    " bytes, shorter than one 2880-byte header block");
    fitsfile* raw_handle = nullptr;
    int st = 0;
    if (fits_open_file(&raw_handle, path.c_str(), READONLY, &st)) {
        if (st == URL_PARSE_ERROR || st == BAD_HDU_NUM || st == END_OF_FILE)
            throw Error("FITS file '" + path + "': the HDU named in brackets is not there (cfitsio: " +
                        fits_status_text(st) + ")");
        throw Error("'" + path + "' is not a readable FITS file (cfitsio: " + fits_status_text(st) + ")");
    }
    return FitsHandle(raw_handle);
}

// Moves to the HDU with the image (the first image extension when no HDU is named and the primary is empty)
// and returns its NAXIS, 2 or 3.
int move_to_image(fitsfile* f, const std::string& path, bool named) {
    int st = 0, hdu = 0, hdutype = 0, naxis = 0;
    fits_get_hdu_num(f, &hdu);
    fits_get_img_dim(f, &naxis, &st);
    if (!st && naxis == 0 && !named) {
        // the primary HDU is empty: the first image extension (a compressed image counts as one)
        int hdus = 0;
        fits_get_num_hdus(f, &hdus, &st);
        for (int h = 2; h <= hdus && !st && naxis == 0; ++h) {
            fits_movabs_hdu(f, h, &hdutype, &st);
            if (!st && (hdutype == IMAGE_HDU || fits_is_compressed_image(f, &st))) fits_get_img_dim(f, &naxis, &st);
        }
        fits_get_hdu_num(f, &hdu);
    }
    if (st) throw Error("FITS file '" + path + "': " + fits_status_text(st) + " (is it truncated or not a FITS image?)");
    if (naxis == 0)
        throw Error("FITS file '" + path + "' has no image in any HDU (NAXIS = 0): nothing to read");
    if (naxis != 2 && naxis != 3)
        throw Error("FITS file '" + path + "' has NAXIS = " + std::to_string(naxis) + " in HDU " + std::to_string(hdu) +
                    ": only 2-D images (or 3 colour planes) are read");
    return naxis;
}

FitsShape image_shape(fitsfile* f, const std::string& path, int naxis) {
    int st = 0;
    FitsShape s;
    long naxes[3] = {1, 1, 1};
    if (fits_get_img_param(f, 3, &s.bitpix, &naxis, naxes, &st))
        throw Error("FITS file '" + path + "': " + fits_status_text(st));
    s.w = naxes[0];
    s.h = naxes[1];
    s.planes = naxis == 3 ? naxes[2] : 1;
    if (s.w < 1 || s.h < 1 || s.w > 65536 || s.h > 65536)
        throw Error("FITS file '" + path + "': image size " + std::to_string(s.w) + "x" + std::to_string(s.h) + " is not supported");
    if (s.planes != 1 && s.planes != 3)
        throw Error("FITS file '" + path + "' has " + std::to_string(s.planes) + " planes: only 1 (grey) or 3 (RGB) are read");
    return s;
}

// The header's sizes are checked against the file and the memory limit before anything is allocated:
// a header of a few bytes may ask for gigabytes. (A tile-compressed image is checked by cfitsio as it reads.)
void check_fits_size(fitsfile* f, const std::string& path, const std::string& file, const FitsShape& s) {
    const std::size_t n = std::size_t(s.w) * std::size_t(s.h) * std::size_t(s.planes);
    const std::string dims = std::to_string(s.w) + "x" + std::to_string(s.h) + (s.planes > 1 ? "x" + std::to_string(s.planes) : "");
    int compressed_status = 0;
    if (!fits_is_compressed_image(f, &compressed_status)) {
        const std::size_t bytes = std::size_t(std::abs(s.bitpix)) / 8;
        LONGLONG head_start = 0, data_start = 0, data_end = 0;
        int addr_status = 0;
        std::error_code ec;
        const auto file_bytes = fs::file_size(file, ec);
        if (!fits_get_hduaddrll(f, &head_start, &data_start, &data_end, &addr_status) && !ec &&
            double(file_bytes) < double(data_start) + double(n) * double(bytes))
            throw Error("FITS file '" + path + "' is truncated: its header says " + dims + " values of " +
                        std::to_string(bytes) + " bytes (" + format_bytes(double(n) * double(bytes)) +
                        "), the file holds " + format_bytes(std::max(0.0, double(file_bytes) - double(data_start))) +
                        " after the header");
    }
    // The float image (grey + alpha or RGBA), one row of doubles, and the caller's copy.
    check_memory("FITS image '" + path + "' (" + dims + ")",
                 2.0 * double(s.w) * double(s.h) * (s.planes == 1 ? 2.0 : 4.0) * 4.0 + double(s.w) * 9.0);
}

// The pixels, grey + alpha or RGBA, bottom row first as FITS stores them; a blank, NaN/Inf or beyond-float
// value is 0 with alpha 0.
Image read_fits_pixels(fitsfile* f, const std::string& path, const FitsShape& s) {
    const long long w = s.w, h = s.h, planes = s.planes;
    const int ch = planes == 1 ? 2 : 4;
    Image img(int(w), int(h), ch);
    std::vector<double> row(static_cast<std::size_t>(w));
    std::vector<char> null(static_cast<std::size_t>(w));
    int st = 0;
    for (long long p = 0; p < planes; ++p)
        for (long long j = 0; j < h; ++j) {
            long first[3] = {1, long(j + 1), long(p + 1)};
            int anynul = 0;
            if (fits_read_pixnull(f, TDOUBLE, first, long(w), row.data(), null.data(), &anynul, &st)) {
                if (st == END_OF_FILE || st == READ_ERROR)
                    throw Error("FITS file '" + path + "' is truncated: its data are shorter than NAXIS1 x NAXIS2 x BITPIX say");
                throw Error("FITS file '" + path + "': reading row " + std::to_string(j + 1) + ": " + fits_status_text(st));
            }
            const int y = int(h - 1 - j);   // bottom row stored first
            const int c = planes == 1 ? 0 : int(p);
            for (long long i = 0; i < w; ++i) {
                const double v = row[std::size_t(i)];
                const bool bad = null[std::size_t(i)] || !std::isfinite(v) || std::abs(v) > 3.0e38;
                img.at(int(i), y, c) = bad ? 0.0f : float(v);
                if (bad) img.at(int(i), y, ch - 1) = 0.0f;
                else if (p == 0) img.at(int(i), y, ch - 1) = 1.0f;
            }
        }
    return img;
}

// The HDU's keywords (the first of each name; COMMENT and HISTORY left out), values as keyword_value gives them.
void read_fits_keywords(fitsfile* f, std::map<std::string, std::string>& keywords) {
    keywords.clear();
    int st = 0, nkeys = 0;
    fits_get_hdrspace(f, &nkeys, nullptr, &st);
    for (int k = 1; k <= nkeys && !st; ++k) {
        char name[FLEN_KEYWORD] = {0}, value[FLEN_VALUE] = {0}, comment[FLEN_COMMENT] = {0};
        if (fits_read_keyn(f, k, name, value, comment, &st)) break;
        const std::string key = trim(name);
        if (!key.empty() && key != "COMMENT" && key != "HISTORY" && !keywords.count(key))
            keywords[key] = keyword_value(value);
    }
}

}  // namespace

// Read with cfitsio (Pence 1999; the FITS Standard 4.0): it applies BSCALE/BZERO, knows BLANK, reads extension
// HDUs by cfitsio's bracket syntax (img.fits[1], img.fits[SCI]) and tile-compressed images (.fz) as images. The
// checks shadelab adds: the file exists, the image is 2-D (or 3 colour planes), at most 65536 pixels a side.
// When no HDU is named and the primary HDU has no image (NAXIS = 0, as in every .fz file), the first image
// extension is read.
Image read_fits(const std::string& path, std::map<std::string, std::string>* keywords) {
    const std::string file = fits_file_part(path);
    const FitsHandle f = open_fits(path, file);
    const int naxis = move_to_image(f.get(), path, path != file);
    const FitsShape shape = image_shape(f.get(), path, naxis);
    check_fits_size(f.get(), path, file, shape);
    Image img = read_fits_pixels(f.get(), path, shape);
    if (keywords) read_fits_keywords(f.get(), *keywords);
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
