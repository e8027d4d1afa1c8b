// The image plug-in's GDAL half (host/image/image_io.hpp says why it is a plug-in; host/image/raster.hpp what it
// reads and how).
#include "image/raster.hpp"
#include "image_io_plugin/plugin.hpp"

#include <gdal_priv.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <mutex>

#include "core/error.hpp"

namespace fs = std::filesystem;

namespace shadelab::image_io {

namespace {

constexpr double kFloatMax = double(std::numeric_limits<float>::max());

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

void register_gdal() {
    static std::once_flag once;
    std::call_once(once, [] {
        GDALAllRegister();
        CPLSetErrorHandler(CPLQuietErrorHandler);   // errors are reported by shadelab, in one line
    });
}

struct Closer {
    void operator()(GDALDataset* d) const { GDALClose(d); }
};

// ISIS's BandBin group (in GDAL's json:ISIS3 metadata): the Name and FilterName of band b (1-based), if any.
std::vector<std::string> isis_band_names(GDALDataset* ds, int b) {
    std::vector<std::string> out;
    char** md = ds->GetMetadata("json:ISIS3");
    if (!md || !md[0]) return out;
    const nlohmann::json j = nlohmann::json::parse(md[0], nullptr, false);
    if (j.is_discarded() || !j.contains("IsisCube") || !j["IsisCube"].contains("BandBin")) return out;
    const auto& bb = j["IsisCube"]["BandBin"];
    for (const char* key : {"Name", "FilterName"}) {
        if (!bb.contains(key)) continue;
        const auto& v = bb[key];
        if (v.is_array() && int(v.size()) >= b && v[std::size_t(b - 1)].is_string()) out.push_back(v[std::size_t(b - 1)]);
        else if (v.is_string() && b == 1) out.push_back(v.get<std::string>());
    }
    return out;
}

std::vector<std::string> names_of(GDALDataset* ds, int b) {
    std::vector<std::string> n = isis_band_names(ds, b);
    const std::string d = ds->GetRasterBand(b)->GetDescription();
    if (!d.empty()) n.push_back(d);
    return n;
}

std::unique_ptr<GDALDataset, Closer> open_raster(const std::string& file, const std::string& shown) {
    register_gdal();
    std::error_code ec;
    if (!fs::exists(file, ec)) throw Error("image '" + shown + "' not found: check the path");
    GDALDataset* ds = static_cast<GDALDataset*>(GDALOpen(file.c_str(), GA_ReadOnly));
    if (!ds) {
        const std::string why = CPLGetLastErrorMsg();
        throw Error("cannot read '" + shown + "' with GDAL" + (why.empty() ? std::string() : ": " + why) +
                    " (ISIS3 .cub, PDS3, PDS4, GeoTIFF and GDAL's other formats are read)");
    }
    if (ds->GetRasterCount() < 1) {
        GDALClose(ds);
        throw Error("'" + shown + "' has no raster bands");
    }
    return std::unique_ptr<GDALDataset, Closer>(ds);
}

// A PDS3 label (GDAL's json:PDS metadata) whose IMAGE object does not say how its samples are stored: GDAL
// opens it anyway and guesses (most significant byte first), which reads any other file as noise. Refused.
void check_pds3_image_label(GDALDataset* ds, const std::string& shown) {
    char** md = ds->GetMetadata("json:PDS");
    if (!md || !md[0]) return;
    const nlohmann::json j = nlohmann::json::parse(md[0], nullptr, false);
    if (j.is_discarded() || !j.contains("IMAGE") || !j["IMAGE"].is_object()) return;
    for (const char* key : {"SAMPLE_TYPE", "SAMPLE_BITS"})
        if (!j["IMAGE"].contains(key))
            throw Error("'" + shown + "': the PDS3 label's IMAGE object has no " + key +
                        " (how the samples are stored, e.g. SAMPLE_TYPE = PC_REAL, SAMPLE_BITS = 32): add it to the label");
}

}  // namespace

namespace gdal {

std::vector<std::string> raster_band_names(const std::string& file) {
    auto ds = open_raster(file, file);
    std::vector<std::string> out;
    for (int b = 1; b <= ds->GetRasterCount(); ++b) {
        const auto n = names_of(ds.get(), b);
        out.push_back(std::to_string(b) + (n.empty() ? std::string() : " " + n.front()));
    }
    return out;
}

Image read_raster_band(const std::string& path) {
    const auto [file, band] = split_band(path);
    auto ds = open_raster(file, path);
    check_pds3_image_label(ds.get(), path);
    const int count = ds->GetRasterCount();
    int b = 0;
    if (band.empty()) b = 1;
    else if (std::all_of(band.begin(), band.end(), [](unsigned char c) { return std::isdigit(c); })) {
        b = std::atoi(band.c_str());
        if (b < 1 || b > count) b = -1;
    } else {
        for (int k = 1; k <= count && b == 0; ++k)
            for (const auto& n : names_of(ds.get(), k))
                if (lower(n) == lower(band)) b = k;
    }
    if (b <= 0) {
        std::string have;
        for (int k = 1; k <= count; ++k) {
            const auto n = names_of(ds.get(), k);
            have += (have.empty() ? "" : ", ") + std::to_string(k) + (n.empty() ? std::string() : " '" + n.front() + "'");
        }
        throw Error(file + " has no band '" + band + "': its bands are " + have + " (give a name or an index 1 to " +
                    std::to_string(count) + " in brackets)");
    }
    GDALRasterBand* rb = ds->GetRasterBand(b);
    const int w = rb->GetXSize(), h = rb->GetYSize();
    if (w < 1 || h < 1 || w > 65536 || h > 65536)
        throw Error("'" + path + "': raster size " + std::to_string(w) + "x" + std::to_string(h) + " is not supported");
    // the image (value and alpha planes, float) and one row of doubles, before either is allocated
    host().check_memory("the band of '" + path + "' (" + std::to_string(w) + "x" + std::to_string(h) + ")",
                 double(w) * double(h) * 2.0 * sizeof(float) + double(w) * sizeof(double));
    int has_nodata = 0;
    const double nodata = rb->GetNoDataValue(&has_nodata);
    // stored value -> physical value: PDS3 SCALING_FACTOR / OFFSET, PDS4 scaling_factor / value_offset, ISIS's
    // Multiplier / Base (GDAL gives 1 and 0 where the label has none); no-data is compared before, in stored units
    const double scale = rb->GetScale(), offset = rb->GetOffset();
    if (!std::isfinite(scale) || !std::isfinite(offset))
        throw Error("'" + path + "': the label's scaling factor / offset (" + std::to_string(scale) + ", " +
                    std::to_string(offset) + ") is not a finite number: correct the label");
    Image img(w, h, 2);
    std::vector<double> row(static_cast<std::size_t>(w));
    for (int y = 0; y < h; ++y) {
        if (rb->RasterIO(GF_Read, 0, y, w, 1, row.data(), w, 1, GDT_Float64, 0, 0) != CE_None)
            throw Error("cannot read row " + std::to_string(y + 1) + " of '" + path + "': " + CPLGetLastErrorMsg() +
                        " (is the file truncated?)");
        for (int x = 0; x < w; ++x) {
            const double v = row[std::size_t(x)];
            // masked: no-data, a non-finite stored value, or a physical value a float cannot hold (a large
            // SCALING_FACTOR times a large stored value would otherwise become Inf)
            const double p = v * scale + offset;
            const bool bad = !std::isfinite(v) || (has_nodata && v == nodata) || !(std::abs(p) <= kFloatMax);
            img.at(x, y, 0) = bad ? 0.0f : float(p);
            img.at(x, y, 1) = bad ? 0.0f : 1.0f;
        }
    }
    return img;
}

}  // namespace gdal

}  // namespace shadelab::image_io
