#include "photometry/isis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdlib>
#include <sstream>

#include "core/error.hpp"
#include "models/catalogue.hpp"
#include "reference/planetary_ref.hpp"
#include "reference/reference.hpp"

namespace shadelab::photometry {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

std::string num(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

std::string at(const std::string& file, int line) { return file + ":" + std::to_string(line) + ": "; }

// ---- the keyword tables ---------------------------------------------------------------------------------

// One keyword of an ISIS model: its catalogue parameter, ISIS's default, the range shadelab accepts (open or
// closed at each end) and, where ISIS's own range differs, what ISIS allows.
struct KeySpec {
    const char* isis;
    const char* param;
    double def;
    double lo, hi;
    bool lo_open, hi_open;
    const char* isis_range;   // nullptr: the same as shadelab's
};

struct ModelSpec {
    const char* isis;
    const char* model;   // catalogue model, nullptr for the empirical laws
    std::vector<KeySpec> keys;
    std::vector<const char*> ignored;   // keywords ISIS reads that do not change the value (warned about)
};

const std::vector<KeySpec> kHapkeCommon = {
    {"Wh", "wh", 0.5, 1e-6, 1.0, false, false, "ISIS: 0 < Wh <= 1"},
    {"B0", "b0", 0.0, 0.0, 10.0, false, false, "ISIS: B0 >= 0"},
    {"Hh", "hh", 0.0, 0.0, 10.0, false, false, "ISIS: Hh >= 0"},
    {"Theta", "theta", 0.0, 0.0, 90.0, false, false, nullptr},
};

std::vector<KeySpec> with(std::vector<KeySpec> a, const std::vector<KeySpec>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

const std::vector<ModelSpec>& specs() {
    static const std::vector<ModelSpec> s = {
        {"Lambert", "lambert", {}, {}},
        {"LommelSeeliger", "lommel_seeliger", {}, {}},
        {"LunarLambert", "lunar_lambert", {{"L", "l", 1.0, -1.0, 2.0, false, false, "ISIS sets no bounds"}}, {}},
        {"LunarLambertMcEwen", "lunar_lambert_mcewen_ratio", {}, {}},
        {"Minnaert", "minnaert_1941", {{"K", "k", 1.0, 0.0, 2.0, false, false, "ISIS: K >= 0"}}, {}},
        {"HapkeHen", "hapke_hen",
         with(kHapkeCommon, {{"Hg1", "hg1", 0.0, -0.9999, 0.9999, false, false, "ISIS: -1 < Hg1 < 1"},
                             {"Hg2", "hg2", 0.0, 0.0, 1.0, false, false, nullptr}}),
         {"Bh", "Ch"}},
        {"HapkeLeg", "hapke_leg",
         with(kHapkeCommon, {{"Bh", "bh", 0.0, -1.0, 1.0, false, false, nullptr},
                             {"Ch", "ch", 0.0, -1.0, 1.0, false, false, nullptr}}),
         {"Hg1", "Hg2"}},
        {"MinnaertEmpirical", nullptr, {}, {}},
        {"LunarLambertEmpirical", nullptr, {}, {}},
    };
    return s;
}

std::string range_text(const KeySpec& k) {
    std::string r = num(k.lo) + (k.lo_open ? " < " : " <= ") + k.isis + (k.hi_open ? " < " : " <= ") + num(k.hi);
    if (k.isis_range) r += std::string(" (") + k.isis_range + "; shadelab bounds it for its fits and kernels)";
    return r;
}

double parse_number(const std::string& text, const std::string& where, const std::string& key) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v))
        throw Error(where + "keyword " + key + " = '" + text + "' is not a finite number");
    return v;
}

// A table keyword: a PVL list (a, b, c) or one string "a,b,c" (both forms ISIS reads).
std::vector<double> parse_table(const pvl::Keyword& k, const std::string& file) {
    std::vector<std::string> items;
    if (k.list) items = k.values;
    else {
        std::string cur;
        std::istringstream in(k.values.empty() ? std::string() : k.values[0]);
        while (std::getline(in, cur, ',')) items.push_back(cur);
    }
    std::vector<double> out;
    for (auto s : items) {
        s.erase(0, s.find_first_not_of(" \t"));
        s.erase(s.find_last_not_of(" \t") + 1);
        out.push_back(parse_number(s, at(file, k.line), k.name + " (entry " + std::to_string(out.size() + 1) + ")"));
    }
    return out;
}

