// shadelab moon profile / compare: profiles of a disc image, alone or against a model (docs/moon.md).
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
#include "moon/fit.hpp"
#include "moon/plot.hpp"

namespace fs = std::filesystem;

namespace shadelab::app::moon_cli {

namespace {

struct ProfileArgs {
    std::string image;
    GeometryArgs geo;
    double across_offset = 0.0;
    std::string output = "out/moon/profile.csv";
    std::string plot;
    std::string pixels_csv;
    bool no_plot = false;
    // compare only
    ModelArgs model;
    double mu_min = 0.05, mu0_min = 0.05;
};

void add_profile_rows(CsvTable& t, const char* name, const std::vector<ProfilePixel>& prof, const PhotometricModel* m,
                      const SunGeometry& sun, double mu_min, double mu0_min) {
    for (const ProfilePixel& pp : prof) {
        const DiscPixel& p = pp.p;
        t.row().add(name).add(pp.s).add(pp.offset).add(double(p.x)).add(double(p.y)).add(p.a.lambda_deg).add(p.a.beta_deg)
            .add(p.a.i_deg).add(p.a.e_deg).add(p.a.g_deg).add(p.a.mu0).add(p.a.mu).add(p.I);
        if (m) {
            const glm::dvec3 N{p.X, p.Y, std::sqrt(std::max(0.0, 1.0 - p.X * p.X - p.Y * p.Y))};
            const double v = m->value(N, sun);
            t.add(v);
            if (p.a.mu >= mu_min && p.a.mu0 >= mu0_min && v > 0.0)
                t.add((p.I - v) / v, 6);
            else
                t.blank();
        }
    }
}

void print_comparison(const char* what, const Comparison& c) {
    std::cout << std::left << std::setw(10) << what << " pixels " << std::setw(7) << c.n << " max abs err "
              << std::setw(12) << num(c.max_abs, 4) << " max rel err " << std::setw(12) << num(c.max_rel, 4)
              << " rms rel err " << num(c.rms_rel, 4) << "\n";
}

Comparison compare_profile(const std::vector<ProfilePixel>& prof, const PhotometricModel& m, const SunGeometry& sun,
                           double mu_min, double mu0_min) {
    std::vector<DiscPixel> px;
    for (const auto& pp : prof) px.push_back(pp.p);
    return compare_pixels(px, m, sun, mu_min, mu0_min);
}

void run_profile(const ProfileArgs& a, bool compare) {
    const LoadedImage li = load(a.image, a.geo, 0, 1);
    const SunGeometry& sun = li.geo.sun;
    const auto eq = equator_profile(li.img, li.geo.disc, sun, a.geo.allow_partial);
    const auto ac = across_profile(li.img, li.geo.disc, sun, a.across_offset, a.geo.allow_partial);
    std::unique_ptr<PhotometricModel> model;
    if (compare) {
        const auto ms = a.model.expand();
        if (ms.size() != 1) throw Error("moon compare takes one model (one --model, one --k, one --lunar-l)");
        model = std::make_unique<PhotometricModel>(ms[0]);
        if (!std::isfinite(a.mu_min) || a.mu_min < 0 || a.mu_min >= 1 || !std::isfinite(a.mu0_min) || a.mu0_min < 0 ||
            a.mu0_min >= 1)
            throw Error("--mu-min and --mu0-min must be in [0, 1)");
    }
    std::vector<std::string> cols{"profile", "s", "offset", "x", "y", "lambda_deg", "beta_deg", "i_deg",
                                  "e_deg", "g_deg", "mu0", "mu", "I"};
    if (compare) {
        cols.push_back("model");
        cols.push_back("rel_err");
    }
    CsvTable t(cols);
    add_profile_rows(t, "equator", eq, model.get(), sun, a.mu_min, a.mu0_min);
    add_profile_rows(t, "across", ac, model.get(), sun, a.mu_min, a.mu0_min);
    t.write(a.output);
    shadelab::log_out() << "image " << a.image << " (" << li.img.width << "x" << li.img.height << "): " << geometry_text(li.geo)
              << "\n";
    shadelab::log_out() << "equator profile " << eq.size() << " pixels, across profile " << ac.size()
              << " pixels (nearest pixel to each 1-px step, exact geometry at its centre)\n";
    if (!a.pixels_csv.empty()) {
        const auto all = disc_pixels(li.img, li.geo.disc, sun, a.geo.allow_partial);
        CsvTable p({"x", "y", "X", "Y", "lambda_deg", "beta_deg", "i_deg", "e_deg", "g_deg", "mu0", "mu", "I"});
        for (const DiscPixel& d : all)
            p.row().add(double(d.x)).add(double(d.y)).add(d.X).add(d.Y).add(d.a.lambda_deg).add(d.a.beta_deg).add(d.a.i_deg)
                .add(d.a.e_deg).add(d.a.g_deg).add(d.a.mu0).add(d.a.mu).add(d.I);
        p.write(a.pixels_csv);
        std::cout << a.pixels_csv << "\n";
    }
    if (compare) {
        std::cout << "model " << model->describe() << "; errors over mu >= " << a.mu_min << ", mu0 >= " << a.mu0_min
                  << " (relative to the model)\n";
        print_comparison("equator", compare_profile(eq, *model, sun, a.mu_min, a.mu0_min));
        print_comparison("across", compare_profile(ac, *model, sun, a.mu_min, a.mu0_min));
        const auto all = disc_pixels(li.img, li.geo.disc, sun, a.geo.allow_partial);
        const Comparison c = compare_pixels(all, *model, sun, a.mu_min, a.mu0_min);
        print_comparison("disc", c);
        std::cout << "worst pixel at X = " << num(c.worst_X, 4) << ", Y = " << num(c.worst_Y, 4) << " disc radii\n";
    }
    std::cout << a.output << "\n";
    if (!a.no_plot) {
        const std::string png = png_for(a.output, a.plot);
        plot_profiles(a.output, png, compare,
                      (compare ? "Image against " + model->describe() : "Profiles of " + fs::path(a.image).filename().string()) +
                          " (" + geometry_text(li.geo) + ")");
        std::cout << png << "\n";
    }
}

}  // namespace

void add_profile(CLI::App* moon, bool compare) {
    auto a = std::make_shared<ProfileArgs>();
    auto* c = compare
                  ? moon->add_subcommand("compare", "Profiles of a disc image against a model at the same geometry, "
                                                    "with the error as numbers and a plot")
                  : moon->add_subcommand("profile", "Profiles (equator and across) of a disc image with per-pixel "
                                                    "geometry (i, e, g, mu0, mu) -> CSV + PNG");
    c->add_option("image", a->image, "Disc image: .png .tif .exr .fits")->required();
    a->geo.add_to(c);
    c->add_option("--across-offset", a->across_offset, "Where the across profile crosses the equator (disc radii)")
        ->capture_default_str();
    if (compare) {
        a->output = "out/moon/compare.csv";
        a->model.models = {"minnaert"};
        a->model.add_to(c, false);
        c->add_option("--mu-min", a->mu_min, "Errors only where mu >= this")->capture_default_str();
        c->add_option("--mu0-min", a->mu0_min, "Errors only where mu0 >= this")->capture_default_str();
    }
    c->add_option("-o,--output", a->output, "CSV file")->capture_default_str();
    c->add_option("--plot", a->plot, "PNG file (default: the CSV's name with .png)");
    c->add_option("--pixels", a->pixels_csv, "Also write every disc pixel with its geometry to this CSV");
    c->add_flag("--no-plot", a->no_plot, "Write the CSV only");
    c->callback([a, compare] { run_profile(*a, compare); });
}

}  // namespace shadelab::app::moon_cli
