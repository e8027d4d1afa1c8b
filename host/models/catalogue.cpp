#include "models/catalogue.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "core/text.hpp"

namespace shadelab {

// Every family's registration, from the list the build writes (cmake/model_families.cmake).
#define SL_FAMILY(name) ModelFamily register_##name##_family();
#include "model_families.inc"
#undef SL_FAMILY

const std::vector<ModelFamily>& model_families() {
    static const std::vector<ModelFamily> all = [] {
        std::vector<ModelFamily> v;
#define SL_FAMILY(name) v.push_back(register_##name##_family());
#include "model_families.inc"
#undef SL_FAMILY
        std::sort(v.begin(), v.end(), [](const ModelFamily& a, const ModelFamily& b) { return a.rank < b.rank; });
        std::set<std::string> names;
        std::set<int> ranks;
        for (auto& f : v) {
            if (!ranks.insert(f.rank).second) throw Error("internal: two model families have rank " + std::to_string(f.rank));
            for (auto& m : f.models) {
                if (!names.insert(m.name).second) throw Error("internal: model '" + m.name + "' registered twice");
                m.family = f.name;
                m.doc = f.doc;
            }
        }
        return v;
    }();
    return all;
}

const std::vector<ModelInfo>& model_catalogue() {
    static const std::vector<ModelInfo> all = [] {
        std::vector<ModelInfo> v;
        for (const auto& f : model_families()) v.insert(v.end(), f.models.begin(), f.models.end());
        return v;
    }();
    return all;
}

const ModelInfo& find_model(const std::string& name) {
    for (const auto& m : model_catalogue())
        if (m.name == name) return m;
    std::vector<std::string> names;
    std::string list;
    for (const auto& m : model_catalogue()) {
        names.push_back(m.name);
        list += (list.empty() ? "" : ", ") + m.name;
    }
    throw Error("unknown model '" + name + "'" + did_you_mean(name, names) + ": choose one of " + list +
                " ('shadelab models' lists them with their parameters)");
}

namespace {
std::string fmt(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}
}  // namespace

void add_demo_children(Material& m, const ModelInfo& info) {
    const glm::dvec3 colours[2] = {{0.85, 0.35, 0.2}, {0.2, 0.45, 0.85}};
    for (int c = 0; c < info.children; ++c) {
        Material child;
        child.model = "lambert";
        child.albedo = colours[c % 2];
        m.children.push_back(child);
    }
}

Material resolve_material(const Material& m, const std::string& where) {
    const std::string at = where.empty() ? "" : where + ": ";
    const ModelInfo* info = nullptr;
    try {
        info = &find_model(m.model);
    } catch (const Error& e) {
        throw Error(at + e.what());
    }
    Material out = m;
    for (const auto& [name, value] : m.params) {
        bool known = false;
        for (const auto& p : info->params) known = known || p.name == name;
        if (!known) {
            std::string names;
            for (const auto& p : info->params) names += (names.empty() ? "" : ", ") + p.name;
            throw Error(at + "model '" + m.model + "' has no parameter '" + name + "'" +
                        (names.empty() ? std::string(" (it takes none)") : " (it takes: " + names + ")"));
        }
    }
    for (const auto& p : info->params) {
        auto it = out.params.find(p.name);
        if (it == out.params.end()) {
            out.params[p.name] = p.def;
            continue;
        }
        const double v = it->second;
        if (!std::isfinite(v) || v < p.lo || v > p.hi || (p.integer && v != std::floor(v)))
            throw Error(at + "parameter '" + p.name + "' of model '" + m.model + "' is " + fmt(v) +
                        ": allowed range is [" + fmt(p.lo) + ", " + fmt(p.hi) + "]" +
                        (p.integer ? " (whole numbers)" : ""));
    }
    for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(m.albedo[c]) || m.albedo[c] < 0.0)
            throw Error(at + "albedo of model '" + m.model + "' must be finite and >= 0 in each channel");
        if (!std::isfinite(m.specular[c]) || m.specular[c] < 0.0)
            throw Error(at + "specular colour of model '" + m.model + "' must be finite and >= 0 in each channel");
    }
    if (int(m.children.size()) != info->children)
        throw Error(at + "model '" + m.model + "' blends " + std::to_string(info->children) +
                    " other models but " + std::to_string(m.children.size()) + " were given");
    for (std::size_t c = 0; c < m.children.size(); ++c) {
        if (find_model(m.children[c].model).children != 0)
            throw Error(at + "model '" + m.model + "' cannot blend '" + m.children[c].model +
                        "', which itself blends other models");
        out.children[c] = resolve_material(m.children[c], where);
    }
    return out;
}

std::vector<double> ordered_params(const ModelInfo& info, const Material& m) {
    std::vector<double> v;
    for (const auto& p : info.params) v.push_back(m.params.at(p.name));
    return v;
}

std::vector<ModelConsts> pack_material(const Material& m) {
    auto pack_one = [](const Material& mat) {
        const ModelInfo& info = find_model(mat.model);
        ModelConsts k{};
        for (int c = 0; c < 3; ++c) {
            k.albedo[c] = float(mat.albedo[c]);
            k.specular[c] = float(mat.specular[c]);
        }
        if (info.pack) info.pack(ordered_params(info, mat), k.block);
        return k;
    };
    std::vector<ModelConsts> out{pack_one(m)};
    for (const auto& c : m.children) out.push_back(pack_one(c));
    return out;
}

}  // namespace shadelab
