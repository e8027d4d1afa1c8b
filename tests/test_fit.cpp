// Fitting one model to another (host/fit/, issue 11). Layers: the domain; exact equivalences recovered to 1e-6
// with the error at rounding level; the error of a returned fit recomputed independently, and no better point
// on a brute-force grid; ill-posed fits said in words; the limb check; ranges never left; stability across
// seeds; the JSON contract and --all.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "fit/all.hpp"
#include "fit/fit.hpp"
#include "fit/report.hpp"
#include "reference/reference.hpp"
#include "scene/batch.hpp"
#include "scene/scene.hpp"
#include "image/image.hpp"
#include "mesh/mesh.hpp"
#include "raster/raster.hpp"
#include "moon/disc.hpp"
#include "speed/pareto.hpp"
#include "support.hpp"

using namespace shadelab;

namespace {

Material target_of(const std::string& model, std::map<std::string, double> params = {}) {
    Material m;
    m.model = model;
    m.params = std::move(params);
    m.albedo = glm::dvec3(0.8);
    m.specular = glm::dvec3(1.0);
    add_demo_children(m, find_model(model));
    for (auto& c : m.children) c.albedo = glm::dvec3(1.0);
    return resolve_material(m);
}

fit::Domain hemisphere(std::size_t n = 16384, std::uint64_t seed = 1, double min_cos = 0.0) {
    fit::HemisphereOptions o;
    o.samples = n;
    o.seed = seed;
    o.min_cos = min_cos;
    return fit::hemisphere_domain(o);
}

fit::FitResult fit_to(const Material& target, const std::string& model, fit::Domain d, fit::FitOptions o = {}) {
    fit::Problem p(test::runtime(), std::move(d), target);
    return fit::fit_model(p, fit::shape_for(model, target, -1.0, nullptr), {}, o);
}

double param(const fit::FitResult& r, const std::string& name) {
    for (const auto& p : r.params)
        if (p.name == name) return p.value;
    FAIL("no parameter " << name);
    return 0.0;
}

bool has(const fit::FitResult& r, const std::string& kind) {
    for (const auto& d : r.diagnostics)
        if (d.kind == kind) return true;
    return false;
}

// rel-rms of `model` at `x` with scale `a` against `target`, written out here from the references alone.
double independent_rel_rms(const fit::Domain& d, const Material& target, const Material& fitted, double a) {
    double num = 0.0, den = 0.0;
    for (std::size_t i = 0; i < d.size(); ++i) {
        const double t = ref::eval_material(d.N[i], d.L[i], d.V[i], d.P[i], target).x;
        const double f = ref::eval_material(d.N[i], d.L[i], d.V[i], d.P[i], fitted).x;
        num += (a * f - t) * (a * f - t);
        den += t * t;
    }
    return std::sqrt(num / den);
}

// Renders a scene file with the batch renderer into `out` (its outputs: colour EXR and AOVs). True on success.
bool render_with_batch(const std::string& scene_file, const std::string& out) {
    std::ostringstream log;
    BatchOptions bo;
    bo.out_dir = out;
    bo.progress = ProgressStyle::Lines;
    bo.log = &log;
    bo.scenes = {scene_file};
    const bool ok = run_batch(bo, test::runtime()).ok == 1;
    if (!ok) WARN(log.str());
    return ok;
}

}  // namespace

TEST_CASE("fit domain: the hemisphere is N = +z with L and V uniform in solid angle", "[modelfit]") {
    const fit::Domain d = hemisphere(65536, 7);
    REQUIRE(d.size() == 65536);
    // Uniform in solid angle: cos theta uniform on [0, 1] (mean 1/2, mean of squares 1/3), azimuths uniform.
    double mL = 0, mV = 0, m2L = 0, cphi = 0, sphi = 0, cdphi = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
        REQUIRE(d.N[i] == glm::dvec3(0, 0, 1));
        REQUIRE(std::abs(glm::length(d.L[i]) - 1.0) < 1e-12);
        REQUIRE(d.L[i].z >= 0.0);
        REQUIRE(d.V[i].z >= 0.0);
        mL += d.L[i].z, mV += d.V[i].z, m2L += d.L[i].z * d.L[i].z;
        cphi += std::atan2(d.L[i].y, d.L[i].x) > 0 ? 1 : -1;
        const glm::dvec2 a(d.L[i]), b(d.V[i]);
        if (glm::length(a) > 1e-9 && glm::length(b) > 1e-9) cdphi += glm::dot(a, b) / (glm::length(a) * glm::length(b));
        sphi += 0;
    }
    const double n = double(d.size());
    CHECK(std::abs(mL / n - 0.5) < 1e-3);
    CHECK(std::abs(mV / n - 0.5) < 1e-3);
    CHECK(std::abs(m2L / n - 1.0 / 3.0) < 1e-3);
    CHECK(std::abs(cphi / n) < 1e-2);
    CHECK(std::abs(cdphi / n) < 1e-2);   // the azimuth difference is uniform: mean cos 0
    // A phase restriction keeps angle(L, V) = G exactly, with V above the horizon.
    fit::HemisphereOptions o;
    o.samples = 4096;
    o.has_phase = true;
    o.phase_deg = 30.0;
    const fit::Domain g = fit::hemisphere_domain(o);
    for (std::size_t i = 0; i < g.size(); ++i) {
        REQUIRE(std::abs(glm::dot(g.L[i], g.V[i]) - std::cos(30.0 * M_PI / 180.0)) < 1e-12);
        REQUIRE(g.V[i].z >= 0.0);
    }
    CHECK_THROWS_WITH(fit::hemisphere_domain(fit::HemisphereOptions{10}), Catch::Contains("--samples"));
}

