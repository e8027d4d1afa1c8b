#include "fit/atlas.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <map>
#include <ostream>
#include <sstream>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "fit/all.hpp"
#include "fit/fit.hpp"
#include "fit/report.hpp"
#include "core/csv.hpp"
#include "plot/gnuplot.hpp"
#include "reference/reference.hpp"

namespace fs = std::filesystem;

namespace shadelab::fit {

namespace {

constexpr double kPi = 3.14159265358979323846;

// An error for a table: rounding-level values shown as such.
std::string err(double e) { return e < 1e-12 ? "< 1e-12" : num(e, 3); }

Material target_of(const std::string& model, std::map<std::string, double> params) {
    Material m;
    m.model = model;
    m.params = std::move(params);
    m.albedo = glm::dvec3(0.8);
    m.specular = glm::dvec3(1.0);
    add_demo_children(m, find_model(model));
    for (auto& c : m.children) c.albedo = glm::dvec3(1.0);
    return resolve_material(m, "atlas");
}

double param(const FitResult& r, const std::string& name) {
    for (const auto& p : r.params)
        if (p.name == name) return p.value;
    throw Error("internal: atlas asked for parameter '" + name + "' of " + r.model);
}

std::string flags(const FitResult& r) {
    std::string s;
    for (const auto& d : r.diagnostics) {
        if (d.kind == "not_representable") continue;
        if (d.kind == "at_limit" && !d.ill_posed) continue;
        const std::string w = d.kind == "at_limit" ? "at limit" : d.kind == "no_effect" ? "no effect"
                              : d.kind == "trade_off" ? "trade-off" : d.kind == "limb" ? "limb-driven" : d.kind;
        if (s.find(w) == std::string::npos) s += (s.empty() ? "" : ", ") + w;
    }
    return s.empty() ? "" : s;
}

class Atlas {
public:
    Atlas(Runtime& rt, const AtlasOptions& o, std::ostream& log) : rt_(rt), o_(o), log_(log) {
        data_ = fs::path(o.docs_dir) / "data" / "fidelity";
        images_ = fs::path(o.docs_dir) / "images" / "fidelity";
        fs::create_directories(data_);
        fs::create_directories(images_);
    }

    Problem& problem(const Material& t, bool at_normal = false) {
        std::ostringstream key;
        key.precision(17);
        key << t.model << at_normal;
        for (const auto& [k, v] : t.params) key << ',' << k << '=' << v;
        auto it = problems_.find(key.str());
        if (it != problems_.end()) return *it->second;
        HemisphereOptions h;
        h.samples = o_.samples;
        h.seed = o_.seed;
        h.at_normal = at_normal;
        auto p = std::make_unique<Problem>(rt_, hemisphere_domain(h), t);
        return *problems_.emplace(key.str(), std::move(p)).first->second;
    }

    FitResult fit(const Material& t, const std::string& model, bool at_normal = false,
                  const std::map<std::string, double>& fixed_params = {}) {
        Problem& p = problem(t, at_normal);
        FitResult r = fit_model(p, shape_for(model, t, -1.0, nullptr), fixed_params);
        ++fits_;
        return r;
    }

    // Every model's speed at its defaults, measured up front in two rounds (each keeps its best), so a burst of
    // load from other processes during one model's turn does not decide its ratio.
    void measure_speeds() {
        for (int round = 0; round < 2; ++round)
            for (const auto& m : model_catalogue()) {
                const double s = measure_mfrag_per_s(rt_, target_of(m.name, {}), o_.timed_fragments, 3);
                speed_[m.name] = std::max(speed_[m.name], s);
            }
    }
    double speed(const std::string& model) {
        auto it = speed_.find(model);
        if (it == speed_.end()) throw Error("internal: atlas has no speed for '" + model + "'");
        return it->second;
    }

    std::string csv_path(const std::string& name) { return (data_ / (name + ".csv")).string(); }
    std::string png_path(const std::string& name) { return (images_ / (name + ".png")).string(); }
    void wrote(const std::string& f) { files_.push_back(f); }

