// Normalising an image to a standard geometry, as ISIS3's photomet does with its normalisation models:
//   albedo:  out = dn * psurf(pharef, incref, emaref) / psurf(g, i, e), and no value (null) where
//            psurf(ref) > thresh * psurf(g, i, e) (ISIS's Albedo: thresh limits the amplification);
//   shade:   out = albedo / psurf(ref) * psurf(g, i, e), the law's shading at a uniform albedo (ISIS's Shade; dn
//            is not used).
// psurf(ref) is the law at ISIS's standard conditions (Hapke: B0 = 0 unless ZeroB0Standard = FALSE). The per-pixel
// law is evaluated on PoCL. Defaults: incref 30, emaref 0, pharef 30 (the standard geometry; ISIS's own
// default is 0, 0 and pharef = incref), thresh 30 and albedo 1 (ISIS's).
#pragma once
#include <string>
#include <vector>

#include "cl/runtime.hpp"
#include "image/image.hpp"
#include "photometry/isis.hpp"

namespace shadelab::photometry {

struct NormalizeOptions {
    std::string mode = "albedo";   // albedo | shade
    double incref = 30.0, emaref = 0.0, pharef = 30.0;
    double thresh = 30.0, albedo = 1.0;
};
// Throws one line naming the option and its range (incref, emaref in [0, 90), pharef in [0, 180), ISIS's).
void check_normalize_options(const NormalizeOptions& o);

struct Normalized {
    std::vector<double> value;   // per pixel; 0 where !valid
    std::vector<char> valid;     // false: null (albedo mode beyond thresh, or the reference value is 0)
    double psurf_ref = 0.0;
    std::size_t nulled = 0;
};

// The pixels of `image` with a value (alpha > 0; the mean of the colour channels, as host/moon reads images) and
// their geometry from three backplane images of phase, incidence and emission in degrees (first channel). Throws
// one line naming the backplane when its size is not the image's, or a pixel's angle is outside [0, 180].
struct PixelGeometry {
    std::vector<Geometry> geometry;
    std::vector<double> dn;
    std::vector<std::pair<int, int>> xy;
};
PixelGeometry geometry_from_backplanes(const Image& image, const std::string& image_name,
                                       const std::vector<std::string>& backplanes);

// dn and geometry per pixel (the same length).
Normalized normalize(Runtime& rt, const Law& law, const std::vector<Geometry>& geometry, const std::vector<double>& dn,
                     const NormalizeOptions& o);

}  // namespace shadelab::photometry
