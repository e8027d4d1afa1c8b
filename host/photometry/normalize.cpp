#include "photometry/normalize.hpp"

#include <cmath>
#include <sstream>

#include "core/error.hpp"
#include "moon/fit.hpp"

namespace shadelab::photometry {

void check_normalize_options(const NormalizeOptions& o) {
    auto in = [](double v, double lo, double hi, const char* name) {
        if (!std::isfinite(v) || v < lo || v >= hi) {
            std::ostringstream m;
            m << "photometry normalize: --" << name << " " << v << " is out of range: allowed " << lo << " <= " << name
              << " < " << hi << " degrees";
            throw Error(m.str());
        }
    };
    if (o.mode != "albedo" && o.mode != "shade")
        throw Error("photometry normalize: --mode '" + o.mode + "' is unknown: use albedo or shade");
    in(o.incref, 0.0, 90.0, "incref");
    in(o.emaref, 0.0, 90.0, "emaref");
    in(o.pharef, 0.0, 180.0, "pharef");
    if (!std::isfinite(o.thresh) || o.thresh <= 0.0)
        throw Error("photometry normalize: --thresh must be a finite number > 0");
    if (!std::isfinite(o.albedo)) throw Error("photometry normalize: --albedo must be finite");
}

PixelGeometry geometry_from_backplanes(const Image& img, const std::string& image_name,
                                       const std::vector<std::string>& names) {
    if (names.size() != 3)
        throw Error("photometry normalize: --backplanes takes three images PHASE,INCIDENCE,EMISSION (degrees)");
    std::vector<Image> bp;
    for (const auto& n : names) {
        bp.push_back(read_image(n));
        if (bp.back().width != img.width || bp.back().height != img.height)
            throw Error(n + " is " + std::to_string(bp.back().width) + "x" + std::to_string(bp.back().height) + " but " +
                        image_name + " is " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                        ": backplanes must have the image's size");
    }
    PixelGeometry out;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            bool ok = true;
            const double v = moon::pixel_intensity(img, x, y, ok);
            if (!ok) continue;
            const Geometry g{bp[0].at(x, y, 0), bp[1].at(x, y, 0), bp[2].at(x, y, 0)};
            check_geometry(g, names[0] + " pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")");
            out.geometry.push_back(g);
            out.dn.push_back(v);
            out.xy.push_back({x, y});
        }
    return out;
}

Normalized normalize(Runtime& rt, const Law& law, const std::vector<Geometry>& geometry, const std::vector<double>& dn,
                     const NormalizeOptions& o) {
    check_normalize_options(o);
    if (dn.size() != geometry.size()) throw Error("internal: normalize needs one geometry per pixel");
    Normalized n;
    n.psurf_ref = evaluate(rt, standard_conditions(law), {{o.pharef, o.incref, o.emaref}})[0];
    if (!(n.psurf_ref > 0.0))
        throw Error("photometry normalize: the law is 0 at the reference geometry (pharef, incref, emaref) = (" +
                    std::to_string(o.pharef) + ", " + std::to_string(o.incref) + ", " + std::to_string(o.emaref) +
                    "): nothing to normalise to");
    const std::vector<double> psurf = evaluate(rt, law, geometry);
    n.value.assign(dn.size(), 0.0);
    n.valid.assign(dn.size(), 0);
    for (std::size_t k = 0; k < dn.size(); ++k) {
        if (o.mode == "shade") {
            n.value[k] = o.albedo / n.psurf_ref * psurf[k];
            n.valid[k] = 1;
            continue;
        }
        // ISIS's Albedo: no value where the reference exceeds thresh times the pixel's law (psurf = 0 included)
        if (n.psurf_ref > psurf[k] * o.thresh || !(psurf[k] > 0.0)) {
            ++n.nulled;
            continue;
        }
        n.value[k] = dn[k] * n.psurf_ref / psurf[k];
        n.valid[k] = 1;
    }
    return n;
}

}  // namespace shadelab::photometry
