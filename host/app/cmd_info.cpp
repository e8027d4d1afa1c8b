// shadelab models / devices: what the catalogue holds and which OpenCL device runs it.
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "cl/runtime.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "models/catalogue.hpp"
#include "shade/shade_program.hpp"
#include "shade/shader.hpp"

namespace shadelab::app {

namespace {

// The documentation page of a model: its family's, as the family registered it.
const std::string& doc_page(const ModelInfo& m) { return m.doc; }

nlohmann::json model_json(const ModelInfo& m) {
    nlohmann::json params = nlohmann::json::array();
    for (const auto& p : m.params)
        params.push_back({{"name", p.name}, {"default", p.def}, {"min", p.lo}, {"max", p.hi},
                          {"integer", p.integer}, {"doc", p.doc}});
    nlohmann::json tables = nlohmann::json::array();
    for (const auto& t : m.tables)
        tables.push_back({{"name", t.name}, {"isis", t.isis}, {"default", t.def}, {"min", t.lo}, {"max", t.hi},
                          {"max_length", t.max_length}, {"knots", t.knots}, {"doc", t.doc}});
    return {{"name", m.name},
            {"family", m.family},
            {"summary", m.summary},
            {"source", m.source},
            {"params", params},
            {"tables", tables},
            {"children", m.children},
            {"reciprocal", m.reciprocal},
            {"energy_conserving", m.energy_conserving},
            {"fast_differs", m.fast_differs},
            {"kernel", m.header},
            {"doc", doc_page(m)}};
}

// A table's default as "v1,v2,..." (what -p name=... takes).
std::string list_text(const std::vector<double>& v) {
    std::ostringstream s;
    for (std::size_t j = 0; j < v.size(); ++j) s << (j ? "," : "") << v[j];
    return s.str();
}

std::string table_line(const TableSpec& t) {
    return t.name + "=" + list_text(t.def) + "  (ISIS " + t.isis + "; 2 to " + std::to_string(t.max_length) +
           " entries in [" + list_text({t.lo}) + ", " + list_text({t.hi}) + "])  " + t.doc;
}

// What --precision fast does to this model (ModelInfo::fast_differs), with its measured errors in both modes
// (its "*" precision row: max relative error against the double reference over tests/test_precision.cpp's
// sweep).
std::string fast_mode_line(const ModelInfo& m) {
    std::ostringstream s;
    if (m.fast_differs)
        s << "its own faster pow (sl_fast_pow: 250 ulp for results >= 2^-10, denormal bases as 0, docs/precision.md)";
    else
        s << "the same program as precise (nothing faster here: docs/precision.md)";
    for (const PrecisionBound& b : m.precision)
        if (b.probe == "*") {
            s << std::setprecision(3) << "; max rel error precise " << b.measured_precise;
            if (m.fast_differs) s << ", fast " << b.measured_fast;
        }
    return s.str();
}

// One model in full: parameters with defaults and ranges, flags, source, doc page.
void print_model(const ModelInfo& m) {
    std::cout << m.name << ": " << m.summary << "\n"
              << "  family:  " << m.family << "\n"
              << "  source:  " << m.source << "\n"
              << "  kernel:  kernels/" << m.header << " (" << m.eval << ")\n"
              << "  doc:     " << doc_page(m) << "\n"
              << "  flags:   " << (m.reciprocal ? "reciprocal" : "not reciprocal") << ", "
              << (m.energy_conserving ? "energy conserving" : "not energy conserving")
              << (m.children > 0 ? ", blends " + std::to_string(m.children) + " child materials" : "") << "\n";
    std::cout << "  fast:    " << fast_mode_line(m) << "\n";
    if (m.params.empty() && m.tables.empty()) std::cout << "  parameters: none\n";
    for (const auto& t : m.tables) std::cout << "  -p " << table_line(t) << "\n";
    for (const auto& p : m.params)
        std::cout << "  -p " << p.name << "=" << p.def << "  range [" << p.lo << ", " << p.hi << "]"
                  << (p.integer ? ", whole numbers" : "") << "  " << p.doc << "\n";
}

// The catalogue as a table: name and summary, then one line per parameter. The name column fits the longest
// name, so no two columns ever run together.
void print_catalogue() {
    std::size_t name_w = 0, param_w = 0;
    for (const auto& m : model_catalogue()) {
        name_w = std::max(name_w, m.name.size());
        for (const auto& p : m.params) param_w = std::max(param_w, p.name.size());
    }
    for (const auto& m : model_catalogue()) {
        std::cout << std::left << std::setw(int(name_w + 2)) << m.name << m.summary << "\n";
        for (const auto& p : m.params)
            std::cout << "    " << std::setw(int(param_w + 2)) << p.name << "default " << p.def << ", range ["
                      << p.lo << ", " << p.hi << "]  " << p.doc << "\n";
        for (const auto& t : m.tables) std::cout << "    " << table_line(t) << "\n";
    }
}

// The catalogue's models for which `pick` holds, comma-separated, or "none".
template <class Pick>
std::string models_where(Pick pick) {
    std::string out;
    for (const auto& info : model_catalogue())
        if (pick(info)) out += (out.empty() ? "" : ", ") + info.name;
    return out.empty() ? "none" : out;
}

// The models shaded with two chains a work-item on a device of this width (Shader::chains_for).
std::string two_chain_models(std::size_t width) {
    return models_where([width](const ModelInfo& info) { return Shader::chains_for(info, width) > 1; });
}

// The models whose work-items take more lanes than the device's on this device (Shader::lanes_for).
std::string wide_lane_models(std::size_t width) {
    return models_where([width](const ModelInfo& info) { return Shader::lanes_for(info, width) > width; });
}

// The models that keep plain stores at every size (ModelInfo::plain_stores).
std::string plain_store_models() {
    return models_where([](const ModelInfo& info) { return info.plain_stores; });
}

// The models that would stream past the threshold but keep plain stores on a device of this width, their
// work-items' blocks being part of a line (Shader::streams_output with the work-item's fragments decides).
std::string half_line_models(std::size_t width) {
    const std::size_t big = (Shader::kStreamOutputBytes + 11) / 12;
    return models_where([width, big](const ModelInfo& info) {
        return Shader::streams_output(info, big) &&
               !Shader::streams_output(info, big, Shader::frags_per_item(info, width));
    });
}

}  // namespace

void require_model_name(const std::string& name, const std::string& option) {
    try {
        find_model(name);
    } catch (const Error& e) {
        throw UsageError(std::string(e.what()) + " [" + option + "]");
    }
}

void add_models_command(CLI::App& app) {
    struct Args {
        std::string name;
        bool json = false;
    };
    auto a = std::make_shared<Args>();
    auto* cmd = app.add_subcommand("models", "List every lighting model with its parameters and ranges "
                                             "(or one model in full: 'shadelab models NAME')");
    cmd->add_option("name", a->name, "Show this model only: parameters, ranges, flags, source, doc page");
    cmd->add_flag("--json", a->json, "Print JSON: an array with one object per model (name, params, ...)");
    cmd->callback([a] {
        if (!a->name.empty()) require_model_name(a->name, "models");
        if (a->json) {
            nlohmann::json out = nlohmann::json::array();
            for (const auto& m : model_catalogue())
                if (a->name.empty() || m.name == a->name) out.push_back(model_json(m));
            std::cout << (a->name.empty() ? out : out[0]).dump(2) << "\n";
        } else if (!a->name.empty()) {
            print_model(find_model(a->name));
        } else {
            print_catalogue();
        }
    });
}

void add_devices_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("devices", "Show the OpenCL device shadelab picks and where its kernels are");
    cmd->callback([] {
        Runtime rt;
        const std::string chains = two_chain_models(rt.vector_width());   // before any output: a bad SHADELAB_CHAINS is one line
        const std::string wide = wide_lane_models(rt.vector_width());     // likewise a bad SHADELAB_WIDE_LANES
        const bool stream_all = Shader::streams_output(1);  // likewise a bad SHADELAB_STREAM_STORES
        const bool stream_none = !Shader::streams_output(std::size_t(1) << 40);
        const bool kinds = light_kinds_in_programs();        // likewise a bad SHADELAB_LIGHT_KINDS
        std::cout << "device:  " << rt.device_description() << "\n"
                  << "kernels: " << rt.kernel_dir() << "\n"
                  << "lanes:   " << rt.vector_width() << " fragments a shading work-item (SHADELAB_VECTOR_WIDTH); "
                  << Shader::lanes_for(true, rt.vector_width()) << " for the models of N and L only"
                  << (wide == "none" ? std::string() : "; " + std::to_string(Shader::kWideLanes) + " for " + wide)
                  << " (SHADELAB_WIDE_LANES=0 or 1 sets every model's on 8-lane devices)\n"
                  << "chains:  two chains of lanes a work-item, twice the fragments, for " << chains
                  << " (SHADELAB_CHAINS=1 or 2 sets every model's)\n"
                  << "stores:  "
                  << (stream_all    ? std::string("streaming (non-temporal) for every launch")
                      : stream_none ? std::string("plain for every launch")
                                    : "streaming (non-temporal) where a launch's shaded planes reach " +
                                          std::to_string(Shader::kStreamOutputBytes >> 20) + " MB (" +
                                          std::to_string((Shader::kStreamOutputBytes + 11) / 12) +
                                          " fragments), plain below and for " + plain_store_models() +
                                          " (measured slower streamed) and " +
                                          half_line_models(rt.vector_width()) +
                                          " (a work-item's block is part of a line on this device)")
                  << " (SHADELAB_STREAM_STORES=0 or 1 sets every launch's)\n"
                  << "lights:  each light's kind (directional, point, point with a range) "
                  << (kinds ? "built into the shade programs" : "read per light at run time")
                  << " (SHADELAB_LIGHT_KINDS=0 or 1)\n"
                  << "choose another with SHADELAB_CL_PLATFORM=<name part> and SHADELAB_CL_DEVICE=<index>\n";
    });
}

}  // namespace shadelab::app
