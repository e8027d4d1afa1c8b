// Planetary rasters through GDAL (Warmerdam et al., gdal.org): ISIS3 cubes (.cub), PDS3 (.lbl, .img with a PDS
// label), PDS4 (.xml), GeoTIFF (.tif, .tiff, when named with a band) and every other format GDAL reads - one band
// at a time, as a grey image.
//
// The band is chosen in brackets after the file name, as cfitsio chooses an HDU: `cube.cub[3]` (1-based index)
// or `cube.cub[phase]` (a name, case-insensitive, matched against ISIS's BandBin Name and FilterName entries and
// against GDAL's band description); `cube.cub` alone is band 1. Pixels that are GDAL's no-data value, ISIS's
// special pixels (NULL, LIS, LRS, HIS, HRS: all beyond +-3e38 in float) or not finite get value 0 and alpha 0,
// so the photometry and moon tools skip them. Stored values are scaled as the label says (PDS3 SCALING_FACTOR and
// OFFSET, PDS4 scaling_factor and value_offset, ISIS Multiplier and Base). A PDS3 IMAGE without SAMPLE_TYPE or
// SAMPLE_BITS is refused (GDAL would guess). No viewing geometry is read from the labels. tests/test_pds.cpp.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "image/image.hpp"

namespace shadelab {

// True for the extensions GDAL is asked to read by read_image: .cub .lbl .xml .img (also with a [band]), and
// .tif / .tiff only when a band is named in brackets (plain .tif goes to OpenImageIO as before).
bool is_gdal_path(const std::string& path);

// "cube.cub[phase]" -> {"cube.cub", "phase"}; no brackets -> {path, ""}. (Inline: the image plug-in uses it too.)
inline std::pair<std::string, std::string> split_band(const std::string& path) {
    if (!path.empty() && path.back() == ']') {
        const auto open = path.rfind('[');
        if (open != std::string::npos && open > 0) return {path.substr(0, open), path.substr(open + 1, path.size() - open - 2)};
    }
    return {path, ""};
}

// One band as a grey image (2 channels: value, alpha), through the image plug-in (image/image_io.hpp). Throws one line for a missing file, a file GDAL cannot
// open, and a band that is not there (naming the bands the file has).
Image read_raster_band(const std::string& path);

// The bands of a raster, as "1 phase", "2 incidence", ... (name empty when it has none), for messages.
std::vector<std::string> raster_band_names(const std::string& file);

}  // namespace shadelab
