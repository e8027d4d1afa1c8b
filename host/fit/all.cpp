#include "fit/all.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <map>
#include <ostream>
#include <sstream>

#include "core/error.hpp"
#include "core/format.hpp"
#include "fit/report.hpp"
#include "core/csv.hpp"
#include "plot/gnuplot.hpp"
#include "speed/pareto.hpp"

namespace fs = std::filesystem;

namespace shadelab::fit {

namespace {

std::string params_text(const FitResult& f) {
    std::string s;
    for (const auto& p : f.params) s += (s.empty() ? "" : " ") + p.name + "=" + num(p.value, 5);
    return s;
}

// Log axes cannot show 0: errors below this are drawn at it (the CSV keeps the measured value).
constexpr double kErrorFloor = 1e-9;

// One panel: error column `col` against speed, every model a point, the front a line with its members labelled.
std::string panel(const std::string& csv, const std::vector<AllRow>& rows, bool model_error, const std::string& title,
                  const std::string& metric) {
    using plot::gp_number;
    using plot::gp_string;
    std::vector<speed::ParetoPoint> pts;
    std::vector<bool> on;
    double xlo = 1e300, xhi = 0, ylo = 1e300, yhi = 0;
    for (const auto& r : rows) {
        const double e = std::max(model_error ? r.fit.error.at(metric) : r.numeric_rel_rms, kErrorFloor);
        pts.push_back({r.mfrag_per_s, e});
        xlo = std::min(xlo, r.mfrag_per_s), xhi = std::max(xhi, r.mfrag_per_s);
        ylo = std::min(ylo, e), yhi = std::max(yhi, e);
    }
    on = speed::pareto_front(pts);
    const auto order = speed::front_in_speed_order(pts, on);
    const std::string col = model_error ? "plot_error" : "plot_numeric_rel_rms";
    std::ostringstream s;
    s << "set title " << gp_string(title) << "\n"
      << "set xlabel 'speed: million fragments per second on this device (log scale)'\n"
      << "set ylabel " << gp_string(model_error ? "model error: " + metric + " of the best fit against the target (log scale)"
                                                : "numeric error: rel-rms of the float kernel against its own double "
                                                  "reference (log scale)")
      << "\nset logscale xy\nset format y '10^{%L}'\nset format x '%g'\nset key bottom left box opaque\n"
      << "set xrange [" << gp_number(xlo / 2.0) << ":" << gp_number(xhi * 2.0) << "]\n"
      << "set yrange [" << gp_number(ylo / 10.0) << ":" << gp_number(yhi * 30.0) << "]\n"
      << "unset label\n";
    int lab = 1;
    // The target itself (fitted to itself, so it is among the rows) is marked.
    for (std::size_t i = 0; i < rows.size(); ++i)
        if (rows[i].is_target)
            s << "set label " << lab++ << " 'target' at " << gp_number(pts[i].speed, 9) << "," << gp_number(pts[i].error, 9)
              << " offset 0,-1.2 center font 'sans,9' tc rgb '#208020' front\n";
    for (std::size_t i : order)
        s << "set label " << lab++ << " " << gp_string(rows[i].fit.model) << " at " << gp_number(pts[i].speed, 9) << ","
          << gp_number(pts[i].error, 9) << " offset 0,1.0 center noenhanced font 'sans,8' tc rgb '#a00000' front\n";
    const std::string block = model_error ? "$front_model" : "$front_numeric";
    s << block << " << EOD\nx,y\n";
    for (std::size_t i : order) s << gp_number(pts[i].speed, 9) << "," << gp_number(pts[i].error, 9) << "\n";
    s << "EOD\n";
    s << "plot " << gp_string(csv) << " using 'mfrag_per_s':'" << col
      << "' with points pt 7 ps 1.0 lc rgb '#3060c0' title 'catalogue models', " << block
      << " using 1:2 with lines lw 1.5 dt 2 lc rgb '#a00000' notitle, " << block
      << " using 1:2 with points pt 6 ps 2.0 lw 1.5 lc rgb '#a00000' title 'Pareto front'\n";
    return s.str();
}

}  // namespace

double measure_mfrag_per_s(Runtime& rt, const Material& m, std::size_t fragments, int repeats) {
    // Fragments over the visible half of a unit sphere seen from +z (normals = positions), a regular spiral;
    // built once per size (every model of --all is timed on the same buffer).
    static std::map<std::size_t, FragmentBuffer> buffers;
    FragmentBuffer& fb = buffers[fragments];
    if (fb.size() != fragments) {
        fb = FragmentBuffer{};
        fb.reserve(fragments);
        const double golden = 2.39996322972865332;
        for (std::size_t i = 0; i < fragments; ++i) {
            const double z = (double(i) + 0.5) / double(fragments), r = std::sqrt(std::max(0.0, 1.0 - z * z));
            const double phi = golden * double(i);
            const float x = float(r * std::cos(phi)), y = float(r * std::sin(phi)), zz = float(z);
            fb.push_back(x, y, zz, x, y, zz, std::int32_t(i), 0.5f);
        }
    }
    ShadeSetup s;
    s.material = m;
    s.lights = {Light{Light::Type::Directional, {0.5, 0.7, 1.0}, {1, 1, 1}, 1.0, 0.0}};
    s.view = glm::dvec4(0.0, 0.0, 3.0, 1.0);
    Shader shader(rt);
    double best = std::numeric_limits<double>::infinity(), spent = 0.0;
    for (int r = 0; r < std::max(1, repeats) && spent < 60.0; ++r) {
        ShadeTiming t;
        shader.shade(fb, s, &t);
        best = std::min(best, t.kernel_ms);
        spent += t.kernel_ms;
    }
    if (!(best > 0.0) || !std::isfinite(best))
        throw Error("fit --all: the device reported a kernel time of " + std::to_string(best) + " ms for model '" +
                    m.model + "': profiling is not usable on this device");
    return double(fragments) / (best * 1e-3) * 1e-6;
}

// The models --all fits: `given` (each checked), or the catalogue's. A table model (the empirical family) is not a
// candidate: a fit varies no table, so it would fit its albedo at its default tables only.
static std::vector<std::string> candidate_models(const std::vector<std::string>& given, std::ostream& log) {
    std::vector<std::string> models = given;
    if (models.empty())
        for (const auto& m : model_catalogue()) {
            if (has_tables(m))
                log << "fit --all: skipping " << m.name << ": its tables (" << m.tables.front().name
                    << ", ...) are data, not fitted parameters\n";
            else
                models.push_back(m.name);
        }
    for (const auto& m : models)   // every name checked before the long run
        if (has_tables(find_model(m)))
            throw Error("fit --all: model '" + m + "' reads tables (" + find_model(m).tables.front().name +
                        ", ...), which a fit does not vary: leave it out of --models");
    return models;
}

AllResult fit_all(Runtime& rt, Problem& problem, const AllOptions& o, std::ostream& log) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    const std::vector<std::string> models = candidate_models(o.models, log);
    if (!o.out_dir.empty()) plot::find_gnuplot();
    const Material& target = problem.target_material();
    AllResult out;
    out.target_model = target.model;
    out.target_name = problem.target_name();
    out.target_params = target.params;
    out.domain = problem.full().domain().name;
    out.domain_description = problem.full().domain().description;
    out.device = rt.device_description();
    out.timed_fragments = o.timed_fragments;
    double fit_s = 0.0, time_s = 0.0;
    for (std::size_t q = 0; q < models.size(); ++q) {
        AllRow row;
        std::string note;
        const ModelShape shape = shape_for(models[q], target, o.model_specular, &note);
        const auto a = clock::now();
        row.fit = fit_model(problem, shape, {}, o.fit);
        row.fit.note = note;
        row.is_target = models[q] == problem.target_name();
        // The numeric error of the fitted model itself: its float kernel against its double reference.
        {
            Evaluator& ev = problem.full();
            const std::size_t n = ev.size();
            const auto fk = ev.kernel(shape, {row.fit.values()}, 1);
            const auto fr = ev.reference(shape, row.fit.values());
            double num2 = 0.0, den2 = 0.0;
            for (std::size_t i = 0; i < n; ++i) {
                const double d = double(fk[i]) - fr[i];
                num2 += d * d;
                den2 += fr[i] * fr[i];
            }
            row.numeric_rel_rms = den2 > 0.0 ? std::sqrt(num2 / den2) : 0.0;
        }
        const auto b = clock::now();
        row.mfrag_per_s = measure_mfrag_per_s(rt, material_at(shape, row.fit.values()), o.timed_fragments, o.timing_repeats);
        const auto c = clock::now();
        fit_s += std::chrono::duration<double>(b - a).count();
        time_s += std::chrono::duration<double>(c - b).count();
        log << "[" << (q + 1) << "/" << models.size() << "] " << std::left << std::setw(30) << models[q] << std::right
            << " rel-rms " << std::setw(10) << num(row.fit.error.at("rel-rms"), 4) << "  " << std::setw(8)
            << num(row.mfrag_per_s, 4) << " Mfrag/s  fit " << num(std::chrono::duration<double>(b - a).count(), 3) << " s\n";
        out.rows.push_back(std::move(row));
    }
    // A measured target (an image) has no kernel: speed-ups are then over Lambert, and the table says so.
    const bool measured = problem.target_name() != target.model;
    out.speed_reference = measured ? std::string("lambert (the target is measured)") : target.model;
    {
        const auto a = clock::now();
        out.target_mfrag_per_s = measure_mfrag_per_s(rt, target, o.timed_fragments, o.timing_repeats);
        time_s += std::chrono::duration<double>(clock::now() - a).count();
    }
    // Timing is noisy on a shared machine: one more round over every model, each keeping its best.
    {
        const auto a = clock::now();
        for (auto& r : out.rows) {
            const ModelShape shape = shape_for(r.fit.model, target, o.model_specular, nullptr);
            r.mfrag_per_s = std::max(r.mfrag_per_s, measure_mfrag_per_s(rt, material_at(shape, r.fit.values()),
                                                                        o.timed_fragments, o.timing_repeats));
        }
        out.target_mfrag_per_s = std::max(out.target_mfrag_per_s,
                                          measure_mfrag_per_s(rt, target, o.timed_fragments, o.timing_repeats));
        time_s += std::chrono::duration<double>(clock::now() - a).count();
    }
    for (auto& r : out.rows) r.speedup = r.mfrag_per_s / out.target_mfrag_per_s;
    out.metric = o.metric;
    for (const auto& r : out.rows)
        if (!r.fit.error.count(o.metric)) throw Error("--metric '" + o.metric + "' is not measured on this domain");
    const std::string key = o.metric;
    std::stable_sort(out.rows.begin(), out.rows.end(),
                     [&](const AllRow& a, const AllRow& b) { return a.fit.error.at(key) < b.fit.error.at(key); });
    {
        std::vector<speed::ParetoPoint> pts;
        for (const auto& r : out.rows) pts.push_back({r.mfrag_per_s, r.fit.error.at(key)});
        const auto on = speed::pareto_front(pts);
        for (std::size_t i = 0; i < out.rows.size(); ++i) out.rows[i].front = on[i];
    }
    if (!out.rows.empty()) out.target = describe_target(out.rows.front().fit);
    out.fit_seconds = fit_s;
    out.timing_seconds = time_s;
    if (!o.out_dir.empty()) {
        const std::string csv = (fs::path(o.out_dir) / "fit_all.csv").string();
        const std::string png = (fs::path(o.out_dir) / "fit_all.png").string();
        CsvTable t({"rank", "model", "family", "params", "albedo", "rel_rms", "rms", "max_abs", "rel_max",
                          "well_posed", "representable", "limb_sensitive", "mfrag_per_s", "speedup", "pareto_front",
                          "numeric_rel_rms", "de2000_mean", "de2000_p99", "de2000_max", "plot_error",
                          "plot_numeric_rel_rms"});
        for (std::size_t i = 0; i < out.rows.size(); ++i) {
            const AllRow& r = out.rows[i];
            const auto& e = r.fit.error;
            t.row()
                .add(double(i + 1))
                .add(r.fit.model)
                .add(find_model(r.fit.model).family)
                .add(params_text(r.fit))
                .add(r.fit.albedo, 7)
                .add(e.at("rel-rms"), 6)
                .add(e.at("rms"), 6)
                .add(e.at("max-abs"), 6)
                .add(e.at("rel-max"), 6)
                .add(r.fit.well_posed ? 1.0 : 0.0)
                .add(r.fit.representable ? 1.0 : 0.0)
                .add(r.fit.limb.sensitive ? 1.0 : 0.0)
                .add(r.mfrag_per_s, 6)
                .add(r.speedup, 5)
                .add(r.front ? 1.0 : 0.0)
                .add(r.numeric_rel_rms, 4);
            for (const char* m : {"de2000-mean", "de2000-p99", "de2000-max"})
                if (e.count(m)) t.add(e.at(m), 5);
                else t.blank();
            t.add(std::max(e.at(key), kErrorFloor), 6)
                .add(std::max(r.numeric_rel_rms, kErrorFloor), 4);
        }
        t.write(csv);
        out.files.push_back(csv);
        std::ostringstream s;
        s << plot::gnuplot_preamble(png, 1800, 820, 11);
        s << "set multiplot layout 1,2 title \"" << "Every catalogue model fitted to " << out.target << " on the "
          << out.domain << " (" << problem.full().size() << " samples)\\nspeed: shading kernel on " << out.device
          << "\" noenhanced font 'sans,13'\n";
        s << panel(csv, out.rows, true, "model error against speed (the target: " + num(out.target_mfrag_per_s, 4) +
                                            " Mfrag/s; < 1e-9 drawn at 1e-9)", key);
        s << panel(csv, out.rows, false, "numeric error of each fitted model (float kernel vs its double reference)", key);
        s << "unset multiplot\n";
        plot::run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
        out.files.push_back(png);
    }
    out.seconds = std::chrono::duration<double>(clock::now() - t0).count();
    return out;
}

