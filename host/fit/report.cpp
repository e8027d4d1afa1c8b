#include "fit/report.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/format.hpp"

namespace shadelab::fit {

namespace {
// JSON numbers only for finite values (nlohmann writes NaN/Inf as null anyway; say so explicitly).
nlohmann::json jnum(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }
}  // namespace

std::string describe_target(const FitResult& r) {
    std::string s = r.target;
    std::string args;
    for (const auto& [k, v] : r.target_params) args += (args.empty() ? "" : ", ") + k + "=" + num(v, 6);
    return args.empty() ? s : s + "(" + args + ")";
}

nlohmann::json to_json(const FitResult& r) {
    nlohmann::json j;
    j["model"] = r.model;
    j["target"] = r.target;
    nlohmann::json tp = nlohmann::json::object();
    for (const auto& [k, v] : r.target_params) tp[k] = jnum(v);
    j["target_params"] = tp;
    nlohmann::json params = nlohmann::json::object(), se = nlohmann::json::object(), fixed = nlohmann::json::array();
    for (const auto& p : r.params) {
        params[p.name] = jnum(p.value);
        se[p.name] = p.se_known ? jnum(p.se) : nlohmann::json(nullptr);
        if (p.fixed) fixed.push_back(p.name);
    }
    j["params"] = params;
    j["standard_errors"] = se;
    j["fixed"] = fixed;
    j["albedo"] = jnum(r.albedo);
    j["albedo_standard_error"] = jnum(r.se_albedo);
    nlohmann::json err = nlohmann::json::object();
    for (const auto& [k, v] : r.error) err[k] = jnum(v);
    j["error"] = err;
    const auto& a = r.worst.angles;
    j["largest_difference"] = {{"theta_i_deg", jnum(a.theta_i)}, {"theta_r_deg", jnum(a.theta_r)},
                               {"dphi_deg", jnum(a.dphi)},       {"phase_deg", jnum(a.phase)},
                               {"target", jnum(r.worst.target)}, {"fit", jnum(r.worst.fit)}};
    j["well_posed"] = r.well_posed;
    j["representable"] = r.representable;
    nlohmann::json diags = nlohmann::json::array();
    for (const auto& d : r.diagnostics) diags.push_back({{"kind", d.kind}, {"text", d.text}, {"ill_posed", d.ill_posed}});
    j["diagnostics"] = diags;
    if (r.limb.done) {
        nlohmann::json lp = nlohmann::json::object();
        for (std::size_t q = 0; q < r.params.size() && q < r.limb.params.size(); ++q) lp[r.params[q].name] = jnum(r.limb.params[q]);
        j["limb_check"] = {{"cos_min", r.limb.cos_min},           {"sample_share", jnum(r.limb.sample_share)},
                           {"error_share", jnum(r.limb.error_share)}, {"refitted", r.limb.refitted},
                           {"sensitive", r.limb.sensitive}};
        if (r.limb.refitted) {
            nlohmann::json& lc = j["limb_check"];
            lc["params"] = lp;
            lc["albedo"] = jnum(r.limb.albedo);
            lc["rel-rms"] = jnum(r.limb.rel_rms);
            lc["max_shift"] = jnum(r.limb.max_shift);
        }
    }
    j["domain"] = {{"name", r.domain}, {"description", r.domain_description}, {"samples", r.samples}};
    j["kernel_evaluations"] = r.kernel_evaluations;
    j["reference_evaluations"] = r.reference_evaluations;
    j["seconds"] = jnum(r.seconds);
    if (!r.note.empty()) j["note"] = r.note;
    return j;
}

std::string to_text(const FitResult& r) {
    std::ostringstream s;
    s << r.model << " fitted to " << describe_target(r) << "\n";
    s << "  domain: " << r.domain_description << "\n";
    if (!r.note.empty()) s << "  note: " << r.note << "\n";
    for (const auto& p : r.params) {
        s << "  " << std::left << std::setw(14) << p.name << std::right << " = " << std::setw(14) << num(p.value, 9);
        if (p.fixed) s << "   (held fixed)";
        else if (p.integer) s << "   (whole number: every value searched)";
        else if (p.se_known) s << "   +- " << num(p.se, 3);
        else s << "   +- (undetermined)";
        s << "   range [" << num(p.lo, 6) << ", " << num(p.hi, 6) << "]\n";
    }
    s << "  " << std::left << std::setw(14) << "albedo" << std::right << " = " << std::setw(14) << num(r.albedo, 9)
      << "   +- " << num(r.se_albedo, 3) << "   (free grey scale)\n";
    s << "  error:";
    for (const auto& [k, v] : r.error) s << "  " << k << " " << num(v, 4);
    s << "\n";
    const auto& a = r.worst.angles;
    s << "  largest difference at theta_i " << num(a.theta_i, 4) << ", theta_r " << num(a.theta_r, 4) << ", dphi "
      << num(a.dphi, 4) << " deg (phase " << num(a.phase, 4) << "): target " << num(r.worst.target, 5) << ", fit "
      << num(r.worst.fit, 5) << "\n";
    if (r.limb.done)
        s << "  limb check: samples with NoL or NoV < " << r.limb.cos_min << " are " << num(100 * r.limb.sample_share, 3)
          << "% of the domain and carry " << num(100 * r.limb.error_share, 3) << "% of the squared error; "
          << (r.limb.refitted ? "refit without them moves the parameters by " + num(100 * r.limb.max_shift, 3) +
                                    "% of their range"
                              : std::string("not over 3x their share: not limb-driven (no refit)"))
          << (r.limb.sensitive ? " (LIMB-SENSITIVE)" : "") << "\n";
    s << "  " << (r.well_posed ? "well posed" : "ILL-POSED") << "; "
      << (r.representable ? "representable" : "NOT REPRESENTABLE") << "\n";
    for (const auto& d : r.diagnostics) s << "  - " << d.text << "\n";
    s << "  " << r.kernel_evaluations << " kernel and " << r.reference_evaluations << " reference evaluations, "
      << num(r.seconds, 3) << " s\n";
    return s.str();
}

}  // namespace shadelab::fit
