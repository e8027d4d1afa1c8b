// Small text helpers shared by the command line and the tests.
#pragma once
#include <sstream>
#include <string>
#include <vector>

namespace shadelab {

// Splits at every `sep`, keeping empty fields ("a,,b" -> a, "", b; "a," -> a, "").
inline std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::string cur;
    std::istringstream in(s);
    while (std::getline(in, cur, sep)) out.push_back(cur);
    if (!s.empty() && s.back() == sep) out.push_back("");
    return out;
}

}  // namespace shadelab
