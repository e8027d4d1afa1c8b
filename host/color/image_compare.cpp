#include "color/image_compare.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "color/color.hpp"
#include "core/error.hpp"

namespace shadelab {

namespace {
double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    const std::size_t k = std::min(v.size() - 1, std::size_t(std::ceil(q * double(v.size()))) - (q > 0 ? 1 : 0));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    return v[k];
}
}  // namespace

NonFinitePixels find_non_finite(const Image& img) {
    NonFinitePixels n;
    const std::size_t ch = std::size_t(std::max(img.channels, 1));
    for (std::size_t p = 0; p * ch < img.pixels.size(); ++p) {
        bool bad = false;
        for (std::size_t c = 0; c < ch && p * ch + c < img.pixels.size(); ++c) bad = bad || !std::isfinite(img.pixels[p * ch + c]);
        if (!bad) continue;
        if (n.count++ == 0 && img.width > 0) {
            n.x = int(p % std::size_t(img.width));
            n.y = int(p / std::size_t(img.width));
        }
    }
    return n;
}

namespace {
bool pixel_finite(const Image& img, int x, int y) {
    for (int c = 0; c < img.channels; ++c)
        if (!std::isfinite(img.at(x, y, c))) return false;
    return true;
}
}  // namespace

ImageDiff compare_images(const Image& a, const Image& b, double rel_floor, bool ignore_nonfinite) {
    if (a.width != b.width || a.height != b.height)
        throw Error("images differ in size (" + std::to_string(a.width) + "x" + std::to_string(a.height) + " vs " +
                    std::to_string(b.width) + "x" + std::to_string(b.height) + "): compare renders of the same size");
    if (a.channels < 3 || b.channels < 3) throw Error("images must have at least 3 colour channels (RGB)");
    if (!ignore_nonfinite) {
        for (const auto& [img, which] : {std::pair{&a, "image"}, std::pair{&b, "reference"}}) {
            const NonFinitePixels n = find_non_finite(*img);
            if (n.count)
                throw Error(std::string("the ") + which + " has " + std::to_string(n.count) + " pixel" + (n.count == 1 ? "" : "s") +
                            " holding NaN or Inf, the first at (x, y) = (" + std::to_string(n.x) + ", " + std::to_string(n.y) + ")" +
                            ": fix what produced it, or exclude such pixels (--ignore-nonfinite)");
        }
    }
    ImageDiff d;
    d.de_map = Image(a.width, a.height, 1);
    std::vector<double> des, rels;
    des.reserve(std::size_t(a.width) * a.height);
    double de_sum = 0.0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            if (!pixel_finite(a, x, y) || !pixel_finite(b, x, y)) {
                ++d.nonfinite_excluded;
                continue;
            }
            const bool ca = a.channels < 4 || a.at(x, y, 3) > 0.5f;
            const bool cb = b.channels < 4 || b.at(x, y, 3) > 0.5f;
            if (ca != cb) { ++d.coverage_mismatch; continue; }
            if (!ca) continue;
            glm::dvec3 pa, pb;
            for (int c = 0; c < 3; ++c) {
                pa[c] = std::max(0.0, double(a.at(x, y, c)));
                pb[c] = std::max(0.0, double(b.at(x, y, c)));
                const double err = std::abs(pa[c] - pb[c]);
                d.abs_max = std::max(d.abs_max, err);
                if (pb[c] >= rel_floor) rels.push_back(err / pb[c]);
            }
            const double de = delta_e2000(lab_from_linear_srgb(pa), lab_from_linear_srgb(pb));
            d.de_map.at(x, y, 0) = float(de);
            des.push_back(de);
            de_sum += de;
            d.de_max = std::max(d.de_max, de);
        }
    d.pixels = des.size();
    d.de_mean = des.empty() ? 0.0 : de_sum / double(des.size());
    d.de_p99 = percentile(des, 0.99);
    d.rel_p99 = percentile(rels, 0.99);
    for (double r : rels) d.rel_max = std::max(d.rel_max, r);
    return d;
}

Image colourise_delta_e(const Image& m, double scale_max) {
    // A perceptually ordered ramp (dark blue, purple, orange, yellow-white), linear-light values.
    static const glm::dvec3 stops[] = {{0.0, 0.0, 0.05}, {0.25, 0.02, 0.35}, {0.9, 0.25, 0.02}, {1.0, 1.0, 0.7}};
    Image out(m.width, m.height, 4);
    const double s = scale_max > 0 ? scale_max : 1.0;
    for (int y = 0; y < m.height; ++y)
        for (int x = 0; x < m.width; ++x) {
            const double v = double(m.at(x, y, 0));
            // NaN would pass through std::clamp and int(NaN) is undefined: show it as full scale.
            const double t = (std::isfinite(v) ? std::clamp(v / s, 0.0, 1.0) : 1.0) * 3.0;
            const int i = std::min(2, int(t));
            const glm::dvec3 c = glm::mix(stops[i], stops[i + 1], t - i);
            for (int k = 0; k < 3; ++k) out.at(x, y, k) = float(c[k]);
            out.at(x, y, 3) = 1.0f;
        }
    return out;
}

}  // namespace shadelab
