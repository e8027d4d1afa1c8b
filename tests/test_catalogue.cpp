// One harness over the whole catalogue (pbrt's habit: one generic test called per configuration).
// It checks what every model must satisfy, whichever family wrote it; the family test files go deeper.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <regex>
#include <set>

#include "cl/runtime.hpp"
#include "models/catalogue.hpp"
#include "reference/reference.hpp"
#include "shade/shader.hpp"
#include "support.hpp"

using namespace shadelab;

namespace {
Material default_material(const ModelInfo& info, double albedo = 1.0) {
    Material m;
    m.model = info.name;
    m.albedo = glm::dvec3(albedo);
    m.specular = glm::dvec3(albedo);
    for (int c = 0; c < info.children; ++c) {
        Material child;
        child.albedo = glm::dvec3(0.3 + 0.4 * c);
        m.children.push_back(child);
    }
    return resolve_material(m);
}

// The directional albedo from the reference: the white furnace of tests/support.hpp on its (cos theta, phi) grid,
// steps x 2 steps midpoints over the whole hemisphere.
double directional_albedo(const Material& m, const glm::dvec3& V, int steps) {
    test::Furnace f;
    f.n_theta = steps;
    f.n_phi = 2 * steps;
    return test::furnace_reference(m, V, f);
}
}  // namespace

TEST_CASE("every model in the catalogue has a reference, a summary and a source", "[catalogue]") {
    const auto& all = model_catalogue();
    REQUIRE(!all.empty());
    for (const auto& m : all) {
        INFO("model " << m.name);
        CHECK_NOTHROW(ref::reference_for(m.name));
        CHECK(!m.summary.empty());
        CHECK(!m.source.empty());
        CHECK(!m.header.empty());
        for (const auto& p : m.params) {
            INFO("param " << p.name);
            CHECK(p.lo <= p.def);
            CHECK(p.def <= p.hi);
        }
    }
    for (const auto& name : ref::models_with_reference()) {
        INFO("reference without a model: " << name);
        CHECK_NOTHROW(find_model(name));
    }
}

// The catalogue-wide check is deliberately coarse: it catches a model whose kernel and reference disagree
// in substance. Near NoL = 0, NoV = 0 or L = -V the float rounding of the inputs (~6e-8) is amplified by
// pow/tan/division and by band thresholds, so the family tests own the tight, conditioning-aware bounds;
// here those triples are only required to be finite.
TEST_CASE("every model's kernel is finite and close to its reference at default parameters", "[catalogue][kernel]") {
    const auto sweep = test::make_sweep(20000, 777);
    Shader shader(test::runtime());
    std::cout << std::left << std::setw(28) << "model"
              << " max abs err (conditioned) / peak, share over 1e-4 of peak  (default parameters, 20k triples)\n";
    for (const auto& info : model_catalogue()) {
        const Material m = default_material(info, 0.75);
        const auto out = shader.eval_directions(m, sweep.N, sweep.L, sweep.V, sweep.P);
        double peak = 0.0, max_abs = 0.0;
        std::size_t non_finite = 0, conditioned = 0, over = 0, worst = 0;
        std::vector<glm::dvec3> ref(sweep.size());
        for (std::size_t i = 0; i < sweep.size(); ++i) {
            ref[i] = ref::eval_material(sweep.dN[i], sweep.dL[i], sweep.dV[i], sweep.dP[i], m);
            peak = std::max({peak, std::abs(ref[i].x), std::abs(ref[i].y), std::abs(ref[i].z)});
        }
        for (std::size_t i = 0; i < sweep.size(); ++i) {
            for (int c = 0; c < 3; ++c) non_finite += std::isfinite(out[3 * i + std::size_t(c)]) ? 0 : 1;
            const double NoL = glm::dot(sweep.dN[i], sweep.dL[i]), NoV = glm::dot(sweep.dN[i], sweep.dV[i]);
            const double LoV = glm::dot(sweep.dL[i], sweep.dV[i]);
            if (std::abs(NoL) < 1e-3 || std::abs(NoV) < 1e-3 || LoV < -1.0 + 1e-3) continue;
            ++conditioned;
            double e = 0.0;
            for (int c = 0; c < 3; ++c) e = std::max(e, std::abs(out[3 * i + std::size_t(c)] - ref[i][c]));
            if (e > max_abs) { max_abs = e; worst = i; }
            over += e > 1e-4 * std::max(peak, 1e-6) ? 1 : 0;
        }
        const double share = double(over) / double(std::max<std::size_t>(conditioned, 1));
        std::cout << std::setw(28) << info.name << " " << max_abs / std::max(peak, 1e-12) << "  " << share << "\n";
        INFO("model " << info.name << ": worst conditioned triple " << worst << " (" << sweep.kind[worst]
                      << "), error " << max_abs << ", peak " << peak);
        CHECK(non_finite == 0);
        CHECK(conditioned > sweep.size() / 2);
        // Discontinuous models (bands, toon thresholds) may land one band off on a few inputs lying within
        // float rounding of a threshold; anything beyond 0.1% of triples is a real disagreement.
        CHECK(share <= 1e-3);
    }
}

