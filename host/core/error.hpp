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

// A mistake in how a command was called (an unknown model name on the command line, options that do not go
// together): exit code 2 instead of 1, like the command-line parser's own usage errors.
class UsageError : public Error {
public:
    explicit UsageError(const std::string& what_went_wrong) : Error(what_went_wrong) {}
};

}  // namespace shadelab