bool is_bool_word(const std::string& v) {
    for (const char* w : {"TRUE", "FALSE", "YES", "NO"})
        if (pvl::iequals(v, w)) return true;
    return false;
}

// ---- evaluation helpers -----------------------------------------------------------------------------------

// cos and sin in degrees with exact zeros at the multiples of 90 (so that i = 90 is unlit, not lit by 6e-17).
double cosd(double d) {
    const double r = std::remainder(d, 360.0);
    return std::abs(r) == 90.0 ? 0.0 : std::cos(r * kDeg);
}
double sind(double d) {
    const double r = std::remainder(d, 360.0);
    return (r == 0.0 || std::abs(r) == 180.0) ? 0.0 : std::sin(r * kDeg);
}

// tan(psi/2) of the azimuth psi between the planes of incidence and emission, from the half-angle forms
//   sin^2(psi/2) = sin((g + i - e)/2) sin((g - i + e)/2) / (sin i sin e),
//   cos^2(psi/2) = sin((i + e + g)/2) sin((i + e - g)/2) / (sin i sin e),
// which keep their digits at psi = 0 and 180 (1 - cos psi does not). A phase no facet can have is clamped as ISIS
// clamps cos psi: g < |i - e| gives psi = 0, g > i + e gives psi = 180 (tan 1e18). psi = 0 when a sine is 0.
double tan_half_azimuth(const Geometry& g, double si, double se) {
    if (si * se == 0.0) return 0.0;
    const double num = sind(0.5 * (g.phase + g.incidence - g.emission)) * sind(0.5 * (g.phase - g.incidence + g.emission));
    const double den = sind(0.5 * (g.incidence + g.emission + g.phase)) * sind(0.5 * (g.incidence + g.emission - g.phase));
    if (!(num > 0.0)) return 0.0;
    if (!(den > 0.0)) return 1e18;
    return std::min(std::sqrt(num / den), 1e18);
}

std::size_t round_up(std::size_t n, std::size_t m) { return (n + m - 1) / m * m; }

cl::Buffer to_device(Runtime& rt, const std::vector<float>& v) {
    return cl::Buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(float),
                      const_cast<float*>(v.data()));
}

}  // namespace

// ---- reading ---------------------------------------------------------------------------------------------

namespace {

// The empirical law's tables (law.empirical set), its splines and its catalogue material (the empirical family's
// model with the tables under their catalogue names: what the double reference evaluates).
void set_empirical_tables(Law& law, const std::vector<double>& phases, const std::vector<double>& params,
                          const std::vector<double>& bright) {
    law.phases = phases;
    law.params = params;
    law.brightness = bright;
    law.param_of_phase = NaturalSpline(phases, params);
    law.brightness_of_phase = NaturalSpline(phases, bright);
    law.material = Material{};
    law.material.model = law.empirical == 1 ? "minnaert_empirical" : "lunar_lambert_empirical";
    law.material.albedo = glm::dvec3(1.0);
    law.material.tables = {{"phase_list", phases},
                           {law.empirical == 1 ? "k_list" : "l_list", params},
                           {"phase_curve_list", bright}};
}

}  // namespace

const std::vector<std::string>& isis_model_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        for (const auto& s : specs()) v.push_back(s.isis);
        return v;
    }();
    return names;
}

std::string Law::describe() const {
    std::ostringstream s;
    if (!isis_name.empty()) s << isis_name << " -> ";
    if (empirical) {
        s << (empirical == 1 ? "Minnaert K(g)" : "Lunar-Lambert L(g)") << " and B(g) tables of " << phases.size()
          << " phases (" << phases.front() << " to " << phases.back() << " deg), natural cubic spline";
        return s.str();
    }
    s << material.model;
    for (const auto& [k, v] : material.params) s << " " << k << "=" << v;
    return s.str();
}