    // Residual plots: the incidence plane (theta_i against signed theta_r: V across the normal from L for
    // theta_r > 0, dphi = 180 deg; on L's side for theta_r < 0, dphi = 0) and a lit sphere seen from +z with the light at 60 deg phase, as relative residuals
    // (fit - target) / max target.
    void residual_plot(const std::string& name, const Material& target, const FitResult& r) {
        Material fm;
        fm.model = r.model;
        fm.albedo = glm::dvec3(r.albedo);
        fm.specular = target.specular;
        for (const auto& p : r.params) fm.params[p.name] = p.value;
        add_demo_children(fm, find_model(r.model));
        for (auto& c : fm.children) c.albedo = glm::dvec3(1.0);
        fm = resolve_material(fm, "atlas");
        const std::string csv_plane = csv_path(name + "_plane"), csv_sphere = csv_path(name + "_sphere");
        CsvTable plane({"theta_i", "theta_r", "target", "fit", "residual"});
        const glm::dvec3 N(0, 0, 1);
        std::vector<double> pt, pf;
        double tmax = 0.0;
        const int G = 46;   // 2 deg steps
        for (int a = 0; a < G; ++a)
            for (int b = 0; b < 2 * G - 1; ++b) {
                const double ti = 89.5 * a / (G - 1), tr = -89.5 + 179.0 * b / (2 * G - 2);
                const double ri = ti * kPi / 180.0, rr = tr * kPi / 180.0;
                const glm::dvec3 L(std::sin(ri), 0.0, std::cos(ri)), V(-std::sin(rr), 0.0, std::cos(rr));
                const double t = ref::eval_material(N, L, V, glm::dvec3(0.0), target).x;
                const double f = ref::eval_material(N, L, V, glm::dvec3(0.0), fm).x;
                pt.push_back(t);
                pf.push_back(f);
                tmax = std::max(tmax, std::abs(t));
            }
        for (int a = 0, q = 0; a < G; ++a)
            for (int b = 0; b < 2 * G - 1; ++b, ++q) {
                const double ti = 89.5 * a / (G - 1), tr = -89.5 + 179.0 * b / (2 * G - 2);
                plane.row().add(ti, 5).add(tr, 5).add(pt[q], 6).add(pf[q], 6).add((pf[q] - pt[q]) / tmax, 5);
            }
        plane.write(csv_plane);
        wrote(csv_plane);
        CsvTable sphere({"x", "y", "target", "fit", "residual"});
        const glm::dvec3 V(0, 0, 1), L = glm::normalize(glm::dvec3(std::sin(60 * kPi / 180), 0.0, std::cos(60 * kPi / 180)));
        const int S = 61;
        std::vector<std::array<double, 4>> cells;
        double smax = 0.0;
        for (int y = 0; y < S; ++y)
            for (int x = 0; x < S; ++x) {
                const double X = -1.0 + 2.0 * (x + 0.5) / S, Y = -1.0 + 2.0 * (y + 0.5) / S;
                if (X * X + Y * Y >= 1.0) continue;
                const glm::dvec3 Ns(X, Y, std::sqrt(1.0 - X * X - Y * Y));
                const double t = glm::dot(Ns, L) > 0 ? ref::eval_material(Ns, L, V, glm::dvec3(0.0), target).x : 0.0;
                const double f = glm::dot(Ns, L) > 0 ? ref::eval_material(Ns, L, V, glm::dvec3(0.0), fm).x : 0.0;
                cells.push_back({X, Y, t, f});
                smax = std::max(smax, std::abs(t));
            }
        for (const auto& c : cells) sphere.row().add(c[0], 5).add(c[1], 5).add(c[2], 6).add(c[3], 6).add((c[3] - c[2]) / smax, 5);
        sphere.write(csv_sphere);
        wrote(csv_sphere);
        const std::string png = png_path(name);
        std::ostringstream s;
        s << plot::gnuplot_preamble(png, 1500, 560, 11)
          << "set multiplot layout 1,2 title \"" << r.model << " (" << fit_params(r) << ") fitted to "
          << describe_target(r) << ": residual (fit - target) / max target\" noenhanced font 'sans,13'\n"
          << "set palette defined (-1 '#2040c0', 0 '#ffffff', 1 '#c02020')\n";
        double pm = 0.0;
        for (std::size_t q = 0; q < pt.size(); ++q) pm = std::max(pm, std::abs(pf[q] - pt[q]) / tmax);
        double sm = 0.0;
        for (const auto& c : cells) sm = std::max(sm, std::abs(c[3] - c[2]) / smax);
        pm = std::max(pm, 1e-12);
        sm = std::max(sm, 1e-12);
        s << "set title 'incidence plane: L at theta_i; V at theta_r, > 0 across the normal (dphi = 180 deg), < 0 on the light''s side (dphi = 0)' noenhanced\n"
          << "set xlabel 'theta_r (deg)' noenhanced\nset ylabel 'theta_i (deg)' noenhanced\n"
          << "set xrange [-90:90]\nset yrange [0:90]\nset cbrange [" << plot::gp_number(-pm) << ":" << plot::gp_number(pm) << "]\n"
          << "plot " << plot::gp_string(csv_plane) << " using 'theta_r':'theta_i':'residual' with image notitle\n";
        s << "set title 'lit sphere seen along +z, light at 60 deg phase (to the right)'\n"
          << "set xlabel 'x'\nset ylabel 'y'\nset size ratio -1\nset xrange [-1:1]\nset yrange [-1:1]\n"
          << "set cbrange [" << plot::gp_number(-sm) << ":" << plot::gp_number(sm) << "]\n"
          << "plot " << plot::gp_string(csv_sphere) << " using 'x':'y':(" << 1.0 / S << "):(" << 1.0 / S
          << "):'residual' with boxxy fs solid 1.0 noborder lc palette notitle\n"
          << "unset multiplot\n";
        plot::run_gnuplot(s.str(), png, "the CSVs " + csv_plane + " and " + csv_sphere + " were written");
        wrote(png);
    }