TEST_CASE("fit: known equivalences come back to 1e-6 with the error at rounding level", "[modelfit]") {
    struct Case {
        std::string target;
        std::map<std::string, double> tp;
        std::string model;
        std::map<std::string, double> expect;
        double min_cos = 0.0;
    };
    const std::vector<Case> cases = {
        // Unity's k is the 1941 exponent minus 1: NoL (NoL NoV)^k = NoL^(k+1) NoV^k. For k >= 0 the saturate never clips.
        {"minnaert_unity", {{"k", 0.3}}, "minnaert_1941", {{"k", 1.3}}},
        {"minnaert_1941", {{"k", 1.6}}, "minnaert_unity", {{"k", 0.6}}},
        // Blender's d <= 1 is the 1941 law where its clamp max(NoV NoL, 0.1) is inactive: NoL, NoV >= sqrt(0.1).
        {"minnaert_blender", {{"darkness", 0.6}}, "minnaert_1941", {{"k", 0.6}}, 0.3163},
        {"minnaert_1941", {{"k", 0.45}}, "minnaert_blender", {{"darkness", 0.45}}, 0.3163},
        {"oren_nayar", {{"sigma", 0.0}}, "lambert", {}},
        {"lambert", {}, "oren_nayar", {{"sigma", 0.0}}},
        {"oren_nayar", {{"sigma", 0.4}}, "oren_nayar_st", {{"sigma", 0.4}}},
        {"oren_nayar_st", {{"sigma", 1.1}}, "oren_nayar", {{"sigma", 1.1}}},
        {"wrap", {{"wrap_value", 0.5}}, "half_lambert", {}},
        {"half_lambert", {}, "wrap", {{"wrap_value", 0.5}}},
    };
    for (const auto& c : cases) {
        const Material t = target_of(c.target, c.tp);
        const fit::FitResult r = fit_to(t, c.model, hemisphere(8192, 3, c.min_cos));
        INFO(c.target << " -> " << c.model << "\n" << fit::to_text(r));
        for (const auto& [name, v] : c.expect) CHECK(std::abs(param(r, name) - v) <= 1e-6);
        CHECK(std::abs(r.albedo - 0.8) <= 1e-6);
        CHECK(r.error.at("rel-rms") <= 1e-12);
        CHECK(r.representable);
    }
}

TEST_CASE("fit: every catalogue model fitted to itself at its defaults comes back with error 0", "[modelfit]") {
    fit::FitOptions o;
    o.limb_check = false;
    for (const auto& info : model_catalogue()) {
        const Material t = target_of(info.name);
        const fit::FitResult r = fit_to(t, info.name, hemisphere(4096, 5), o);
        INFO(fit::to_text(r));
        CHECK(r.error.at("rel-rms") <= 1e-9);
        // Where the parameters are determined (no diagnostic says otherwise) they come back too.
        if (r.well_posed)
            for (const auto& p : info.params) CHECK(std::abs(param(r, p.name) - p.def) <= 1e-6 * std::max(1.0, p.hi - p.lo));
    }
}

