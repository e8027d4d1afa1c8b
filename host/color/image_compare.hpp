// Image against image: per-pixel CIEDE2000 (on linear sRGB -> Lab) and relative error on linear values.
#pragma once
#include <cstddef>
#include <string>

#include "image/image.hpp"

namespace shadelab {

// The figures of a comparison, without the map: what tables and charts keep per image pair.
struct DiffFigures {
    std::size_t pixels = 0;            // pixels compared (covered in both, when both have alpha)
    std::size_t coverage_mismatch = 0; // covered in one image only (not compared, counted)
    double de_mean = 0.0, de_p99 = 0.0, de_max = 0.0;   // CIEDE2000
    double rel_max = 0.0, rel_p99 = 0.0;  // |a - b| / |b| per channel, where |b| >= rel_floor
    double abs_max = 0.0;
    std::size_t nonfinite_excluded = 0;   // pixels left out because either image holds NaN/Inf there
};

struct ImageDiff : DiffFigures {
    Image de_map;                      // width x height x 1: Delta E 2000 per pixel (0 where not compared)
};

// Pixels holding NaN or Inf in any channel: how many, and the first in row order (x, y; -1 when none).
struct NonFinitePixels {
    std::size_t count = 0;
    int x = -1, y = -1;
};
NonFinitePixels find_non_finite(const Image& img);

// `b` is the reference. Images must have the same size; colours are linear RGB (as read_image returns).
// Values are clamped to >= 0 before the Lab conversion (Lab is undefined for negative light).
// NaN/Inf pixels are never averaged: by default either image holding one is refused (shadelab::Error naming
// the first pixel and the count); with `ignore_nonfinite` those pixels are left out of every figure, their
// map value is 0, and `nonfinite_excluded` counts them.
ImageDiff compare_images(const Image& a, const Image& b, double rel_floor = 1e-3, bool ignore_nonfinite = false);

// Colour-maps a Delta E map for viewing: 0 -> dark blue, `scale_max` and above -> yellow-white; a NaN/Inf
// entry (a map not made by compare_images) shows as full scale.
Image colourise_delta_e(const Image& de_map, double scale_max);

}  // namespace shadelab