    static std::string fit_params(const FitResult& r) {
        std::string s;
        for (const auto& p : r.params) s += (s.empty() ? "" : ", ") + p.name + " = " + num(p.value, 4);
        return s.empty() ? "albedo only" : s;
    }

    std::vector<std::string>& files() { return files_; }
    std::size_t fits() const { return fits_; }
    std::ostream& log() { return log_; }

private:
    Runtime& rt_;
    AtlasOptions o_;
    std::ostream& log_;
    fs::path data_, images_;
    std::map<std::string, std::unique_ptr<Problem>> problems_;
    std::map<std::string, double> speed_;
    std::vector<std::string> files_;
    std::size_t fits_ = 0;
};

}  // namespace

std::vector<std::string> write_atlas(Runtime& rt, const AtlasOptions& o, std::ostream& log) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    plot::find_gnuplot();
    Atlas A(rt, o, log);
    log << "atlas: timing every model\n";
    A.measure_speeds();
    std::ostringstream md;
    md << "# Model fidelity: which model looks like which, and at what price\n\n"
       << "This page is generated by `shadelab fit --atlas docs` (host/fit/atlas.cpp) and checked by tests/test_fit.cpp; "
          "edit the generator, not the page.\n\n"
       << "## shadelab fit\n\n"
       << "```sh\n"
       << "shadelab fit --target oren_nayar -p sigma=0.4 --model minnaert_1941 [--json out/fit.json]\n"
       << "shadelab fit --target oren_nayar -p sigma=0.4 --all -o out/fit --json out/fit/all.json\n"
       << "shadelab fit --target oren_nayar -p sigma=0.4 --model minnaert_1941 --phase 0        # L, V at 0 deg phase only\n"
       << "shadelab fit --target phong -p n=32 --model blinn_phong --at-normal                  # the view-on-normal slice\n"
       << "shadelab fit --target oren_nayar -p sigma=0.5 --all --over scenes/lights.json --metric de2000-p99 -o out/fit\n"
       << "shadelab batch scenes/outputs.json -o out/aov                                          # colour EXR + normal and depth AOVs\n"
       << "shadelab fit --over out/aov/aov_demo.exr --scene scenes/outputs.json --model blinn_phong # fit a batch render\n"
       << "shadelab moon render -m oren_nayar -p sigma=0.5 --albedo 0.3 --phase 40 -q -o out/disc.exr\n"
       << "shadelab fit --over out/disc.exr --phase 40 --model minnaert_1941                    # fit a disc image\n"
       << "shadelab fit --atlas docs                                                            # this page (not run by the tests: minutes; tests/test_fit.cpp refits its rows)\n"
       << "build/bench_fit                                                                      # fit speed (not run by the tests: minutes; ctest runs it with --smoke)\n"
       << "```\n\n"
       << "`fit` finds the parameters of `--model` (within their catalogue ranges) and a free grey scale that minimise "
          "rel-rms = sqrt(sum (a f - t)^2 / sum t^2) against the target `t` (the target's double reference). The scale "
          "is solved in closed form inside the objective and reported as `albedo` (the scale times the grey albedo "
          "0.8 both models are given, `--albedo`). The search needs nothing but the catalogue's data (parameter names, "
          "ranges, whole-number flags and the references), so new models are fitted without changes: a coarse grid "
          "(up to 3 parameters) or 2048 quasi-random points over the ranges (every value of a whole-number parameter), "
          "then bounded Levenberg-Marquardt on the float kernel on PoCL (parameter sets evaluated in batches: "
          "`eval_batch` in kernels/shade.cl, many sets x many samples per launch), then a polish with the double "
          "references. Known equivalences come back to 1e-6 with the error at rounding level (tests). A model that "
          "blends children (gradient) is fitted with white Lambert children and says so.\n\n"
       << "It prints the parameters with standard errors (from the Jacobian at the optimum), the errors (rel-rms, "
          "rms, max-abs, rel-max; on a scene also de2000-mean, -p99, -max), where the largest difference is, and in "
          "words whether the fit is well posed: a parameter at its range limit, a parameter with no effect, a flat "
          "objective or a standard error over 10% of the range, two parameters (or one and the albedo) that trade off "
          "(|correlation| > 0.995), a target the model cannot represent (rel-rms > 5%), and the limb check: the fit "
          "redone over NoL, NoV >= 0.05; when the samples below that (9.75% of the hemisphere) carry over three times "
          "their share of the squared error and the parameters move by more than 0.1% of their range, the fit is "
          "called limb-driven (Minnaert's NoV^(k-1) diverges at the limb; k < 0.5 makes its square non-integrable "
          "without the model's guard). The refit runs only when that share is exceeded (below it the fit is not "
          "limb-driven whatever the refit says). The default objective is never changed by that check.\n\n"
       << "`--json FILE` writes `model`, `target`, `params` {name: value}, `albedo`, `error` {metric: value}, and "
          "beside them `standard_errors`, `diagnostics` [{kind, text}], `well_posed`, `representable`, "
          "`limb_check`, `largest_difference`, `domain`, evaluation counts. With `--all`, `results` holds one such "
          "object per catalogue model plus `mfrag_per_s` (its shading kernel on 262144 fragments on this device), "
          "`speedup` over the target and `pareto_front`; `-o DIR` gets `fit_all.csv` and `fit_all.png` (model error "
          "against speed with the Pareto front, and each fitted model's numeric error, float kernel against its own "
          "double reference, beside it).\n\n"
       << "Domains (`--over`): `hemisphere` (default): N = +z, L and V each uniform in solid angle over the upper "
          "hemisphere, 65536 samples (`--samples`; randomised Halton points, `--seed`), stable to ~2e-4 in k across "
          "seeds for Minnaert against Oren-Nayar (tested to 1e-3); `--phase G` keeps pairs with angle(L, V) = G, "
          "`--at-normal` sets V = N, `--min-cos C` keeps NoL, NoV >= C. `SCENE.json`: the fragments the scene renders "
          "(its meshes depth-composed, its camera and lights, ambient included), rendered colours compared per "
          "channel (grey albedo and specular; coloured lights); the target and the fitted model replace every "
          "material; de2000-mean, -p99, -max are reported beside rel-rms (limb check off: a fragment's lights share "
          "its output). A disc image (`.png .exr .tif .fits` with `--phase`, `--pa`, `--centre`, `--radius` as "
          "`moon fit` takes them): the image is the target, one sample per disc pixel (N the unit sphere under it, "
          "V = +z); `--all` then times speed-ups against Lambert. The planner's per-material catalogue search, "
          "the default of `shadelab plan SCENE` and `render/batch --tolerance`, uses the scene domain (docs/planner.md). "
          "A batch render (`--over IMAGE.exr --scene SCENE.json`, the colour EXR the batch wrote for `outputs.exr` "
          "and the scene it rendered): the image's pixels are the target, three outputs (r, g, b) per covered pixel; "
          "N comes from the normal AOV (`outputs.normal`: world-space normal, alpha = coverage) and P from the depth "
          "AOV (`outputs.depth`: view-space depth) on the pixel centre's ray of the scene's camera, V = "
          "normalize(eye - P); the lights, ambient and size are the scene's, which is why the scene file must be "
          "given (the AOVs hold no camera or lights). The AOVs default to the scene's own `outputs.normal` and "
          "`outputs.depth` in the image's folder (where `batch -o DIR` put them); `--normal FILE` and `--depth FILE` "
          "name others. The fitted model replaces every material (one model for the whole image), metrics as on a "
          "scene. A missing AOV, an image that is not one (channel count, non-unit normals, negative depth) or sizes "
          "that differ from each other or from the scene are refused in one line naming the file. Tested: oren_nayar "
          "rendered by the batch with a directional and a coloured point light comes back to 1e-4 in sigma and "
          "albedo; minnaert_1941's error on it agrees with a recomputation from the references on the rasterised "
          "fragments.\n\n"
       << "Speed (`build/bench_fit`; it prints the process's CPU time beside the wall time, because on this shared "
          "machine the wall time mostly shows the load): `--all` against oren_nayar sigma 0.4 over the default "
          "domain, 44 models, took 11.7 s of CPU time (so 5.9 s at best on two free cores; 52.6 s wall at load "
          "average 19), with 158 M kernel and 48 M reference evaluations; the command itself (`shadelab fit --target "
          "oren_nayar -p sigma=0.4 --all`, chart included, programs already in PoCL's cache) took 13.0 s of CPU time "
          "against 18.5 s before the cuts below (a profile of it; 297 M kernel and 56 M reference evaluations), and "
          "every fitted parameter and error of the 44 rows is the same to the last digit of the JSON. The cuts: the "
          "coarse search screens its grid on the domain's first 1024 samples and ranks only the best 128 on 4096 "
          "(where the starts are picked, as before); the limb check's refit runs only when the grazing samples carry "
          "over three times their share (below that the verdict is already \"not limb-driven\"); the references' "
          "values of the optimum are kept, not recomputed (the fit and `--all`'s numeric error ask for them again); "
          "`--all` times each kernel on 262144 fragments (was 1M: copying the buffer cost more than the kernel). The "
          "planetary models (three Hapke forms, two lunar-Lambert) take more than half of what is left: their kernels "
          "are the slowest in the catalogue and Hapke has up to 9 parameters. One pair (minnaert_1941 against "
          "oren_nayar): 0.21 s wall, 2.1 M kernel and 1.1 M reference evaluations.\n\n"
       << "## The atlas\n\n"
       << "Every number below is a "
          "fit of one catalogue model to another with `shadelab fit` over the default domain: N = +z, L and V each uniform "
          "in solid angle over the upper hemisphere, "
       << o.samples << " samples (randomised Halton points, seed " << o.seed
       << "), the shaded value for a unit light, grey albedo 0.8, and a free grey scale (reported as the albedo). "
          "The error is rel-rms = sqrt(sum (fit - target)^2 / sum target^2) of the best fit, computed with the double "
          "references. Speed-up: the fitted model's shading kernel against the target's, both at their catalogue "
          "defaults (a kernel's speed can depend on its parameters: blinn_phong runs 57 Mfrag/s at n = 32 and about "
          "190 at the n = 0, ks ~ 0 of some fits), measured on this shared machine ("
       << rt.device_description() << ", " << o.timed_fragments
       << " fragments, best of 3). \"Flags\" are the fit's own diagnostics (host/fit/fit.hpp): *at limit* (the best "
          "value is at the end of the parameter's range and the error would fall beyond it), *no effect*, *flat*, "
          "*trade-off* (two parameters, or one and the albedo, do the same thing here), *limb-driven* (the few samples "
          "with NoL or NoV < 0.05 carry most of the error and move the fit).\n\n"
       << "How to read the errors: rel-rms 0.01 is a 1% rms difference in shaded value, about what an sRGB 8-bit image "
          "shows as a just-visible change in smooth gradients; 0.1 is a plainly different look.\n\n";