// The tables of an empirical law's Algorithm group (PhaseList, KList or LList, PhaseCurveList), checked.
static void read_empirical_tables(Law& law, const pvl::Block& alg, const std::string& isis, const std::string& file) {
    law.empirical = pvl::iequals(isis, "MinnaertEmpirical") ? 1 : 2;
    const char* pkey = law.empirical == 1 ? "KList" : "LList";
    auto table = [&](const char* key) {
        const pvl::Keyword* kw = alg.keyword(key);
        if (!kw)
            throw Error(at(file, alg.line) + isis + " needs keyword " + key +
                        " (PhaseList, " + pkey + " and PhaseCurveList, one entry per phase angle)");
        return std::make_pair(kw, parse_table(*kw, file));
    };
    const auto [kp, phases] = table("PhaseList");
    const auto [kk, params] = table(pkey);
    const auto [kb, bright] = table("PhaseCurveList");
    if (phases.size() < 3)
        throw Error(at(file, kp->line) + "PhaseList has " + std::to_string(phases.size()) +
                    " entries: ISIS's spline needs at least 3");
    for (std::size_t j = 0; j < phases.size(); ++j) {
        if (phases[j] < 0.0 || phases[j] > 180.0)
            throw Error(at(file, kp->line) + "PhaseList entry " + std::to_string(j + 1) + " = " + num(phases[j]) +
                        " is out of range: allowed 0 <= phase <= 180 degrees");
        if (j > 0 && !(phases[j] > phases[j - 1]))
            throw Error(at(file, kp->line) + "PhaseList is not increasing: entry " + std::to_string(j + 1) + " = " +
                        num(phases[j]) + " follows " + num(phases[j - 1]) + " (phases must be strictly increasing)");
    }
    if (params.size() != phases.size())
        throw Error(at(file, kk->line) + std::string(pkey) + " has " + std::to_string(params.size()) +
                    " entries but PhaseList has " + std::to_string(phases.size()) + ": one per phase angle");
    if (bright.size() != phases.size())
        throw Error(at(file, kb->line) + "PhaseCurveList has " + std::to_string(bright.size()) +
                    " entries but PhaseList has " + std::to_string(phases.size()) + ": one per phase angle");
    set_empirical_tables(law, phases, params, bright);
}