TEST_CASE("fit: a fit that is not exact reports the error an independent evaluation finds, and no grid point beats it",
          "[modelfit]") {
    const Material t = target_of("oren_nayar", {{"sigma", 0.4}});
    const fit::Domain d = hemisphere(16384, 11);
    const fit::FitResult r = fit_to(t, "minnaert_1941", d);
    INFO(fit::to_text(r));
    Material m;
    m.model = "minnaert_1941";
    m.albedo = glm::dvec3(0.8);
    m.params["k"] = param(r, "k");
    const double e = independent_rel_rms(d, t, resolve_material(m), r.scale);
    CHECK(r.error.at("rel-rms") > 0.05);
    CHECK(std::abs(e - r.error.at("rel-rms")) <= 1e-12 * e);
    // Brute force: k on a grid of 0.002 over [0, 2], the best scale in closed form for each.
    std::vector<double> tv(d.size());
    for (std::size_t i = 0; i < d.size(); ++i) tv[i] = ref::eval_material(d.N[i], d.L[i], d.V[i], d.P[i], t).x;
    double best = 1e300;
    for (int q = 0; q <= 1000; ++q) {
        m.params["k"] = 0.002 * q;
        double ft = 0, ff = 0, tt = 0;
        std::vector<double> fv(d.size());
        for (std::size_t i = 0; i < d.size(); ++i) {
            fv[i] = ref::eval_material(d.N[i], d.L[i], d.V[i], d.P[i], m).x;
            ft += fv[i] * tv[i], ff += fv[i] * fv[i], tt += tv[i] * tv[i];
        }
        const double a = ft / ff;
        double ssr = 0;
        for (std::size_t i = 0; i < d.size(); ++i) ssr += (a * fv[i] - tv[i]) * (a * fv[i] - tv[i]);
        best = std::min(best, std::sqrt(ssr / tt));
    }
    CHECK(r.error.at("rel-rms") <= best + 1e-12);
    // The clamp of Blender's Minnaert over the whole hemisphere: its cost measured, and recomputed.
    const Material tb = target_of("minnaert_blender", {{"darkness", 0.6}});
    const fit::FitResult rb = fit_to(tb, "minnaert_1941", d);
    m.params["k"] = param(rb, "k");
    const double eb = independent_rel_rms(d, tb, resolve_material(m), rb.scale);
    INFO(fit::to_text(rb));
    CHECK(rb.error.at("rel-rms") > 1e-3);
    CHECK(std::abs(eb - rb.error.at("rel-rms")) <= 1e-12 * eb);
}

TEST_CASE("fit: ill-posed fits are said in words, with no NaN and no exception", "[modelfit]") {
    SECTION("a parameter with no effect: ks with a black specular colour") {
        const Material t = target_of("lambert");
        fit::Problem p(test::runtime(), hemisphere(8192), t);
        fit::ModelShape s = fit::shape_for("blinn_phong", t, 0.0, nullptr);   // black specular colour
        const fit::FitResult r = fit::fit_model(p, s);
        INFO(fit::to_text(r));
        bool ks_no_effect = false;
        for (const auto& d : r.diagnostics) ks_no_effect = ks_no_effect || (d.kind == "no_effect" && d.text.rfind("ks ", 0) == 0);
        CHECK(ks_no_effect);
        CHECK_FALSE(r.well_posed);
        CHECK(r.error.at("rel-rms") <= 1e-12);   // Lambert is its diffuse part
        const std::string j = fit::to_json(r).dump();
        CHECK(j.find("NaN") == std::string::npos);
    }
    SECTION("a target the model cannot represent: toon fitted by Lambert") {
        const fit::FitResult r = fit_to(target_of("toon"), "lambert", hemisphere(8192));
        INFO(fit::to_text(r));
        CHECK_FALSE(r.representable);
        CHECK(has(r, "not_representable"));
        CHECK(std::isfinite(r.albedo));
        CHECK(r.albedo > 0.0);
        for (const auto& [k, v] : r.error) CHECK(std::isfinite(v));
    }
    SECTION("Minnaert at phase 0 (on the normal: one geometry; over the hemisphere) against all phases") {
        const Material t = target_of("oren_nayar", {{"sigma", 0.4}});
        fit::HemisphereOptions o;
        o.samples = 4096;
        o.has_phase = true;
        o.phase_deg = 0.0;
        o.at_normal = true;   // L = V = N: one geometry, where k has no effect
        const fit::FitResult r0 = fit_to(t, "minnaert_1941", fit::hemisphere_domain(o));
        INFO(fit::to_text(r0));
        CHECK_FALSE(r0.well_posed);
        CHECK(has(r0, "no_effect"));
        // Phase 0 over the hemisphere (L = V, the full-moon case): Minnaert's mu^(2k - 1) against Oren-Nayar's
        // bright limb is decided by the few grazing samples, and said so; over all phases the same fit is well posed.
        o.samples = 16384;
        o.at_normal = false;
        const fit::FitResult rp = fit_to(t, "minnaert_1941", fit::hemisphere_domain(o));
        INFO(fit::to_text(rp));
        CHECK_FALSE(rp.well_posed);
        CHECK(has(rp, "limb"));
        const fit::FitResult rall = fit_to(t, "minnaert_1941", hemisphere(16384));
        INFO(fit::to_text(rall));
        CHECK(rall.well_posed);
        const fit::FitResult ra = fit_to(target_of("minnaert_normalized", {{"k", 0.8}}), "minnaert_1941", hemisphere(8192));
        INFO(fit::to_text(ra));
        CHECK(ra.well_posed);
        CHECK(std::abs(param(ra, "k") - 0.8) <= 1e-6);
    }
}

