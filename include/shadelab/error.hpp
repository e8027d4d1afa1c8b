// The one exception type of shadelab's public API: a one-line message saying what went wrong, with which
// file or field, and what to do.
#pragma once
#include <stdexcept>
#include <string>

namespace shadelab::api {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& what_went_wrong) : std::runtime_error(what_went_wrong) {}
};

}  // namespace shadelab::api
