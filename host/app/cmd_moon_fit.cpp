// shadelab moon fit: Minnaert fits of k and B0 on disc images, per image, per longitude bin, per cell (docs/moon.md).
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
#include "core/text.hpp"
#include "moon/fit.hpp"
#include "moon/plot.hpp"

namespace fs = std::filesystem;

namespace shadelab::app::moon_cli {

namespace {

struct FitArgs {
    std::vector<std::string> images;
    GeometryArgs geo;
    double mu_min = 0.2, mu0_min = 0.2;
    std::size_t min_pixels = 50;
    std::string method = "minnaert-plot";
    int bins = 0;
    int grid = 0;
    bool free_b0 = false;
    std::string output = "out/moon/fit.csv";
    bool no_plot = false;
    std::string law = "minnaert", free;   // Hapke: moon/fit.hpp fit_hapke_disc
    std::vector<std::string> params;
};

void print_fit(const MinnaertFit& f) {
    std::cout << "  k  = " << num(f.k, 7) << " +- " << num(f.se_k, 3) << "\n"
              << "  B0 = " << num(f.B0, 7) << " +- " << num(f.se_B0, 3) << "\n"
              << "  rms residual of ln(mu I) " << num(f.rms, 3) << ", rms relative residual " << num(f.rms_rel, 3) << "\n"
              << "  pixels used " << f.used << " of " << f.candidates << " on the disc (" << f.below_thresholds
              << " outside the thresholds, " << f.non_positive << " with I <= 0); ln(mu mu0) from "
              << num(f.x_min, 4) << " to " << num(f.x_max, 4) << "\n";
    std::cout << "  noise of I from neighbouring pixels: sigma " << num(f.noise_sigma, 3);
    if (f.bias_k != 0.0 || f.bias_ln_B0 != 0.0)
        std::cout << "; the logarithms' bias at that noise (second order): k " << num(f.bias_k, 2) << ", B0 "
                  << num(std::expm1(f.bias_ln_B0) * 100.0, 2) << "%";
    std::cout << "\n";
    for (const auto& w : f.warnings) shadelab::log_out() << "warning: " << w << "\n";
}

struct FitRow {
    double phase, k, se_k, B0, se_B0;
};

// k in bins of photometric longitude (B0 held at the whole-disc value unless --free-b0), table and chart.
void fit_bins(const FitArgs& a, const std::vector<DiscPixel>& pixels, const SunGeometry& sun, const FitOptions& local,
              const std::string& stem, const std::string& tag, const std::string& b0_note) {
    const auto bins = fit_longitude_bins(pixels, sun, local, a.bins);
    CsvTable bt({"bin", "lambda_lo", "lambda_hi", "lambda_mid", "k", "se_k", "B0", "se_B0", "pixels", "note"});
    std::cout << "  k in " << a.bins << " bins of photometric longitude (" << b0_note << "):\n";
    for (const auto& b : bins) {
        bt.row().add(double(b.i)).add(b.lo).add(b.hi).add(0.5 * (b.lo + b.hi));
        if (b.ok) {
            bt.add(b.fit.k).add(b.fit.se_k).add(b.fit.B0).add(b.fit.se_B0).add(double(b.fit.used)).add("");
            std::cout << "    lambda " << std::setw(8) << num(b.lo, 4) << " .. " << std::setw(8) << num(b.hi, 4)
                      << "  k = " << num(b.fit.k, 5) << " +- " << num(b.fit.se_k, 2) << "  (" << b.fit.used
                      << " px)\n";
        } else {
            bt.blank().blank().blank().blank().blank().add(b.why);
            std::cout << "    lambda " << std::setw(8) << num(b.lo, 4) << " .. " << std::setw(8) << num(b.hi, 4)
                      << "  no fit: " << b.why << "\n";
        }
    }
    const std::string bcsv = stem + "-bins" + tag + ".csv";
    bt.write(bcsv);
    std::cout << bcsv << "\n";
    if (!a.no_plot) {
        plot_errorbars(bcsv, stem + "-bins" + tag + ".png", "lambda_mid", "k", "se_k",
                       "photometric longitude (deg, + towards the sun)", "Minnaert k",
                       "Minnaert k by photometric longitude, phase " + num(sun.phase_deg) + " deg (" + b0_note + ")");
        std::cout << stem + "-bins" + tag + ".png" << "\n";
    }
}

// k in the cells of an NxN grid over the disc: the k map, table and chart.
void fit_kmap(const FitArgs& a, const std::vector<DiscPixel>& pixels, const SunGeometry& sun, const FitOptions& local,
              const std::string& stem, const std::string& tag, const std::string& b0_note) {
    const auto cells = fit_grid(pixels, sun, local, a.grid);
    CsvTable gt({"i", "j", "X", "Y", "k", "se_k", "B0", "pixels", "note"});
    std::size_t fitted = 0;
    for (const auto& c : cells) {
        gt.row().add(double(c.i)).add(double(c.j)).add(c.X).add(c.Y);
        if (c.ok) {
            ++fitted;
            gt.add(c.fit.k).add(c.fit.se_k).add(c.fit.B0).add(double(c.fit.used)).add("");
        } else {
            gt.blank().blank().blank().blank().add(c.why);
        }
    }
    const std::string gcsv = stem + "-kmap" + tag + ".csv";
    gt.write(gcsv);
    std::cout << "  k map: " << fitted << " of " << cells.size() << " cells fitted (" << b0_note << ")\n" << gcsv << "\n";
    if (!a.no_plot) {
        plot_k_map(gcsv, stem + "-kmap" + tag + ".png", a.grid,
                   "Minnaert k map, phase " + num(sun.phase_deg) + " deg (" + std::to_string(a.grid) + "x" +
                       std::to_string(a.grid) + " cells)");
        std::cout << stem + "-kmap" + tag + ".png" << "\n";
    }
}

// Image i of n: the whole-disc fit (a summary row), its Minnaert plot points, then bins and cells.
MinnaertFit fit_image(const FitArgs& a, const FitOptions& o, std::size_t i, CsvTable& summary,
                      std::vector<std::pair<std::string, MinnaertFit>>& plots, std::vector<FitRow>& rows) {
    const std::size_t n = a.images.size();
    const std::string stem = stem_of(a.output);
    const LoadedImage li = load(a.images[i], a.geo, i, n);
    const SunGeometry& sun = li.geo.sun;
    const auto pixels = disc_pixels(li.img, li.geo.disc, sun, a.geo.allow_partial);
    std::cout << "image " << a.images[i] << ": " << geometry_text(li.geo) << "\n"
              << "Minnaert fit I = B0 mu0^k mu^(k-1) over mu >= " << o.mu_min << ", mu0 >= " << o.mu0_min
              << ": " << to_string(o.method) << "\n";
    const MinnaertFit f = fit_minnaert(pixels, sun, o);
    print_fit(f);
    rows.push_back({sun.phase_deg, f.k, f.se_k, f.B0, f.se_B0});
    summary.row().add(a.images[i]).add(sun.phase_deg).add(sun.pa_deg).add(f.k).add(f.se_k).add(f.B0).add(f.se_B0)
        .add(f.rms).add(f.rms_rel).add(double(f.used));

    const std::string tag = n == 1 ? "" : "-" + std::to_string(i + 1);
    const std::string plot_csv = stem + "-minnaert" + tag + ".csv";
    CsvTable pts({"x", "y"});
    for (const auto& p : minnaert_plot_points(pixels, o)) pts.row().add(p.x).add(p.y);
    pts.write(plot_csv);
    std::cout << plot_csv << "\n";
    plots.push_back({plot_csv, f});

    // Bins and cells: k alone, with B0 held at the whole-disc value (unless --free-b0).
    FitOptions local = o;
    if (!a.free_b0) local.fixed_ln_B0 = f.ln_B0;
    const std::string b0_note = a.free_b0 ? "k and B0 free in each" : "B0 held at " + num(f.B0, 6);
    if (a.bins > 0) fit_bins(a, pixels, sun, local, stem, tag, b0_note);
    if (a.grid > 0) fit_kmap(a, pixels, sun, local, stem, tag, b0_note);
    return f;
}

void run_fit(const FitArgs& a) {
    FitOptions o;
    o.mu_min = a.mu_min;
    o.mu0_min = a.mu0_min;
    o.min_pixels = a.min_pixels;
    o.method = parse_fit_method(a.method);
    check_fit_options(o);
    const std::string stem = stem_of(a.output);
    const std::size_t n = a.images.size();
    if (a.law == "minnaert" && (!a.params.empty() || !a.free.empty()))
        throw Error("moon fit: -p and --free go with a Hapke law (--law hapke_hen); the Minnaert fit has k and B0");
    if (a.law != "minnaert" && (a.bins > 0 || a.grid > 0))
        throw Error("moon fit: --bins and --grid are Minnaert k maps; they do not go with --law " + a.law);
    if (a.law != "minnaert") {   // a Hapke law, fitted to each image (moon/fit.hpp says what one image determines)
        photometry::FitSpec spec{a.law, {}, a.free.empty() ? std::vector<std::string>{} : split(a.free, ',')};
        for (const auto& p : a.params) spec.start.insert(parse_param(p));
        Runtime rt;
        for (std::size_t i = 0; i < n; ++i) {
            const LoadedImage li = load(a.images[i], a.geo, i, n);
            const auto pixels = disc_pixels(li.img, li.geo.disc, li.geo.sun, a.geo.allow_partial);
            std::cout << "image " << a.images[i] << ": " << geometry_text(li.geo) << "\n"
                      << describe_hapke_disc_fit(fit_hapke_disc(rt, pixels, li.geo.sun, o, spec), li.geo.sun);
        }
        return;
    }
    CsvTable summary({"image", "phase_deg", "pa_deg", "k", "se_k", "B0", "se_B0", "rms_ln", "rms_rel", "pixels"});
    std::vector<std::pair<std::string, MinnaertFit>> plots;
    std::vector<FitRow> rows;
    for (std::size_t i = 0; i < n; ++i) fit_image(a, o, i, summary, plots, rows);
    summary.write(a.output);
    if (n > 1) {
        std::cout << "summary (one fit per image):\n  " << std::left << std::setw(10) << "phase" << std::setw(22) << "k"
                  << "B0\n";
        for (const auto& r : rows)
            std::cout << "  " << std::setw(10) << num(r.phase, 5) << std::setw(22) << (num(r.k, 6) + " +- " + num(r.se_k, 2))
                      << num(r.B0, 6) << " +- " << num(r.se_B0, 2) << "\n";
    }
    std::cout << a.output << "\n";
    if (n > 1 && !a.no_plot) {
        const std::string png = stem + "-phase.png";
        plot_errorbars(a.output, png, "phase_deg", "k", "se_k", "phase angle (deg)", "Minnaert k",
                       "Minnaert k against phase (" + std::to_string(n) + " images)");
        std::cout << png << "\n";
    }
    if (!a.no_plot) {
        for (std::size_t i = 0; i < plots.size(); ++i) {
            const std::string png = stem_of(plots[i].first) + ".png";
            plot_minnaert(plots[i].first, png, plots[i].second,
                          "Minnaert plot: " + fs::path(a.images[i]).filename().string());
            std::cout << png << "\n";
        }
    }
}

}  // namespace

void add_fit(CLI::App* moon) {
    auto a = std::make_shared<FitArgs>();
    auto* c = moon->add_subcommand("fit", "Minnaert fit of k and B0 on disc image(s): ln(mu I) = ln B0 + k ln(mu mu0)");
    c->add_option("images", a->images, "Disc image(s): .png .tif .exr .fits")->required();
    a->geo.add_to(c);
    c->add_option("--mu-min", a->mu_min, "Keep the limb out: use pixels with mu >= this")->capture_default_str();
    c->add_option("--mu0-min", a->mu0_min, "Keep the terminator out: use pixels with mu0 >= this")->capture_default_str();
    c->add_option("--min-pixels", a->min_pixels, "Refuse fits with fewer pixels")->capture_default_str();
    c->add_option("--method", a->method,
                  "minnaert-plot (least squares on ln(mu I) vs ln(mu mu0)), weighted (the same, weights "
                  "I_model^2), intensity (least squares on I: unbiased under noise)")
        ->capture_default_str();
    c->add_option("--bins", a->bins, "Also fit k in this many bins of photometric longitude")->capture_default_str();
    c->add_option("--grid", a->grid, "Also fit k in the cells of an NxN grid over the disc (a k map)")
        ->capture_default_str();
    c->add_flag("--free-b0", a->free_b0, "Fit B0 as well in each bin/cell (default: hold the whole-disc B0)");
    c->add_option("--law", a->law, "minnaert, or a Hapke law (hapke_hen, hapke_leg, hapke_2012) fitted on I")->capture_default_str();
    c->add_option("--free", a->free, "Hapke: parameters to fit (default wh,theta,hg1; bh for hapke_leg)");
    c->add_option("-p,--param", a->params, "Hapke: start / held value NAME=VALUE (repeatable)");
    c->add_option("-o,--output", a->output, "Summary CSV; the Minnaert plot goes to <name>-minnaert.csv/.png")
        ->capture_default_str();
    c->add_flag("--no-plot", a->no_plot, "Write the CSVs only");
    c->callback([a] { run_fit(*a); });
}

}  // namespace shadelab::app::moon_cli