TEST_CASE("fit: the limb check flags a fit driven by near-grazing samples, and only then", "[modelfit]") {
    // Minnaert k = 0.3: NoV^(k - 1) diverges at the limb (guarded at 1e-3), so a few grazing samples carry most of
    // the squared error of any smooth model fitted to it.
    const fit::FitResult r = fit_to(target_of("minnaert_1941", {{"k", 0.3}}), "oren_nayar", hemisphere(16384));
    INFO(fit::to_text(r));
    REQUIRE(r.limb.done);
    CHECK(r.limb.sensitive);
    CHECK(has(r, "limb"));
    CHECK(r.limb.error_share > 0.5);
    // Oren-Nayar fitted by Minnaert over the whole hemisphere is not limb-driven.
    const fit::FitResult q = fit_to(target_of("oren_nayar", {{"sigma", 0.4}}), "minnaert_1941", hemisphere(16384));
    INFO(fit::to_text(q));
    REQUIRE(q.limb.done);
    CHECK_FALSE(q.limb.sensitive);
    CHECK_FALSE(has(q, "limb"));
}

TEST_CASE("fit: no model is ever evaluated outside its parameter ranges", "[modelfit]") {
    std::size_t seen = 0;
    std::set<std::string> models;
    auto check = [&](const std::string& model, const std::vector<double>& x) {
        const ModelInfo& info = find_model(model);
        REQUIRE(x.size() == info.params.size());
        for (std::size_t j = 0; j < x.size(); ++j) {
            INFO(model << " " << info.params[j].name << " = " << x[j]);
            REQUIRE(std::isfinite(x[j]));
            REQUIRE(x[j] >= info.params[j].lo);
            REQUIRE(x[j] <= info.params[j].hi);
            if (info.params[j].integer) REQUIRE(x[j] == std::floor(x[j]));
        }
        ++seen;
        models.insert(model);
    };
    const Material t = target_of("phong", {{"n", 8.0}});
    fit::Problem p(test::runtime(), hemisphere(4096), t);
    p.set_observer(check);
    // Optima at range limits (ks, f0), wide log ranges (n), whole numbers (steps), a signed range (unity k).
    for (const char* m : {"cook_torrance", "blinn_phong", "banded", "minnaert_unity", "wrap", "oren_nayar_blender"})
        fit::fit_model(p, fit::shape_for(m, t, -1.0, nullptr));
    CHECK(seen > 100);
    CHECK(models.size() == 6);
}

TEST_CASE("fit: fitted parameters are stable to 1e-3 across seeds of the default domain", "[modelfit]") {
    const Material t = target_of("oren_nayar", {{"sigma", 0.4}});
    std::vector<double> k, a;
    for (std::uint64_t seed : {1, 2, 3}) {
        fit::HemisphereOptions o;   // the default: 65536 samples
        o.seed = seed;
        fit::FitOptions fo;
        fo.limb_check = false;
        const fit::FitResult r = fit_to(t, "minnaert_1941", fit::hemisphere_domain(o), fo);
        k.push_back(param(r, "k"));
        a.push_back(r.albedo);
    }
    for (std::size_t i = 1; i < k.size(); ++i) {
        CHECK(std::abs(k[i] - k[0]) <= 1e-3);
        CHECK(std::abs(a[i] - a[0]) <= 1e-3);
    }
}

