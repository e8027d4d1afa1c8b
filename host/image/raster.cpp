#include "image/raster.hpp"

#include "core/format.hpp"
#include "image/image_io.hpp"

namespace shadelab {

bool is_gdal_path(const std::string& path) {
    const auto [file, band] = split_band(path);
    const std::string e = lower_ext(file);
    if (e == ".cub" || e == ".lbl" || e == ".xml" || e == ".img") return true;
    return !band.empty() && (e == ".tif" || e == ".tiff");
}

// GDAL's part is in the image plug-in (host/image/image_io.hpp): loaded only when a raster is read.
std::vector<std::string> raster_band_names(const std::string& file) { return image_io::plugin().raster_band_names(file); }

Image read_raster_band(const std::string& path) { return image_io::plugin().read_raster_band(path); }

}  // namespace shadelab
