// The one home of small text helpers every module needs: numbers as text, file extensions, image sizes.
#pragma once
#include <string>

namespace shadelab {

// `x` with `digits` significant digits, as an ostream prints it by default (6: "0.333333", "1e+06").
std::string num(double x, int digits = 6);

// `x` with exactly `decimals` digits after the point ("3.14").
std::string fixed(double x, int decimals);

// The extension of `path`, lower case, with its dot (".png"; "" when there is none).
std::string lower_ext(const std::string& path);

// An image size "WIDTHxHEIGHT" (or "WIDTHXHEIGHT") with each side in [min_side, max_side]. Throws
// shadelab::Error naming `option` and the text: "--size expects WIDTHxHEIGHT such as 512x512, got 'abc'",
// "--size 4x4: each side must be in [8, 16384]".
struct ImageSize {
    int width = 0, height = 0;
};
ImageSize parse_size(const std::string& text, const std::string& option, int min_side, int max_side,
                     const std::string& example = "512x512");

}  // namespace shadelab