TEST_CASE("fit: the JSON holds the contract keys, and --all writes results with speeds, the table and the chart", "[modelfit]") {
    const Material t = target_of("oren_nayar", {{"sigma", 0.4}});
    fit::Problem p(test::runtime(), hemisphere(8192), t);
    const fit::FitResult r = fit::fit_model(p, fit::shape_for("minnaert_1941", t, -1.0, nullptr));
    const nlohmann::json j = fit::to_json(r);
    CHECK(j.at("model") == "minnaert_1941");
    CHECK(j.at("target") == "oren_nayar");
    CHECK(j.at("params").is_object());
    CHECK(j.at("params").at("k").is_number());
    CHECK(j.at("albedo").is_number());
    CHECK(j.at("error").at("rel-rms").is_number());

    fit::AllOptions o;
    o.models = {"lambert", "minnaert_1941", "oren_nayar_st", "oren_nayar"};
    o.out_dir = test::scratch_dir("fit_all").string();
    o.timed_fragments = 1 << 16;
    std::ostringstream log;
    const fit::AllResult all = fit::fit_all(test::runtime(), p, o, log);
    const nlohmann::json ja = fit::to_json(all);
    REQUIRE(ja.at("results").size() == 4);
    double last = -1.0;
    std::vector<speed::ParetoPoint> pts;
    for (const auto& row : ja.at("results")) {
        CHECK(row.at("mfrag_per_s").get<double>() > 0.0);
        CHECK(row.at("params").is_object());
        const double e = row.at("error").at("rel-rms").get<double>();
        CHECK(e >= last);   // sorted by error
        last = e;
        pts.push_back({row.at("mfrag_per_s").get<double>(), e});
    }
    // The front marks: a row is on it iff no other row is at least as fast and as accurate and better in one.
    for (std::size_t i = 0; i < pts.size(); ++i) {
        bool dominated = false;
        for (std::size_t q = 0; q < pts.size(); ++q)
            dominated = dominated || (q != i && pts[q].speed >= pts[i].speed && pts[q].error <= pts[i].error &&
                                      (pts[q].speed > pts[i].speed || pts[q].error < pts[i].error));
        CHECK(ja.at("results")[i].at("pareto_front").get<bool>() == !dominated);
    }
    // oren_nayar_st is oren_nayar: error at rounding level, first or second.
    CHECK(ja.at("results")[0].at("error").at("rel-rms").get<double>() <= 1e-12);
    CHECK(std::filesystem::exists(std::filesystem::path(o.out_dir) / "fit_all.csv"));
    CHECK(std::filesystem::file_size(std::filesystem::path(o.out_dir) / "fit_all.png") > 1000);
}

namespace {
// Rows of a CSV written by CsvTable (core/csv.hpp) (no quoting: it writes no commas inside fields).
std::vector<std::map<std::string, std::string>> read_csv(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::map<std::string, std::string>> rows;
    std::string line;
    std::vector<std::string> head;
    auto split = [](const std::string& l) {
        std::vector<std::string> v;
        std::stringstream s(l);
        std::string f;
        while (std::getline(s, f, ',')) v.push_back(f);
        if (!l.empty() && l.back() == ',') v.push_back("");
        return v;
    };
    if (std::getline(in, line)) head = split(line);
    while (std::getline(in, line)) {
        const auto f = split(line);
        std::map<std::string, std::string> r;
        for (std::size_t i = 0; i < head.size() && i < f.size(); ++i) r[head[i]] = f[i];
        rows.push_back(r);
    }
    return rows;
}
}  // namespace

TEST_CASE("fit: the fidelity atlas in the docs matches what the fit computes today", "[modelfit]") {
    const std::string dir = test::kSourceDir + "/docs/data/fidelity/";
    // The exact maps between Minnaert parameterisations, recovered to 1e-6 where they are exact.
    const auto maps = read_csv(dir + "minnaert_maps.csv");
    REQUIRE(maps.size() >= 5);
    int exact = 0;
    for (const auto& r : maps) {
        const bool clipped = r.at("target") == "minnaert_unity" && std::stod(r.at("target_value")) < 0.0;
        const bool clamped = r.at("target") == "minnaert_blender" && r.at("domain") == "hemisphere";
        if (clipped || clamped) {
            CHECK(std::stod(r.at("rel_rms")) > 1e-3);   // where the map is not exact the atlas shows its cost
            continue;
        }
        INFO(r.at("target") << " -> " << r.at("model"));
        CHECK(std::stod(r.at("abs_difference")) <= 1e-6);
        CHECK(std::stod(r.at("rel_rms")) <= 1e-12);
        ++exact;
    }
    CHECK(exact >= 5);
    // One row of the Minnaert-against-Oren-Nayar table refitted now, on the atlas's domain (65536 samples, seed 1).
    const auto rows = read_csv(dir + "minnaert_vs_oren_nayar.csv");
    bool found = false;
    for (const auto& r : rows) {
        if (r.at("model") != "minnaert_1941" || std::abs(std::stod(r.at("sigma")) - 0.4) > 1e-9) continue;
        found = true;
        fit::FitOptions o;
        o.limb_check = false;
        const fit::FitResult f = fit_to(target_of("oren_nayar", {{"sigma", 0.4}}), "minnaert_1941", hemisphere(65536, 1), o);
        CHECK(std::abs(param(f, "k") - std::stod(r.at("value"))) <= 1e-5);
        CHECK(std::abs(f.error.at("rel-rms") - std::stod(r.at("rel_rms"))) <= 1e-5);
    }
    CHECK(found);
}

