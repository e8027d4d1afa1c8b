#include "models/catalogue.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "core/spline.hpp"
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

namespace {

// The model of `family` named `name`; throws shadelab::Error naming what it was looked up for.
ModelInfo& family_model(ModelFamily& family, const std::string& name, const char* what) {
    const auto it = std::find_if(family.models.begin(), family.models.end(),
                                 [&](const ModelInfo& m) { return m.name == name; });
    if (it == family.models.end())
        throw Error("internal: family '" + family.name + "' has no model '" + name + "' to " + what);
    return *it;
}

}  // namespace

void use_two_chains(ModelFamily& family, const std::vector<std::string>& names) {
    for (const std::string& name : names) {
        ModelInfo& info = family_model(family, name, "give two chains");
        info.chains = info.chains_avx2 = 2;
    }
}

void use_two_chains_on_avx2(ModelFamily& family, const std::vector<std::string>& names) {
    for (const std::string& name : names) family_model(family, name, "give two chains on AVX2").chains_avx2 = 2;
}

void use_sixteen_lanes_on_avx2(ModelFamily& family, const std::vector<std::string>& names, int chains) {
    if (chains != 1 && chains != 2) throw Error("internal: " + std::to_string(chains) + " chains: use 1 or 2");
    for (const std::string& name : names) {
        ModelInfo& info = family_model(family, name, "give sixteen lanes on AVX2");
        if (info.normals_only)
            throw Error("internal: model '" + name + "' reads N and L only, whose lanes are capped "
                        "(Shader::kNormalsOnlyLanes); it cannot take sixteen");
        info.lanes_avx2 = 16;
        info.chains_avx2 = chains;
    }
}

void use_plain_stores(ModelFamily& family, const std::vector<std::string>& names) {
    for (const std::string& name : names) family_model(family, name, "give plain stores").plain_stores = true;
}