Law law_from_pvl(const pvl::Block& root, const std::string& file) {
    const pvl::Block* obj = root.find("Object", "PhotometricModel");
    if (!obj) throw Error(file + ": no 'Object = PhotometricModel' (ISIS's photometric parameter form)");
    const pvl::Block* alg = obj->find("Group", "Algorithm");
    if (!alg) throw Error(at(file, obj->line) + "Object PhotometricModel has no 'Group = Algorithm'");
    const pvl::Keyword* name = alg->keyword("PHTNAME");   // ISIS: PHTNAME (GUI form) before Name
    if (!name) name = alg->keyword("Name");
    if (!name || name->values.size() != 1)
        throw Error(at(file, alg->line) + "Group Algorithm has no keyword Name (the photometric model, e.g. Name = HapkeHen)");
    const ModelSpec* spec = nullptr;
    for (const auto& s : specs())
        if (pvl::iequals(s.isis, name->values[0])) spec = &s;
    if (!spec) {
        std::string names;
        for (const auto& n : isis_model_names()) names += (names.empty() ? "" : ", ") + n;
        throw Error(at(file, name->line) + "Name = " + name->values[0] +
                    " is not a photometric model shadelab knows: choose one of " + names);
    }
    Law law;
    law.isis_name = spec->isis;
    law.source = file;

    auto known = [&](const std::string& key) {
        if (pvl::iequals(key, "Name") || pvl::iequals(key, "PHTNAME")) return true;
        for (const auto& k : spec->keys)
            if (pvl::iequals(k.isis, key)) return true;
        for (const char* k : spec->ignored)
            if (pvl::iequals(k, key)) return true;
        if (spec->model == nullptr)
            for (const char* k : {"PhaseList", "KList", "LList", "PhaseCurveList"})
                if (pvl::iequals(k, key)) return true;
        return (std::string(spec->isis).rfind("Hapke", 0) == 0) && pvl::iequals(key, "ZeroB0Standard");
    };
    for (const auto& k : alg->keywords) {
        if (!known(k.name))
            law.warnings.push_back(at(file, k.line) + "keyword " + k.name + " is not read by ISIS's " + spec->isis +
                                   " (ignored, as ISIS ignores it)");
        for (const char* ig : spec->ignored)
            if (pvl::iequals(ig, k.name))
                law.warnings.push_back(at(file, k.line) + "keyword " + k.name + " does not enter " + spec->isis +
                                       " (ISIS reads it and does not use it either)");
    }
    if (const pvl::Keyword* z = alg->keyword("ZeroB0Standard"); z && known(z->name)) {
        if (z->values.size() != 1 || !is_bool_word(z->values[0]))
            throw Error(at(file, z->line) + "ZeroB0Standard = " + (z->values.empty() ? "" : z->values[0]) +
                        " is not allowed: use TRUE, FALSE, YES or NO");
        law.zero_b0_standard = pvl::iequals(z->values[0], "TRUE") || pvl::iequals(z->values[0], "YES");
    }

    if (spec->model) {
        Material m;
        m.model = spec->model;
        m.albedo = glm::dvec3(1.0);
        for (const auto& k : spec->keys) {
            double v = k.def;
            if (const pvl::Keyword* kw = alg->keyword(k.isis)) {
                if (kw->values.size() != 1)
                    throw Error(at(file, kw->line) + "keyword " + k.isis + " of " + spec->isis + " takes one number");
                v = parse_number(kw->values[0], at(file, kw->line), k.isis);
                const bool ok = (k.lo_open ? v > k.lo : v >= k.lo) && (k.hi_open ? v < k.hi : v <= k.hi);
                if (!ok)
                    throw Error(at(file, kw->line) + k.isis + " = " + kw->values[0] + " is out of range for " +
                                spec->isis + ": allowed " + range_text(k));
            }
            m.params[k.param] = v;
        }
        law.material = resolve_material(m, file);
        return law;
    }

    // The empirical laws: three tables over phase, no defaults (ISIS refuses a file without them).
    read_empirical_tables(law, *alg, spec->isis, file);
    return law;
}

Law law_from_pvl_file(const std::string& path) { return law_from_pvl(pvl::parse_file(path), path); }

Law standard_conditions(const Law& law) {
    Law s = law;
    const std::string& m = s.material.model;
    if (!s.empirical && s.zero_b0_standard && (m == "hapke_hen" || m == "hapke_leg" || m == "hapke_2012"))
        s.material.params["b0"] = 0.0;
    return s;
}

Law law_from_model(const std::string& model, const std::map<std::string, double>& params,
                   const std::map<std::string, std::vector<double>>& tables) {
    Law law;
    Material m;
    m.model = model;
    m.params = params;
    m.tables = tables;
    m.albedo = glm::dvec3(1.0);
    law.material = resolve_material(m);
    // The empirical family's catalogue models take ISIS's path (the splines in double per row, eval_empirical).
    if (model == "minnaert_empirical" || model == "lunar_lambert_empirical") {
        const Material r = law.material;
        law.empirical = model == "minnaert_empirical" ? 1 : 2;
        set_empirical_tables(law, r.tables.at("phase_list"), r.tables.at(law.empirical == 1 ? "k_list" : "l_list"),
                             r.tables.at("phase_curve_list"));
    }
    return law;
}

void check_geometry(const Geometry& g, const std::string& where) {
    const std::pair<const char*, double> angles[] = {
        {"phase", g.phase}, {"incidence", g.incidence}, {"emission", g.emission}};
    for (const auto& [name, v] : angles)
        if (!std::isfinite(v) || v < 0.0 || v > 180.0)
            throw Error(where + std::string(where.empty() ? "" : ": ") + name + " " + num(v) +
                        " is out of range: allowed 0 to 180 degrees");
}

// ---- evaluation ------------------------------------------------------------------------------------------

