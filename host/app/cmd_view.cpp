// shadelab view: BRDF-Explorer-style views of one or several models side by side (host/view/view.hpp).
#include <iostream>
#include <memory>
#include <sstream>

#include "app/commands.hpp"
#include "cl/runtime.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "models/catalogue.hpp"
#include "view/view.hpp"

namespace shadelab::app {

namespace {

struct ViewArgs {
    std::string model;
    std::vector<std::string> params;
    std::vector<std::string> vs;
    std::string out = "view";
    double phase = 45.0;
};

// "MODEL" or "MODEL:name=value,name=value" -> a resolved grey material with albedo 1, and its legend label.
view::ViewModel view_model(const std::string& model, const std::vector<std::string>& params, const std::string& opt) {
    require_model_name(model, opt);
    view::ViewModel vm;
    vm.material.model = model;
    vm.material.albedo = glm::dvec3(1.0);
    std::string label = model;
    for (const auto& p : params) {
        const auto kv = parse_param(p);
        vm.material.params[kv.first] = kv.second;
        std::ostringstream s;
        s << kv.first << "=" << kv.second;
        label += (label.size() == model.size() ? " (" : ", ") + s.str();
    }
    if (label.size() != model.size()) label += ")";
    add_demo_children(vm.material, find_model(model));
    vm.material = resolve_material(vm.material, opt + " " + model);
    vm.label = label;
    return vm;
}

void run_view(const ViewArgs& a) {
    std::vector<view::ViewModel> models{view_model(a.model, a.params, "view")};
    for (const auto& spec : a.vs) {
        const auto colon = spec.find(':');
        const std::string name = spec.substr(0, colon);
        std::vector<std::string> params;
        if (colon != std::string::npos)
            for (const auto& p : split(spec.substr(colon + 1), ','))
                if (!p.empty()) params.push_back(p);
        models.push_back(view_model(name, params, "--vs"));
    }
    if (!(a.phase >= 0.0 && a.phase <= 180.0)) throw UsageError("--phase must be in [0, 180] degrees");
    view::ViewOptions o;
    o.sphere_phase_deg = a.phase;
    Runtime rt;
    const view::ViewFiles f = view::write_views(rt, models, a.out, o);
    for (const auto& w : f.written) std::cout << w << "\n";
}

}  // namespace

void add_view_command(CLI::App& app) {
    auto a = std::make_shared<ViewArgs>();
    auto* cmd = app.add_subcommand("view", "Look at models as BRDF Explorer does: incidence-plane lobes, albedo "
                                           "against angle, the theta_h x theta_d slice, a lit sphere (PNG + CSV)");
    cmd->add_option("model", a->model, "The model to view (see 'shadelab models')")->required();
    cmd->add_option("-p,--param", a->params, "Parameter of MODEL, name=value (repeatable)");
    cmd->add_option("--vs", a->vs, "Another model beside it: MODEL or MODEL:name=value,name=value (repeatable)");
    cmd->add_option("-o,--out", a->out, "Folder for the PNGs and the CSVs behind them")->capture_default_str();
    cmd->add_option("--phase", a->phase, "Angle between light and viewer for the lit sphere, degrees")
        ->capture_default_str();
    cmd->callback([a] { run_view(*a); });
}

}  // namespace shadelab::app