    // ---- 1. Minnaert against Oren-Nayar -------------------------------------------------------------------------
    {
        log << "atlas: Minnaert forms against Oren-Nayar\n";
        const std::vector<std::pair<std::string, std::string>> forms = {
            {"minnaert_1941", "k"}, {"minnaert_unity", "k"}, {"minnaert_blender", "darkness"},
            {"minnaert_normalized", "k"}, {"minnaert_b", "k"}};
        CsvTable t({"sigma", "model", "parameter", "value", "albedo", "rel_rms", "lambert_rel_rms", "speedup", "flags"});
        md << "## Minnaert against Oren-Nayar (seeds 000-002: \"Minnaert looks like Oren-Nayar, cheaper\")\n\n"
           << "Each Minnaert form fitted to the paper's qualitative Oren-Nayar (`oren_nayar`) at sigma in [0, 1.2]; "
              "Lambert's own best fit for comparison. Table: best parameter / rel-rms.\n\n"
           << "| sigma | Lambert | minnaert_1941 k | minnaert_unity k | minnaert_blender d | minnaert_normalized k | minnaert_b k |\n"
           << "| --- | --- | --- | --- | --- | --- | --- |\n";
        for (int q = 0; q <= 12; q += 1) {
            const double sigma = 0.1 * q;
            const Material tgt = target_of("oren_nayar", {{"sigma", sigma}});
            const FitResult lam = A.fit(tgt, "lambert");
            md << "| " << fixed(sigma, 1) << " | " << err(lam.error.at("rel-rms"));
            for (const auto& [model, pname] : forms) {
                const FitResult r = A.fit(tgt, model);
                const double sp = A.speed(model) / A.speed("oren_nayar");
                t.row().add(sigma, 3).add(model).add(pname).add(param(r, pname), 7).add(r.albedo, 7)
                    .add(r.error.at("rel-rms"), 5).add(lam.error.at("rel-rms"), 5).add(sp, 4).add(flags(r));
                md << " | " << fixed(param(r, pname), 3) << " / " << err(r.error.at("rel-rms"));
                if (!flags(r).empty()) md << " (" << flags(r) << ")";
            }
            md << " |\n";
        }
        const std::string csv = A.csv_path("minnaert_vs_oren_nayar");
        t.write(csv);
        A.wrote(csv);
        md << "\nminnaert_1941 and minnaert_normalized stay at exactly k = 1 for sigma <= 0.2: their limb guard (cosines "
              "below 1e-3 faded to 0, docs/models/minnaert.md) applies for k < 1 only, so the value jumps at k = 1 on the "
              "grazing samples, and that jump costs more than a k just below 1 gains; the unguarded minnaert_unity finds "
              "k_1941 = 1 + k_unity = 0.995 at sigma 0.1.\n\nSpeed-up over `oren_nayar` on this machine:";
        for (const auto& [model, _] : forms) md << " " << model << " " << fixed(A.speed(model) / A.speed("oren_nayar"), 2) << "x;";
        md << " lambert " << fixed(A.speed("lambert") / A.speed("oren_nayar"), 2) << "x. Table: `data/fidelity/minnaert_vs_oren_nayar.csv`.\n\n";
        const Material tgt = target_of("oren_nayar", {{"sigma", 0.4}});
        A.residual_plot("minnaert_1941_vs_oren_nayar_0.4", tgt, A.fit(tgt, "minnaert_1941"));
        md << "![residual of minnaert_1941 fitted to oren_nayar sigma 0.4](images/fidelity/minnaert_1941_vs_oren_nayar_0.4.png)\n\n";
    }