TEST_CASE("every model returns finite values for invalid input (NaN normal, zero vectors)", "[catalogue][stability]") {
    Shader shader(test::runtime());
    const float nan = std::nanf("");
    // N = NaN; L = 0; V = 0; N = 0; everything 0; N = inf.
    const std::vector<float> N = {nan, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, INFINITY, 0, 0};
    const std::vector<float> L = {0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 1};
    const std::vector<float> V = {0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1};
    const std::vector<float> P(N.size(), 0.0f);
    for (const auto& info : model_catalogue()) {
        const auto out = shader.eval_directions(default_material(info), N, L, V, P);
        for (std::size_t i = 0; i < out.size(); ++i) {
            INFO("model " << info.name << " case " << i / 3);
            CHECK(std::isfinite(out[i]));
        }
    }
}

// Parameter sets to probe a model's properties: defaults, then each parameter at each end of its range.
std::vector<Material> probe_materials(const ModelInfo& info) {
    std::vector<Material> out{default_material(info)};
    for (const auto& p : info.params)
        for (double v : {p.lo, p.hi}) {
            Material m = default_material(info);
            m.params[p.name] = v;
            out.push_back(resolve_material(m));
        }
    return out;
}

double max_reciprocity_asymmetry(const Material& m) {
    std::mt19937_64 g(99);
    const glm::dvec3 N{0, 0, 1}, P{0.3, -0.2, 0.1};
    double worst = 0.0;
    for (int i = 0; i < 2000; ++i) {
        const glm::dvec3 L = test::random_above(g), V = test::random_above(g);
        const double a = ref::eval_material(N, L, V, P, m).y / L.z;   // f_r(L, V) up to pi
        const double b = ref::eval_material(N, V, L, P, m).y / V.z;   // f_r(V, L)
        worst = std::max(worst, std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-12}));
    }
    return worst;
}

TEST_CASE("reciprocity holds for the models flagged reciprocal over their whole range, and fails for the others",
          "[catalogue][physics]") {
    for (const auto& info : model_catalogue()) {
        if (info.children) continue;   // blends inherit their children's property
        double worst = 0.0;
        for (const Material& m : probe_materials(info)) worst = std::max(worst, max_reciprocity_asymmetry(m));
        std::cout << "reciprocity " << std::setw(28) << info.name << " max rel asymmetry " << worst
                  << (info.reciprocal ? "  (flagged reciprocal)\n" : "  (flagged not reciprocal)\n");
        INFO("model " << info.name << " max relative asymmetry over defaults and range ends " << worst);
        if (info.reciprocal)
            CHECK(worst < 1e-9);
        else
            CHECK(worst > 1e-6);
    }
}