TEST_CASE("fit over a scene: the rendered colours of its fragments, recomputed with the reference's own light sum",
          "[modelfit]") {
    const std::string file = test::kScenes + "/lights.json";   // a directional and two point lights, ambient
    const Scene scene = load_scene(file);
    const fit::Domain d = fit::scene_domain(file, 3);
    REQUIRE(d.grouped());
    REQUIRE(d.per_group == scene.lights.size());
    const Material t = target_of("oren_nayar", {{"sigma", 0.5}});
    fit::Problem p(test::runtime(), d, t);
    const fit::FitResult r = fit::fit_model(p, fit::shape_for("minnaert_1941", t, -1.0, nullptr));
    INFO(fit::to_text(r));
    for (const char* m : {"rel-rms", "de2000-mean", "de2000-p99", "de2000-max"}) {
        REQUIRE(r.error.count(m));
        CHECK(std::isfinite(r.error.at(m)));
    }
    CHECK(r.error.at("de2000-mean") > 0.0);
    CHECK(r.error.at("de2000-p99") >= r.error.at("de2000-mean"));
    CHECK(r.error.at("de2000-max") >= r.error.at("de2000-p99"));
    // ref::shade_point sums the lights (with its own attenuation) and the ambient term for each fragment.
    Material fm;
    fm.model = "minnaert_1941";
    fm.albedo = glm::dvec3(r.albedo);
    fm.params["k"] = param(r, "k");
    fm = resolve_material(fm);
    double num = 0.0, den = 0.0;
    for (std::size_t i = 0; i < d.size(); i += d.per_group) {
        const glm::dvec3 a = ref::shade_point(d.P[i], d.N[i], d.V[i], t, scene.lights, scene.ambient);
        const glm::dvec3 b = ref::shade_point(d.P[i], d.N[i], d.V[i], fm, scene.lights, scene.ambient);
        for (int c = 0; c < 3; ++c) num += (b[c] - a[c]) * (b[c] - a[c]), den += a[c] * a[c];
    }
    CHECK(std::abs(std::sqrt(num / den) - r.error.at("rel-rms")) <= 1e-9);
    // Oren-Nayar's trig-free form is the same function on the scene too.
    const fit::FitResult same = fit::fit_model(p, fit::shape_for("oren_nayar_st", t, -1.0, nullptr));
    CHECK(std::abs(param(same, "sigma") - 0.5) <= 1e-6);
    CHECK(same.error.at("de2000-max") <= 1e-6);
}

TEST_CASE("fit over a disc image: the model a disc was rendered with comes back from its pixels", "[modelfit]") {
    moon::DiscRenderOptions r;
    r.width = r.height = 160;
    r.disc = moon::Disc{80.0, 80.0, 72.0};   // what disc_image_domain assumes by default: centred, 0.45 of the side
    Material m;
    m.model = "oren_nayar";
    m.params["sigma"] = 0.5;
    m.albedo = glm::dvec3(0.3);
    r.material = resolve_material(m);
    r.sun = moon::sun_geometry(40.0, 250.0);
    const std::string path = (test::scratch_dir("fit_disc") / "disc.exr").string();
    write_image(path, moon::render_disc(test::runtime(), r));
    fit::DiscImageOptions o;
    o.image = path;
    o.phase_deg = 40.0;
    o.pa_deg = 250.0;
    std::vector<double> values;
    fit::Domain d = fit::disc_image_domain(o, values);
    REQUIRE(d.size() == values.size());
    fit::Problem p(test::runtime(), std::move(d), std::move(values), path);
    const fit::FitResult f = fit::fit_model(p, fit::shape_for("oren_nayar_st", p.target_material(), -1.0, nullptr));
    INFO(fit::to_text(f));
    CHECK(f.target == path);
    // The image holds float kernel values: the fit comes back to float rounding.
    CHECK(std::abs(param(f, "sigma") - 0.5) <= 1e-5);
    CHECK(std::abs(f.albedo - 0.3) <= 1e-5);
    CHECK(f.error.at("rel-rms") <= 1e-6);
    // A different law leaves a measured, finite error and its best k.
    const fit::FitResult g = fit::fit_model(p, fit::shape_for("minnaert_1941", p.target_material(), -1.0, nullptr));
    CHECK(g.error.at("rel-rms") > 0.01);
    CHECK(std::isfinite(param(g, "k")));
}