    // ---- 2. Blinn-Phong against Phong ---------------------------------------------------------------------------
    {
        log << "atlas: Blinn-Phong against Phong\n";
        CsvTable t({"phong_n", "slice", "blinn_n", "ratio", "ks", "albedo", "rel_rms", "flags"});
        md << "## Blinn-Phong against Phong: the exponent relation (the common \"n_Blinn = 4 n_Phong\" rule)\n\n"
           << "`blinn_phong` (n, ks and the albedo free) fitted to `phong` (ks = 1) over the whole hemisphere and over the "
              "view-on-normal slice (V = N, L over the hemisphere, `--at-normal`), where the rule is usually derived.\n\n"
           << "| Phong n | hemisphere: Blinn n | ratio | rel-rms | at normal: Blinn n | ratio | rel-rms |\n| --- | --- | --- | --- | --- | --- | --- |\n";
        for (double n : {1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0, 256.0, 1024.0}) {
            const Material tgt = target_of("phong", {{"n", n}, {"ks", 1.0}});
            md << "| " << n;
            for (bool at_normal : {false, true}) {
                const FitResult r = A.fit(tgt, "blinn_phong", at_normal);
                const double bn = param(r, "n");
                t.row().add(n).add(at_normal ? "at_normal" : "hemisphere").add(bn, 7).add(bn / n, 5).add(param(r, "ks"), 5)
                    .add(r.albedo, 6).add(r.error.at("rel-rms"), 5).add(flags(r));
                md << " | " << fixed(bn, 1) << " | " << fixed(bn / n, 2) << " | " << err(r.error.at("rel-rms"));
            }
            md << " |\n";
        }
        const std::string csv = A.csv_path("blinn_phong_vs_phong");
        t.write(csv);
        A.wrote(csv);
        md << "\nTable: `data/fidelity/blinn_phong_vs_phong.csv`. Speed-up of blinn_phong over phong: "
           << fixed(A.speed("blinn_phong") / A.speed("phong"), 2) << "x.\n\n";
        const Material tgt = target_of("phong", {{"n", 32.0}, {"ks", 1.0}});
        A.residual_plot("blinn_phong_vs_phong_32", tgt, A.fit(tgt, "blinn_phong"));
        md << "![residual of blinn_phong fitted to phong n 32](images/fidelity/blinn_phong_vs_phong_32.png)\n\n";
    }