std::string all_table_text(const AllResult& r) {
    std::ostringstream s;
    s << "every model fitted to " << r.target << "\n  domain: " << r.domain_description << "\n  speed: shading kernel, "
      << r.timed_fragments << " fragments, best of runs, on " << r.device << "; speed-ups over "
      << r.speed_reference << " at " << num(r.target_mfrag_per_s, 4) << " Mfrag/s\n";
    s << "  " << std::left << std::setw(5) << "rank" << std::setw(30) << "model" << std::right << std::setw(11) << r.metric
      << std::setw(10) << "Mfrag/s" << std::setw(9) << "speedup" << "  front  " << std::left << "parameters (albedo)\n";
    for (std::size_t i = 0; i < r.rows.size(); ++i) {
        const AllRow& a = r.rows[i];
        s << "  " << std::left << std::setw(5) << (i + 1) << std::setw(30) << a.fit.model << std::right << std::setw(11)
          << num(a.fit.error.at(r.metric), 3) << std::setw(10) << num(a.mfrag_per_s, 4) << std::setw(9)
          << num(a.speedup, 3) << (a.front ? "    *    " : "         ") << params_text(a.fit)
          << (a.fit.params.empty() ? "" : " ") << "(" << num(a.fit.albedo, 5) << ")"
          << (a.fit.well_posed ? "" : " [ill-posed]") << (a.fit.limb.sensitive ? " [limb]" : "") << "\n";
    }
    s << "  * on the Pareto front of speed against model error; fitting took " << num(r.fit_seconds, 3)
      << " s, timing " << num(r.timing_seconds, 3) << " s, all " << num(r.seconds, 3) << " s\n";
    return s.str();
}

nlohmann::json to_json(const AllResult& r) {
    nlohmann::json j;
    j["target"] = r.target_name.empty() ? r.target_model : r.target_name;
    nlohmann::json tp = nlohmann::json::object();
    for (const auto& [k, v] : r.target_params) tp[k] = v;
    j["target_params"] = tp;
    j["target_mfrag_per_s"] = r.target_mfrag_per_s;
    j["speed_reference"] = r.speed_reference;
    j["domain"] = {{"name", r.domain}, {"description", r.domain_description}};
    j["device"] = r.device;
    j["timed_fragments"] = r.timed_fragments;
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& a : r.rows) {
        nlohmann::json o = to_json(a.fit);
        o["mfrag_per_s"] = a.mfrag_per_s;
        o["speedup"] = a.speedup;
        o["pareto_front"] = a.front;
        o["numeric_rel_rms"] = a.numeric_rel_rms;
        rows.push_back(o);
    }
    j["results"] = rows;
    j["files"] = r.files;
    j["seconds"] = r.seconds;
    j["fit_seconds"] = r.fit_seconds;
    j["timing_seconds"] = r.timing_seconds;
    return j;
}

}  // namespace shadelab::fit