TEST_CASE("fit over a batch render with normal and depth AOVs: the model it was rendered with comes back",
          "[modelfit]") {
    // Model A (oren_nayar sigma 0.5, grey albedo 0.8) rendered by the batch with a directional and a point light
    // and ambient, colour EXR plus the normal and depth AOVs.
    const std::filesystem::path dir = test::scratch_dir("fit_aov");
    const std::string scene_file = (dir / "aov.json").string();
    std::ofstream(scene_file)
        << "{ \"name\": \"aov\", \"camera\": { \"view_from\": [0.4, 0.3, 1] }, \"resolution\": [96, 72], "
        << "\"meshes\": [ { \"path\": \"" << test::kMeshes << "/spot.obj\", \"material\": { \"model\": \"oren_nayar\", "
        << "\"params\": { \"sigma\": 0.5 }, \"albedo\": [0.8, 0.8, 0.8] } } ], "
        << "\"lights\": [ { \"type\": \"directional\", \"direction\": [1, 1.2, 1], \"intensity\": 0.8 }, "
        << "{ \"type\": \"point\", \"position\": [-2, 1.5, 2], \"colour\": [0.4, 0.6, 1.0], \"intensity\": 6 } ], "
        << "\"ambient\": [0.02, 0.02, 0.025], "
        << "\"outputs\": { \"exr\": \"{name}.exr\", \"normal\": \"{name}_normal.exr\", \"depth\": \"{name}_depth.exr\" } }\n";
    REQUIRE(render_with_batch(scene_file, (dir / "out").string()));
    const std::string image = (dir / "out" / "aov.exr").string();
    std::vector<double> values;
    fit::Domain d = fit::aov_image_domain({image, scene_file, "", ""}, values);   // AOVs: the scene's outputs
    REQUIRE(d.grouped());
    REQUIRE(d.per_group == 2);
    REQUIRE(values.size() == d.outputs());

    // The geometry the AOVs give is the rasteriser's own: every fragment's P and N, recomputed here by
    // rasterising the scene, against the domain's (same pixel order: row-major).
    const Scene scene = load_scene(scene_file, SceneLoadOptions{(dir / "out").string(), ""});
    const SceneGeometry g = load_scene_geometry(scene, [](const std::string& p) { return load_mesh(p); });
    RasterOptions ro;
    ro.width = scene.width;
    ro.height = scene.height;
    const FragmentBuffer fb = rasterize(g.meshes[0], g.camera, ro);
    REQUIRE(fb.size() * 2 == d.size());
    double p_err = 0.0, n_err = 0.0;
    for (std::size_t i = 0; i < fb.size(); ++i) {
        p_err = std::max(p_err, glm::length(glm::dvec3(fb.px[i], fb.py[i], fb.pz[i]) - d.P[2 * i]));
        n_err = std::max(n_err, glm::length(glm::dvec3(fb.nx[i], fb.ny[i], fb.nz[i]) - d.N[2 * i]));
    }
    INFO("max |P_aov - P_raster| " << p_err << ", max |N_aov - N_raster| " << n_err);
    CHECK(p_err <= 1e-4 * glm::length(g.camera.eye - g.camera.target));
    CHECK(n_err <= 1e-6);

    fit::Problem p(test::runtime(), std::move(d), std::move(values), image);
    const Material start = target_of("lambert");   // the fitted model's albedo before its scale: 0.8
    // Model A back: sigma and the albedo to float rounding of the pixels.
    const fit::FitResult a = fit::fit_model(p, fit::shape_for("oren_nayar", start, -1.0, nullptr));
    INFO(fit::to_text(a));
    CHECK(std::abs(param(a, "sigma") - 0.5) <= 1e-4);
    CHECK(std::abs(a.albedo - 0.8) <= 1e-4);
    CHECK(a.error.at("rel-rms") <= 1e-5);
    CHECK(a.error.at("de2000-max") <= 1e-3);

    // Model B (minnaert_1941): a non-zero error, the one an independent recomputation finds: the references'
    // own light sum (ref::shade_point) at the rasterised fragments, against the EXR's pixels.
    const fit::FitResult b = fit::fit_model(p, fit::shape_for("minnaert_1941", start, -1.0, nullptr));
    INFO(fit::to_text(b));
    REQUIRE(std::isfinite(b.error.at("rel-rms")));
    CHECK(b.error.at("rel-rms") > 1e-3);
    Material fm;
    fm.model = "minnaert_1941";
    fm.albedo = glm::dvec3(b.albedo);
    fm.params["k"] = param(b, "k");
    fm = resolve_material(fm);
    const Image colour = read_image(image);
    double num = 0.0, den = 0.0;
    for (std::size_t i = 0; i < fb.size(); ++i) {
        const glm::dvec3 P(fb.px[i], fb.py[i], fb.pz[i]), N(fb.nx[i], fb.ny[i], fb.nz[i]);
        const glm::dvec3 f = ref::shade_point(P, N, glm::normalize(g.camera.eye - P), fm, scene.lights, scene.ambient);
        const int px = fb.pixel[i] % colour.width, py = fb.pixel[i] / colour.width;
        for (int c = 0; c < 3; ++c) {
            const double t = colour.at(px, py, c);
            num += (f[c] - t) * (f[c] - t);
            den += t * t;
        }
    }
    const double independent = std::sqrt(num / den);
    INFO("independent rel-rms " << independent);
    CHECK(std::abs(independent - b.error.at("rel-rms")) <= 1e-3 * b.error.at("rel-rms"));
}

