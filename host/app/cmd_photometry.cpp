// shadelab photometry: ISIS3's photometric models at (phase, incidence, emission), from ISIS's own PVL parameter
// files or by catalogue name, on PoCL (docs/photometry.md).
//   photometry eval --pvl FILE --phase G --incidence I --emission E    the value, last number on stdout
//   photometry eval --pvl FILE --csv IN.csv -o OUT.csv                 every row of a table, a `value` column added
#include <chrono>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>

#include "app/commands.hpp"
#include "cl/runtime.hpp"
#include "core/error.hpp"
#include "photometry/csv.hpp"
#include "photometry/isis.hpp"

namespace shadelab::app {

namespace {

struct EvalArgs {
    std::string pvl, model, csv, out, precision = "precise";
    std::vector<std::string> params;
    double phase = -1.0, incidence = -1.0, emission = -1.0;
    bool reference = false;
};

photometry::Law law_from_args(const EvalArgs& a) {
    if (a.pvl.empty() == a.model.empty())
        throw Error("photometry eval: give the law either as --pvl FILE (ISIS's PhotometricModel form) or as --model NAME");
    if (!a.pvl.empty()) {
        if (!a.params.empty()) throw Error("photometry eval: -p/--param goes with --model, not with --pvl");
        return photometry::law_from_pvl_file(a.pvl);
    }
    std::map<std::string, double> p;
    for (const auto& s : a.params) p.insert(parse_param(s));
    return photometry::law_from_model(a.model, p);
}

void run_eval(const EvalArgs& a) {
    const photometry::Law law = law_from_args(a);
    const Precision precision = parse_precision(a.precision);
    for (const auto& w : law.warnings) std::cerr << "shadelab: warning: " << w << "\n";
    const bool single = a.phase >= 0.0 || a.incidence >= 0.0 || a.emission >= 0.0;
    if (single == !a.csv.empty())
        throw Error("photometry eval: give either --phase, --incidence and --emission (one geometry) or --csv IN.csv -o OUT.csv");
    Runtime rt;
    std::cout << "law: " << law.describe() << "\n";
    if (single) {
        if (a.phase < 0.0 || a.incidence < 0.0 || a.emission < 0.0)
            throw Error("photometry eval: --phase, --incidence and --emission are all needed (degrees, 0 to 180)");
        const photometry::Geometry g{a.phase, a.incidence, a.emission};
        photometry::check_geometry(g, "photometry eval");
        const double v = photometry::evaluate(rt, law, {g}, precision)[0];
        std::cout << "geometry: phase " << g.phase << " deg, incidence " << g.incidence << " deg, emission "
                  << g.emission << " deg\n";
        if (a.reference)
            std::cout << "reference (double): " << std::setprecision(12) << photometry::evaluate_reference(law, g) << "\n";
        std::cout << "device: " << rt.device_description() << ", " << precision_name(precision) << " mode\n"
                  << "value: " << std::setprecision(9) << v << "\n";
        return;
    }
    if (a.out.empty()) throw Error("photometry eval --csv: give the output table with -o OUT.csv");
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    const photometry::GeometryTable t = photometry::read_geometry_csv(a.csv);
    const auto t1 = clock::now();
    const std::vector<double> values = photometry::evaluate(rt, law, t.geometry, precision);
    const auto t2 = clock::now();
    photometry::write_values_csv(a.out, t, values);
    const auto t3 = clock::now();
    auto s = [](auto d) { return std::chrono::duration<double>(d).count(); };
    std::cout << "rows: " << t.geometry.size() << " (read " << s(t1 - t0) << " s, evaluate " << s(t2 - t1)
              << " s incl. kernel build, write " << s(t3 - t2) << " s)\n"
              << "wrote: " << a.out << "\n";
}

}  // namespace

void add_photometry_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("photometry", "ISIS3's photometric models (Hapke, Lunar-Lambert, Minnaert, ...) "
                                                 "at photometric angles, from ISIS PVL files (docs/photometry.md)");
    cmd->require_subcommand(1);
    auto a = std::make_shared<EvalArgs>();
    auto* ev = cmd->add_subcommand("eval", "Evaluate a photometric law at one geometry or every row of a CSV table");
    ev->add_option("--pvl", a->pvl, "ISIS photometric parameter file (Object = PhotometricModel, Group = Algorithm)");
    ev->add_option("--model", a->model, "or a catalogue model by name (shadelab models), e.g. hapke_hen");
    ev->add_option("-p,--param", a->params, "name=value parameter of --model (repeatable)");
    ev->add_option("--phase", a->phase, "phase angle g, degrees [0, 180]");
    ev->add_option("--incidence", a->incidence, "incidence angle i, degrees [0, 180] (>= 90: unlit, 0)");
    ev->add_option("--emission", a->emission, "emission angle e, degrees [0, 180] (>= 90: unseen, 0)");
    ev->add_option("--csv", a->csv, "table with columns phase, incidence, emission (degrees), one geometry per row");
    ev->add_option("-o,--out", a->out, "output table: the input with a value column");
    ev->add_flag("--reference", a->reference, "also print the double-precision reference (one geometry)");
    ev->add_option("--precision", a->precision, "precise | fast (docs/precision.md)")->capture_default_str();
    ev->callback([a] { run_eval(*a); });
}

}  // namespace shadelab::app
