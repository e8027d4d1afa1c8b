// Fit results as text (what `shadelab fit` prints) and as JSON (the contract: model, target,
// params {name: value}, albedo, error {metric: value}; more keys beside them).
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "fit/fit.hpp"

namespace shadelab::fit {

nlohmann::json to_json(const FitResult& r);

// Several lines: the fitted parameters with standard errors, the errors, where the largest difference is,
// the limb check, and every diagnostic in words.
std::string to_text(const FitResult& r);

// "oren_nayar(sigma=0.4)"
std::string describe_target(const FitResult& r);

}  // namespace shadelab::fit