    // ---- 3. Blinn-Phong / Phong against Beckmann and GGX Cook-Torrance -------------------------------------------
    {
        log << "atlas: Phong lobes against Cook-Torrance\n";
        CsvTable t({"target", "m", "model", "slice", "n", "ks", "albedo", "rel_rms", "walter_n", "flags"});
        md << "## Blinn-Phong and Phong against Beckmann and GGX Cook-Torrance (n against m, alpha)\n\n"
           << "Targets: `cook_torrance` (Beckmann) and `cook_torrance_ggx` at kd = 1, ks = 1, f0 = 0.04 and roughness m. "
              "Fitted: `blinn_phong` and `phong` (n, ks, albedo free). Walter et al. (2007) give n = 2 / m^2 - 2 for the "
              "Beckmann distribution.\n\n"
           << "The 1982 form divides by NoV, so over the whole hemisphere its grazing-view values (with the Fresnel "
              "rise) dominate the error and no cosine lobe follows them; the view-on-normal slice (V = N) compares the "
              "lobes alone.\n\n"
           << "| target | m | 2/m^2 - 2 | hemisphere: Blinn n | rel-rms | Phong n | rel-rms | at normal: Blinn n | rel-rms | Phong n | rel-rms |\n"
           << "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
        for (const char* tm : {"cook_torrance", "cook_torrance_ggx"})
            for (double m : {0.1, 0.2, 0.3, 0.5}) {
                const Material tgt = target_of(tm, {{"m", m}});
                md << "| " << tm << " | " << m << " | " << fixed(2.0 / (m * m) - 2.0, 1);
                for (bool at_normal : {false, true}) {
                    const FitResult b = A.fit(tgt, "blinn_phong", at_normal), p = A.fit(tgt, "phong", at_normal);
                    for (const FitResult* r : {&b, &p})
                        t.row().add(tm).add(m, 3).add(r->model).add(at_normal ? "at_normal" : "hemisphere").add(param(*r, "n"), 6)
                            .add(param(*r, "ks"), 5).add(r->albedo, 6).add(r->error.at("rel-rms"), 5)
                            .add(2.0 / (m * m) - 2.0, 5).add(flags(*r));
                    md << " | " << fixed(param(b, "n"), 1) << " | " << err(b.error.at("rel-rms")) << " | "
                       << fixed(param(p, "n"), 1) << " | " << err(p.error.at("rel-rms"));
                }
                md << " |\n";
            }
        const std::string csv = A.csv_path("phong_vs_cook_torrance");
        t.write(csv);
        A.wrote(csv);
        md << "\nTable: `data/fidelity/phong_vs_cook_torrance.csv`. Speed-up of blinn_phong over cook_torrance: "
           << fixed(A.speed("blinn_phong") / A.speed("cook_torrance"), 2) << "x, over cook_torrance_ggx: "
           << fixed(A.speed("blinn_phong") / A.speed("cook_torrance_ggx"), 2) << "x.\n\n";
    }

