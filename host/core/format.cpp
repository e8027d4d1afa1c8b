#include "core/format.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "core/error.hpp"

namespace shadelab {

std::string num(double x, int digits) {
    std::ostringstream s;
    s << std::setprecision(digits) << x;
    return s.str();
}

std::string fixed(double x, int decimals) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(decimals) << x;
    return s.str();
}

std::string lower_ext(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

ImageSize parse_size(const std::string& text, const std::string& option, int min_side, int max_side,
                     const std::string& example) {
    int a = 0, b = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &a, &x, &b, &extra) != 3 || (x != 'x' && x != 'X'))
        throw Error(option + " expects WIDTHxHEIGHT such as " + example + ", got '" + text + "'");
    if (a < min_side || b < min_side || a > max_side || b > max_side)
        throw Error(option + " " + text + ": each side must be in [" + std::to_string(min_side) + ", " +
                    std::to_string(max_side) + "]");
    return ImageSize{a, b};
}

}  // namespace shadelab