// ISIS continues an empirical table's natural spline beyond its last phase, where a steep table can run away
// (K -> -60 makes mu^(K-1) overflow): a value the float kernel cannot hold is refused, naming the row, the
// parameter the spline gives there and the table's range, never written as a number.
void check_empirical_finite(const Law& law, const std::vector<Geometry>& rows) {
    for (std::size_t r = 0; r < rows.size(); ++r) {
        const double v = evaluate_reference(law, rows[r]);
        if (std::isfinite(v) && std::fabs(v) <= double(std::numeric_limits<float>::max())) continue;
        const Geometry& g = rows[r];
        throw Error("row " + std::to_string(r + 1) + " (phase " + num(g.phase) + " deg): the " +
                    (law.empirical == 1 ? std::string("MinnaertEmpirical law is not finite: K = ")
                                        : std::string("LunarLambertEmpirical law is not finite: L = ")) +
                    num(law.param_of_phase(g.phase)) + ", B = " + num(law.brightness_of_phase(g.phase)) +
                    " from the tables' spline, which are given for phases " + num(law.phases.front()) + " to " +
                    num(law.phases.back()) + " deg: extend PhaseList and its tables to cover this phase");
    }
}

PhoArrays pho_arrays(const Law& law, const std::vector<Geometry>& rows, std::size_t first, std::size_t n,
                     std::size_t padded) {
    PhoArrays p;
    for (auto* v : {&p.mu0, &p.mu, &p.sin_i, &p.sin_e, &p.cos_g, &p.tan_half_g, &p.tan_half_psi}) v->assign(padded, 0.0f);
    for (std::size_t j = 0; j < n; ++j) {
        const Geometry& g = rows[first + j];
        p.mu0[j] = float(cosd(g.incidence));
        p.mu[j] = float(cosd(g.emission));
        if (law.empirical) {
            p.sin_i[j] = float(law.param_of_phase(g.phase));
            // B(g) held at 0 where the continued spline falls below it, as the catalogue model (docs/photometry.md)
            p.sin_e[j] = float(std::max(law.brightness_of_phase(g.phase), 0.0));
            continue;
        }
        const double si = sind(g.incidence), se = sind(g.emission);
        p.sin_i[j] = float(si);
        p.sin_e[j] = float(se);
        p.cos_g[j] = float(cosd(g.phase));
        p.tan_half_g[j] = float(g.phase >= 180.0 ? 1e18 : std::tan(0.5 * g.phase * kDeg));
        p.tan_half_psi[j] = float(tan_half_azimuth(g, si, se));
    }
    return p;
}

std::vector<std::string> pho_defines(const Law& law, Precision precision, bool raw, std::size_t device_width) {
    std::vector<std::string> defines;
    if (law.empirical) {
        // The empirical kernel reads no model, but the file is built with one: the catalogue's Lommel-Seeliger,
        // wherever its family registered it.
        const ModelInfo& any = find_model("lommel_seeliger");
        defines = {"SL_MODEL_HEADER=<" + any.header + ">", "SL_EVAL=" + any.eval};
    } else {
        const ModelInfo& info = find_model(law.material.model);
        defines = {"SL_MODEL_HEADER=<" + info.header + ">", "SL_EVAL=" + info.eval};
        if (ref::is_planetary_model(info.name)) defines.push_back("SL_PHO_EVAL=" + info.name + "_pho");
    }
    if (precision == Precision::Fast) defines.push_back("SL_FAST=1");
    if (raw) defines.push_back("SL_PHO_RAW=1");
    if (!law.empirical)   // the chains of the law's catalogue model's shade kernel, at the device's lanes
        if (const std::size_t chains = Shader::chains_for(find_model(law.material.model), device_width); chains > 1)
            defines.push_back("SL_CHAINS=" + std::to_string(chains));
    return defines;
}

std::size_t pho_rows_per_item(const Law& law, std::size_t device_width) {
    // The device's lanes, not Shader::lanes_for's: the laws whose shade kernel takes sixteen lanes on AVX2 measured
    // no gain at sixteen here (docs/speed.md, "Sixteen lanes on AVX2": hapke_leg 0.73-1.05x in bench_photometry)
    if (law.empirical) return 1;
    return Shader::frags_of(device_width, Shader::chains_for(find_model(law.material.model), device_width));
}

