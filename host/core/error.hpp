// shadelab: the one error type every layer throws.
// The message is one line for the user: what went wrong, with which file, and what to do.
#pragma once
#include <stdexcept>
#include <string>

namespace shadelab {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& what_went_wrong) : std::runtime_error(what_went_wrong) {}
};

}  // namespace shadelab
