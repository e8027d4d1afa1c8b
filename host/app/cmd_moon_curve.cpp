// shadelab moon curve: analytic intensity profiles of a sphere (equator and across) -> CSV + PNG (docs/moon.md).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>

#include "app/cmd_moon.hpp"
#include "app/commands.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "core/log.hpp"
#include "moon/plot.hpp"

namespace fs = std::filesystem;

namespace shadelab::app::moon_cli {

namespace {

struct CurveArgs {
    ModelArgs model;
    double phase = 0.0;
    int samples = 401;
    double across_offset = 0.0;
    std::string output = "out/moon/curve.csv";
    std::string plot;
    bool no_plot = false;
};

void run_curve(const CurveArgs& a) {
    const SunGeometry sun = sun_geometry(a.phase, 0.0);
    const auto models = a.model.expand();
    std::vector<std::vector<CurvePoint>> eq, ac;
    for (const auto& m : models) {
        eq.push_back(equator_curve(m, sun, a.samples));
        ac.push_back(across_curve(m, sun, a.across_offset, a.samples));
    }
    std::vector<std::string> cols{"profile", "s", "lambda_deg", "beta_deg", "mu0", "mu"};
    std::vector<std::string> value_cols, labels;
    for (const auto& m : models) {
        value_cols.push_back(column_name(m));
        labels.push_back(m.describe());
        cols.push_back(value_cols.back());
    }
    CsvTable t(cols);
    for (int which = 0; which < 2; ++which) {
        const auto& curves = which == 0 ? eq : ac;
        for (std::size_t j = 0; j < curves[0].size(); ++j) {
            const CurvePoint& c = curves[0][j];
            t.row().add(which == 0 ? "equator" : "across").add(c.s).add(c.lambda_deg).add(c.beta_deg).add(c.mu0).add(c.mu);
            for (const auto& cv : curves) t.add(cv[j].value);
        }
    }
    t.write(a.output);
    std::cout << a.output << "\n";

    // A few numbers to read without opening the table: the equator at s = -0.9 ... 0.9.
    shadelab::log_out() << "phase " << a.phase << " deg; terminator on the equator at s = " << num(-std::cos(a.phase * kDeg), 4)
              << " (disc radii, + towards the sun); " << a.samples << " samples per profile\n";
    shadelab::log_out() << std::left << std::setw(34) << "equator I/F at s =";
    const double at[] = {-0.9, -0.5, 0.0, 0.5, 0.9};
    for (double s : at) shadelab::log_out() << std::setw(11) << num(s, 2);
    shadelab::log_out() << "\n";
    for (std::size_t m = 0; m < models.size(); ++m) {
        shadelab::log_out() << "  " << std::setw(32) << labels[m];
        for (double s : at) {
            const glm::dvec3 N = s * sun.u + std::sqrt(1 - s * s) * sun.V;
            shadelab::log_out() << std::setw(11) << num(models[m].value(N, sun), 5);
        }
        shadelab::log_out() << "\n";
    }
    if (!a.no_plot) {
        const std::string png = png_for(a.output, a.plot);
        plot_curves(a.output, png, value_cols, labels,
                    "Analytic disc profiles at phase " + num(a.phase) + " deg");
        std::cout << png << "\n";
    }
}

}  // namespace

void add_curve(CLI::App* moon) {
    auto a = std::make_shared<CurveArgs>();
    auto* c = moon->add_subcommand("curve", "Analytic intensity profiles of a sphere (equator and across) -> CSV + PNG");
    a->model.add_to(c, true);
    c->add_option("--phase", a->phase, "Phase angle in degrees, [0, 180]")->capture_default_str();
    c->add_option("--samples", a->samples, "Points per profile")->capture_default_str();
    c->add_option("--across-offset", a->across_offset,
                  "Where the across profile crosses the equator, disc radii (+ towards the sun)")->capture_default_str();
    c->add_option("-o,--output", a->output, "CSV file")->capture_default_str();
    c->add_option("--plot", a->plot, "PNG file (default: the CSV's name with .png)");
    c->add_flag("--no-plot", a->no_plot, "Write the CSV only");
    c->callback([a] { run_curve(*a); });
}

}  // namespace shadelab::app::moon_cli