void enqueue_rows(Runtime& rt, cl::Kernel& k, const Law& law, std::size_t rows, std::size_t local,
                  std::size_t sets) {
    const std::size_t per_item = pho_rows_per_item(law, rt.vector_width());
    const cl::NDRange global = sets ? cl::NDRange(rows / per_item, sets) : cl::NDRange(rows / per_item);
    const cl::NDRange group = sets ? cl::NDRange(local / per_item, 1) : cl::NDRange(local / per_item);
    rt.queue().enqueueNDRangeKernel(k, cl::NullRange, global, group);
}

std::vector<double> evaluate(Runtime& rt, const Law& law, const std::vector<Geometry>& rows, Precision precision,
                             bool raw) {
    for (std::size_t r = 0; r < rows.size(); ++r) check_geometry(rows[r], "row " + std::to_string(r + 1));
    if (law.empirical) check_empirical_finite(law, rows);
    std::vector<double> result(rows.size(), 0.0);
    if (rows.empty()) return result;
    try {
        cl::Program prog = rt.build("photometry.cl", pho_defines(law, precision, raw, rt.vector_width()), Shader::options_for(precision));
        const auto consts = law.empirical ? std::vector<ModelConsts>{} : pack_material(law.material);
        const std::size_t chunk = std::size_t(1) << 22, local = 256;
        for (std::size_t first = 0; first < rows.size(); first += chunk) {
            const std::size_t n = std::min(chunk, rows.size() - first), padded = round_up(n, local);
            // padded to the launch size (eval_photometric has no bounds check): the padding is mu0 = mu = 0, unlit
            const PhoArrays p = pho_arrays(law, rows, first, n, padded);
            cl::Buffer bout(rt.context(), CL_MEM_WRITE_ONLY, padded * sizeof(float));
            cl::Kernel k;
            std::vector<cl::Buffer> keep;
            if (law.empirical) {
                k = cl::Kernel(prog, "eval_empirical");
                keep = {to_device(rt, p.mu0), to_device(rt, p.mu), to_device(rt, p.sin_i), to_device(rt, p.sin_e)};
                for (cl_uint i = 0; i < 4; ++i) k.setArg(i, keep[i]);
                k.setArg(4, bout);
                k.setArg(5, cl_uint(n));
                k.setArg(6, cl_uint(law.empirical));
            } else {
                k = cl::Kernel(prog, "eval_photometric");
                keep = {to_device(rt, p.mu0), to_device(rt, p.mu), to_device(rt, p.sin_i), to_device(rt, p.sin_e),
                        to_device(rt, p.cos_g), to_device(rt, p.tan_half_g), to_device(rt, p.tan_half_psi)};
                for (cl_uint i = 0; i < 7; ++i) k.setArg(i, keep[i]);
                keep.emplace_back(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                  consts.size() * sizeof(ModelConsts), const_cast<ModelConsts*>(consts.data()));
                k.setArg(7, bout);
                k.setArg(8, cl_uint(n));
                k.setArg(9, keep.back());
            }
            enqueue_rows(rt, k, law, padded, local);
            std::vector<float> out(n);
            rt.queue().enqueueReadBuffer(bout, CL_TRUE, 0, n * sizeof(float), out.data());
            for (std::size_t j = 0; j < n; ++j) result[first + j] = out[j];
        }
    } catch (const cl::Error& e) {
        rethrow_cl(e, "photometry evaluation");
    }
    return result;
}

double evaluate_reference(const Law& law, const Geometry& g) {
    check_geometry(g, "");
    const ref::PhotometricAngles a = ref::angles_from_degrees(g.phase, g.incidence, g.emission);
    // the empirical laws through their catalogue model's reference (host/reference/empirical_ref.cpp)
    if (ref::is_planetary_model(law.material.model)) return ref::planetary_value(law.material, a);
    // A model defined on vectors: N = z, L in the xz plane, V at the azimuth psi.
    const glm::dvec3 N{0, 0, 1}, L{a.sin_i, 0.0, a.mu0};
    const glm::dvec3 V{a.sin_e * std::cos(a.psi), a.sin_e * std::sin(a.psi), a.mu};
    return ref::eval_material(N, L, V, N, law.material).x;
}

}  // namespace shadelab::photometry