TEST_CASE("models flagged energy-conserving have directional albedo <= 1 (white furnace)", "[catalogue][physics]") {
    std::cout << "white furnace, default parameters, albedo 1: directional albedo at view angle 0/30/60/85 deg\n";
    for (const auto& info : model_catalogue()) {
        if (info.children) continue;
        const Material m = default_material(info);
        std::cout << "  " << std::setw(28) << info.name;
        for (double deg : {0.0, 30.0, 60.0, 85.0}) {
            const double t = deg * M_PI / 180.0;
            const double a = directional_albedo(m, {std::sin(t), 0.0, std::cos(t)}, 256);
            std::cout << " " << std::setw(9) << a;
            INFO("model " << info.name << " view " << deg << " deg: directional albedo " << a);
            CHECK(std::isfinite(a));
            if (info.energy_conserving) CHECK(a <= 1.0 + 5e-3);   // 5e-3: midpoint-rule error at 256^2
        }
        // A model flagged energy-conserving must be so over its whole range, not only at the defaults.
        if (info.energy_conserving)
            for (const Material& p : probe_materials(info))
                for (double deg : {0.0, 60.0, 85.0}) {
                    const double t = deg * M_PI / 180.0;
                    const double a = directional_albedo(p, {std::sin(t), 0.0, std::cos(t)}, 192);
                    INFO("model " << info.name << " probe parameters, view " << deg << " deg: albedo " << a);
                    CHECK(a <= 1.0 + 1e-2);
                }
        std::cout << (info.energy_conserving ? "  (flagged energy-conserving)\n" : "\n");
    }
}

// docs/models/README.md's table of families against the registrations (ModelFamily: title, doc, models): every
// family has its row, naming exactly its models in catalogue order and linking its page; no row names a model
// the catalogue does not have. The index is written by hand and kept true by this test.
TEST_CASE("the docs index lists every registered family with its models and its page", "[catalogue][docs]") {
    namespace fs = std::filesystem;
    const fs::path index = fs::path(test::kSourceDir) / "docs" / "models" / "README.md";
    std::ifstream in(index);
    REQUIRE(in);
    struct Row { std::vector<std::string> models; std::string page; };
    std::map<std::string, Row> rows;   // by title
    const std::regex row_re(R"(^\| ([^|]+?) \| ([^|]+?) \| ([^|]+?) \|$)"), name_re("`([a-z0-9_]+)`"),
        link_re(R"(\]\(([^)]+)\))");
    for (std::string line; std::getline(in, line);) {
        std::smatch m;
        if (!std::regex_match(line, m, row_re) || m[1] == "family" || m[1].str().find("---") == 0) continue;
        Row r;
        const std::string cell = m[2];
        for (auto it = std::sregex_iterator(cell.begin(), cell.end(), name_re); it != std::sregex_iterator(); ++it)
            r.models.push_back((*it)[1]);
        std::smatch link;
        const std::string page = m[3];
        r.page = std::regex_search(page, link, link_re) ? link[1].str() : page;
        rows[m[1]] = r;
    }
    std::set<std::string> listed;
    for (const ModelFamily& f : model_families()) {
        INFO("family " << f.name << " (title '" << f.title << "', page " << f.doc << ")");
        REQUIRE(rows.count(f.title) == 1);
        const Row& r = rows.at(f.title);
        std::vector<std::string> names;
        for (const auto& m : f.models) names.push_back(m.name);
        CHECK(r.models == names);
        CHECK(fs::exists(fs::path(test::kSourceDir) / f.doc));
        // The page as linked from docs/models/: the index itself says "this page" for its own section.
        const std::string rel = fs::path(f.doc).lexically_relative("docs/models").generic_string();
        if (rel == "README.md") CHECK(r.page.find("this page") != std::string::npos);
        else CHECK(r.page == rel);
    }
    for (const auto& [title, r] : rows)
        for (const auto& name : r.models) {
            INFO("row '" << title << "' names '" << name << "'");
            CHECK_NOTHROW(find_model(name));
        }
}