    // ---- 4. Half-Lambert and wrap against Lambert -------------------------------------------------------------------
    {
        log << "atlas: wrap forms against Lambert\n";
        CsvTable t({"model", "params", "albedo", "rel_rms", "speedup", "flags"});
        md << "## Half-Lambert and wrap against Lambert\n\n| model | best parameters | rel-rms | speed-up over lambert | flags |\n| --- | --- | --- | --- | --- |\n";
        const Material tgt = target_of("lambert", {});
        for (const char* m : {"half_lambert", "half_lambert_seed001", "wrap", "wrap_seed001", "wrap_energy"}) {
            const FitResult r = A.fit(tgt, m);
            const double sp = A.speed(m) / A.speed("lambert");
            t.row().add(m).add(Atlas::fit_params(r)).add(r.albedo, 6).add(r.error.at("rel-rms"), 5).add(sp, 4).add(flags(r));
            md << "| " << m << " | " << Atlas::fit_params(r) << " | " << err(r.error.at("rel-rms")) << " | " << fixed(sp, 2)
               << " | " << flags(r) << " |\n";
        }
        const std::string csv = A.csv_path("wrap_vs_lambert");
        t.write(csv);
        A.wrote(csv);
        md << "\nhalf_lambert and wrap (NoL unclamped) light the back of the surface, which Lambert leaves black: the "
              "best wrap_value is where that costs least; wrap_energy reaches Lambert exactly at w = 0. Table: "
              "`data/fidelity/wrap_vs_lambert.csv`.\n\n";
        A.residual_plot("half_lambert_vs_lambert", tgt, A.fit(tgt, "half_lambert"));
        md << "![residual of half_lambert fitted to lambert](images/fidelity/half_lambert_vs_lambert.png)\n\n";
    }

    // ---- 5. The Minnaert parameterisations against each other -----------------------------------------------------
    {
        log << "atlas: Minnaert parameterisations\n";
        CsvTable t({"target", "target_value", "model", "value", "expected", "abs_difference", "albedo", "rel_rms", "domain"});
        md << "## The Blender, Unity and 1941 Minnaert parameterisations against each other\n\n"
           << "Exact maps: unity k = k_1941 - 1 (where the saturate does not clip: k_unity >= 0); Blender's darkness d <= 1 "
              "is k_1941 = d where its clamp max(NoV NoL, 0.1) is inactive (NoL, NoV >= sqrt(0.1), `--min-cos 0.3163`); "
              "normalized k = k_1941 with the albedo times 2 / (k + 1). The fit must recover them to 1e-6.\n\n"
           << "| target | fitted | expected | found | abs. difference | rel-rms | domain |\n| --- | --- | --- | --- | --- | --- | --- |\n";
        struct Map {
            std::string target, tparam;
            double tv;
            std::string model, mparam;
            double expected;
            double min_cos;
        };
        const std::vector<Map> maps = {
            {"minnaert_unity", "k", 0.3, "minnaert_1941", "k", 1.3, 0.0},
            {"minnaert_unity", "k", 0.0, "minnaert_1941", "k", 1.0, 0.0},
            {"minnaert_1941", "k", 1.7, "minnaert_unity", "k", 0.7, 0.0},
            {"minnaert_blender", "darkness", 0.6, "minnaert_1941", "k", 0.6, 0.3163},
            {"minnaert_1941", "k", 0.8, "minnaert_blender", "darkness", 0.8, 0.3163},
            {"minnaert_blender", "darkness", 0.6, "minnaert_1941", "k", 0.6, 0.0},
            {"minnaert_normalized", "k", 0.7, "minnaert_1941", "k", 0.7, 0.0},
            {"minnaert_unity", "k", -0.5, "minnaert_1941", "k", 0.5, 0.0},
        };
        for (const auto& mp : maps) {
            const Material tgt = target_of(mp.target, {{mp.tparam, mp.tv}});
            HemisphereOptions ho;
            ho.samples = o.samples;
            ho.seed = o.seed;
            ho.min_cos = mp.min_cos;
            Problem p(rt, hemisphere_domain(ho), tgt);
            const FitResult r = fit_model(p, shape_for(mp.model, tgt, -1.0, nullptr));
            const double v = param(r, mp.mparam);
            const std::string dom = mp.min_cos > 0 ? "NoL, NoV >= 0.3163" : "hemisphere";
            t.row().add(mp.target).add(mp.tv, 4).add(mp.model).add(v, 10).add(mp.expected, 6).add(std::abs(v - mp.expected), 3)
                .add(r.albedo, 8).add(r.error.at("rel-rms"), 4).add(dom);
            md << "| " << mp.target << " " << mp.tparam << " = " << mp.tv << " | " << mp.model << " " << mp.mparam << " | "
               << mp.expected << " | " << fixed(v, 7) << " | " << num(std::abs(v - mp.expected), 2) << " | "
               << err(r.error.at("rel-rms")) << " | " << dom << " |\n";
        }
        const std::string csv = A.csv_path("minnaert_maps");
        t.write(csv);
        A.wrote(csv);
        md << "\nWhere a map is not exact the fit says what it costs: Blender's clamp over the whole hemisphere, and "
              "Unity's saturate for k < 0 (it clips NoL (NoL NoV)^k at 1 near the limb). Table: `data/fidelity/minnaert_maps.csv`.\n\n";
    }