TEST_CASE("fit over a batch render: an image without the AOVs it needs is refused in one line", "[modelfit]") {
    const std::filesystem::path dir = test::scratch_dir("fit_aov_bad");
    const std::string scene_file = (dir / "s.json").string();
    std::ofstream(scene_file)
        << "{ \"name\": \"s\", \"resolution\": [32, 24], \"meshes\": [ { \"path\": \"" << test::kMeshes
        << "/spot.obj\" } ], \"lights\": [ { \"type\": \"directional\", \"direction\": [1, 1, 1] } ], "
        << "\"outputs\": { \"exr\": \"{name}.exr\", \"normal\": \"{name}_normal.exr\", \"depth\": \"{name}_depth.exr\" } }\n";
    REQUIRE(render_with_batch(scene_file, (dir / "out").string()));
    const std::string out = (dir / "out").string();
    std::vector<double> v;
    auto message = [&](const fit::AovImageOptions& o) {
        try {
            fit::aov_image_domain(o, v);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("(no error)");
    };
    using Catch::Matchers::Contains;
    // The AOVs missing: named, with what to do.
    std::filesystem::remove(out + "/s_normal.exr");
    const std::string missing = message({out + "/s.exr", scene_file, "", ""});
    CHECK_THAT(missing, Contains("normal AOV") && Contains("s_normal.exr") && Contains("--normal"));
    // The colour image given as the normal AOV: not unit normals; as the depth AOV: four channels.
    CHECK_THAT(message({out + "/s.exr", scene_file, out + "/s.exr", ""}), Contains("not a normal AOV"));
    CHECK_THAT(message({out + "/s.exr", scene_file, out + "/s.exr", out + "/s.exr"}), Contains("not a depth AOV"));
    CHECK_THAT(message({out + "/s.exr", scene_file, "", out + "/s.exr"}), Contains("normal AOV"));
    // A scene that writes no depth AOV, and no --depth.
    const std::string no_depth = (dir / "nodepth.json").string();
    std::ofstream(no_depth) << "{ \"name\": \"s\", \"resolution\": [32, 24], \"meshes\": [ { \"path\": \"" << test::kMeshes
                            << "/spot.obj\" } ], \"lights\": [ { \"type\": \"directional\", \"direction\": [1, 1, 1] } ], "
                            << "\"outputs\": { \"exr\": \"{name}.exr\" } }\n";
    CHECK_THAT(message({out + "/s.exr", no_depth, out + "/s.exr", ""}), Contains("no depth AOV") && Contains("--depth"));
    CHECK(missing.find('\n') == std::string::npos);
}

TEST_CASE("fit evaluator: a material asked for again is not evaluated again, and gets the same values", "[modelfit]") {
    fit::Evaluator ev(test::runtime(), hemisphere(4096));
    const Material a = target_of("oren_nayar", {{"sigma", 0.3}}), b = target_of("oren_nayar", {{"sigma", 0.31}});
    const std::vector<double> va = ev.reference(a);
    const std::size_t one = ev.reference_evaluations();
    REQUIRE(one == 4096);
    const std::vector<double> vb = ev.reference(b);
    CHECK(ev.reference_evaluations() == 2 * one);
    CHECK(vb != va);
    CHECK(ev.reference(a) == va);   // kept: no evaluation
    CHECK(ev.reference_evaluations() == 2 * one);
    Material c = a;                 // another albedo is another material
    c.albedo = glm::dvec3(0.5);
    const std::vector<double> vc = ev.reference(c);
    CHECK(ev.reference_evaluations() == 3 * one);
    double sa = 0.0, sc = 0.0;     // oren_nayar (the qualitative model) is linear in its albedo
    for (std::size_t i = 0; i < 4096; ++i) sa += va[i], sc += vc[i];
    REQUIRE(sa > 0.0);
    CHECK(std::abs(sc / sa - 0.5 / 0.8) <= 1e-12);
}
