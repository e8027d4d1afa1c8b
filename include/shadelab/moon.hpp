// Minnaert fits on disc images: the lunar side of shadelab (docs/moon.md).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "shadelab/types.hpp"

namespace shadelab::api {

// Where the disc is on the image and where the sun is.
struct DiscGeometry {
    double cx = 0.0, cy = 0.0;   // centre, pixels (x right, y down from the top-left corner)
    double radius = 0.0;         // pixels
    double phase_deg = 0.0;      // sun-object-observer angle, [0, 180]
    double pa_deg = 0.0;         // position angle of the sun direction on the image
};

struct MinnaertResult {
    double k = 0.0, se_k = 0.0;
    double B0 = 0.0, se_B0 = 0.0;
    double rms_rel = 0.0;        // rms of I / model - 1 over the pixels used
    std::size_t used = 0;        // pixels in the fit
    std::vector<std::string> warnings;
};

// Fits Minnaert's law I = B0 mu0^k mu^(k-1) to the disc's pixels (method "minnaert-plot", "weighted" or
// "intensity"), keeping mu, mu0 >= 0.2 as `shadelab moon fit` does.
MinnaertResult fit_minnaert(const Image& image, const DiscGeometry& geometry,
                            const std::string& method = "minnaert-plot");

}  // namespace shadelab::api