    // ---- 6. Oren-Nayar variants against the paper's full model ----------------------------------------------------
    {
        log << "atlas: Oren-Nayar variants against the full model\n";
        const std::vector<std::string> variants = {"oren_nayar", "oren_nayar_st", "oren_nayar_seed001", "oren_nayar_seed003",
                                                   "oren_nayar_seed004", "oren_nayar_blender", "oren_nayar_fujii",
                                                   "oren_nayar_fujii_full", "eon", "eon_approx", "lambert"};
        CsvTable t({"sigma", "model", "params", "albedo", "rel_rms", "speedup", "flags"});
        md << "## Oren-Nayar variants against the paper's full model\n\n"
           << "Target: `oren_nayar_full` (C1, C2, C3 and the interreflection term) at albedo 0.8. Each variant's own "
              "roughness fitted (the seeds' forms, Fujii, EON), with its rel-rms; speed-up over oren_nayar_full in the last row.\n\n"
           << "| sigma |";
        for (const auto& v : variants) md << " " << v << " |";
        md << "\n| --- |";
        for (std::size_t q = 0; q < variants.size(); ++q) md << " --- |";
        md << "\n";
        for (double sigma : {0.2, 0.4, 0.8, 1.2}) {
            const Material tgt = target_of("oren_nayar_full", {{"sigma", sigma}});
            md << "| " << sigma << " |";
            for (const auto& v : variants) {
                const FitResult r = A.fit(tgt, v);
                const double sp = A.speed(v) / A.speed("oren_nayar_full");
                t.row().add(sigma, 3).add(v).add(Atlas::fit_params(r)).add(r.albedo, 6).add(r.error.at("rel-rms"), 5).add(sp, 4).add(flags(r));
                md << " " << (r.params.empty() ? "" : fixed(r.params.front().value, 3) + " / ") << err(r.error.at("rel-rms")) << " |";
            }
            md << "\n";
        }
        md << "| speed-up |";
        for (const auto& v : variants) md << " " << fixed(A.speed(v) / A.speed("oren_nayar_full"), 2) << "x |";
        md << "\n";
        const std::string csv = A.csv_path("oren_nayar_variants");
        t.write(csv);
        A.wrote(csv);
        md << "\nTable: `data/fidelity/oren_nayar_variants.csv`.\n\n";
        const Material tgt = target_of("oren_nayar_full", {{"sigma", 0.8}});
        A.residual_plot("oren_nayar_fujii_vs_full_0.8", tgt, A.fit(tgt, "oren_nayar_fujii"));
        md << "![residual of oren_nayar_fujii fitted to oren_nayar_full sigma 0.8](images/fidelity/oren_nayar_fujii_vs_full_0.8.png)\n\n";
    }
    const double secs = std::chrono::duration<double>(clock::now() - t0).count();
    md << "---\n" << A.fits() << " fits and the timings took " << fixed(secs, 1) << " s on this machine.\n";
    const std::string page = (fs::path(o.docs_dir) / "fidelity.md").string();
    write_text_atomically(page, "atlas page", md.str());
    A.wrote(page);
    return A.files();
}

}  // namespace shadelab::fit
