// FITS images (planetary data often comes in it): read with cfitsio (any image HDU, BSCALE/BZERO, BLANK,
// tile-compressed .fz), written by a small writer of the primary HDU (FITS Standard 4.0).
//
// Why not OpenImageIO: the FITS plug-in of OpenImageIO 2.4 (Debian 12) reads scanline y from stored row
// (height - y) instead of (height - 1 - y), so the first stored row is lost and a row of zeros appears; it
// writes with the same offset and does not pad the data to 2880 bytes, so other FITS readers see shifted
// data; and it does not apply BSCALE/BZERO (16-bit data come back normalised to [-1, 1]). These functions do
// it by the standard (the reader through cfitsio, the writer by hand).
//
// Orientation: FITS stores the bottom row first (pixel (1, 1) is displayed at the lower left, as DS9 does);
// in memory row 0 is the top row, so rows are reversed on reading and on writing.
#pragma once
#include <map>
#include <string>

#include "image/image.hpp"

namespace shadelab {

// True for .fits .fit .fts .fz (any case), also with an HDU in cfitsio's brackets: img.fits[1], img.fits[SCI].
bool is_fits_path(const std::string& path);

// Reads an image HDU: the one named in brackets, else the primary HDU, else (the primary empty, as in .fz files)
// the first image extension. BITPIX 8, 16, 32, 64, -32, -64 with BSCALE/BZERO; NAXIS = 2 (grey) or 3 with
// NAXIS3 = 3 (RGB planes). Returns grey + alpha (2 channels) or RGB + alpha (4 channels), linear float;
// blank pixels (BLANK for integers, NaN for floats) get value 0 and alpha 0, so they are skipped by the
// moon tools and never carry NaN further. Header keywords are returned in `keywords` when given
// (name -> value text, quotes removed). Throws shadelab::Error with one clear line on anything else.
Image read_fits(const std::string& path, std::map<std::string, std::string>* keywords = nullptr);

// Writes one plane (NAXIS = 2, BITPIX = -32): the mean of the colour channels (a grey render's value),
// bottom row first, with the given extra keywords (8 upper-case characters at most; numbers written as
// numbers, anything else as a quoted string). Atomic (temporary file, then rename); refuses NaN/Inf.
void write_fits(const std::string& path, const Image& img, const std::map<std::string, std::string>& keywords = {});

// read_image / write_image, which route FITS to the functions above, plus the FITS header keywords.
Image read_any_image(const std::string& path, std::map<std::string, std::string>* fits_keywords = nullptr);
void write_any_image(const std::string& path, const Image& img,
                     const std::map<std::string, std::string>& fits_keywords = {});

}  // namespace shadelab