void use_fast_pow(ModelFamily& family, const std::vector<std::string>& names) {
    for (const std::string& name : names) family_model(family, name, "mark as calling pow").fast_differs = true;
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

namespace {

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// The table spec `name` stands for (shadelab's name or ISIS's keyword, case-insensitive for ISIS's), or nullptr.
const TableSpec* table_named(const ModelInfo& info, const std::string& name) {
    for (const auto& t : info.tables)
        if (name == t.name || (!t.isis.empty() && lower(name) == lower(t.isis))) return &t;
    return nullptr;
}

std::string names_of(const ModelInfo& info) {
    std::string names;
    for (const auto& p : info.params) names += (names.empty() ? "" : ", ") + p.name;
    for (const auto& t : info.tables) names += (names.empty() ? "" : ", ") + t.name + " (list)";
    return names;
}

void check_table_lengths(const ModelInfo& info, const Material& out, const std::string& at);
void check_curves(const ModelInfo& info, const Material& out, const std::string& at);

// One table of `info` checked: length, finite values in range, increasing knots.
void check_table(const TableSpec& t, const std::vector<double>& v, const std::string& at, const std::string& model) {
    const std::string what = at + "table '" + t.name + "' of model '" + model + "'";
    if (v.size() < 2 || v.size() > t.max_length)
        throw Error(what + " has " + std::to_string(v.size()) + " entries: allowed 2 to " +
                    std::to_string(t.max_length) + " (give a list v1,v2,... one entry per phase)");
    for (std::size_t j = 0; j < v.size(); ++j) {
        if (!std::isfinite(v[j]) || v[j] < t.lo || v[j] > t.hi)
            throw Error(what + " entry " + std::to_string(j + 1) + " is " + fmt(v[j]) + ": allowed range is [" +
                        fmt(t.lo) + ", " + fmt(t.hi) + "]");
        if (t.knots && j > 0 && !(v[j] > v[j - 1]))
            throw Error(what + " is not increasing: entry " + std::to_string(j + 1) + " = " + fmt(v[j]) + " follows " +
                        fmt(v[j - 1]) + " (phases must be strictly increasing)");
    }
}

// The tables of `m` under their shadelab names (ISIS's accepted; a scalar given for a table is a one-entry table),
// defaults filled, each checked, all of one length.
void resolve_tables(const ModelInfo& info, const Material& m, Material& out, const std::string& at) {
    out.tables.clear();
    auto take = [&](const std::string& name, const std::vector<double>& v) {
        const TableSpec* t = table_named(info, name);
        if (!t) {
            const std::string names = names_of(info);
            throw Error(at + "model '" + m.model + "' has no table parameter '" + name + "'" +
                        (names.empty() ? std::string(" (it takes none)") : " (it takes: " + names + ")"));
        }
        out.tables[t->name] = v;
    };
    for (const auto& [name, v] : m.tables) take(name, v);
    for (const auto& [name, v] : m.params)
        if (table_named(info, name)) {
            take(name, {v});
            out.params.erase(name);
        }
    for (const auto& t : info.tables) {
        auto it = out.tables.find(t.name);
        if (it == out.tables.end()) it = out.tables.emplace(t.name, t.def).first;
        check_table(t, it->second, at, m.model);
    }
    check_table_lengths(info, out, at);
    check_curves(info, out, at);
}

// Every table of the model as long as its first.
void check_table_lengths(const ModelInfo& info, const Material& out, const std::string& at) {
    if (info.tables.empty()) return;
    const std::string& first = info.tables.front().name;
    for (const auto& t : info.tables)
        if (out.tables.at(t.name).size() != out.tables.at(first).size())
            throw Error(at + "table '" + t.name + "' of model '" + info.name + "' has " +
                        std::to_string(out.tables.at(t.name).size()) + " entries but '" + first + "' has " +
                        std::to_string(out.tables.at(first).size()) + ": one entry per phase");
}

// Each table's spline over the knots, continued beyond them, within [curve_lo, curve_hi] at every phase 0..180
// (every 0.25 degree and at the knots): a table whose end cubic runs away is refused, naming the phase.
void check_curves(const ModelInfo& info, const Material& out, const std::string& at) {
    const TableSpec* knots = nullptr;
    for (const auto& t : info.tables)
        if (t.knots) knots = &t;
    if (!knots) return;
    const std::vector<double>& x = out.tables.at(knots->name);
    for (const auto& t : info.tables) {
        if (t.knots) continue;
        const NaturalSpline s(x, out.tables.at(t.name));
        std::vector<double> probes = x;
        for (int q = 0; q <= 720; ++q) probes.push_back(0.25 * q);
        for (double g : probes) {
            const double v = s(g);
            if (std::isfinite(v) && v >= t.curve_lo && v <= t.curve_hi) continue;
            throw Error(at + "table '" + t.name + "' of model '" + info.name + "': its spline is " + fmt(v) +
                        " at phase " + fmt(g) + " (continued beyond the table's " + fmt(x.front()) + " to " +
                        fmt(x.back()) + " deg), outside [" + fmt(t.curve_lo) + ", " + fmt(t.curve_hi) +
                        "]: extend the table to cover the phases 0 to 180 or smooth it");
        }
    }
}

void resolve_params(const ModelInfo& info, const Material& m, Material& out, const std::string& at) {
    for (const auto& [name, value] : out.params) {
        bool known = false;
        for (const auto& p : info.params) known = known || p.name == name;
        if (!known) {
            const std::string names = names_of(info);
            throw Error(at + "model '" + m.model + "' has no parameter '" + name + "'" +
                        (names.empty() ? std::string(" (it takes none)") : " (it takes: " + names + ")"));
        }
    }
    for (const auto& p : info.params) {
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
}

}  // namespace

Material resolve_material(const Material& m, const std::string& where) {
    const std::string at = where.empty() ? "" : where + ": ";
    const ModelInfo* info = nullptr;
    try {
        info = &find_model(m.model);
    } catch (const Error& e) {
        throw Error(at + e.what());
    }
    Material out = m;
    resolve_tables(*info, m, out, at);
    resolve_params(*info, m, out, at);
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
        const ModelInfo& ci = find_model(m.children[c].model);
        if (ci.children != 0)
            throw Error(at + "model '" + m.model + "' cannot blend '" + m.children[c].model +
                        "', which itself blends other models");
        if (has_tables(ci))
            throw Error(at + "model '" + m.model + "' cannot blend '" + m.children[c].model +
                        "': a blend's children read no table buffer (use a model without tables)");
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

std::vector<float> pack_table(const Material& m) {
    const ModelInfo& info = find_model(m.model);
    if (!info.pack_table) return {0.0f};
    return info.pack_table(m);
}

}  // namespace shadelab
