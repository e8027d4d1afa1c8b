// shadelab moon: lunar limb darkening - analytic curves, rendered discs, profiles, Minnaert fits, comparisons.
// The work is in host/moon/; this file turns options into calls and prints results. docs/moon.md is the manual.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "app/commands.hpp"
#include "cl/runtime.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/limits.hpp"
#include "core/text.hpp"
#include "models/catalogue.hpp"
#include "moon/disc.hpp"
#include "moon/fit.hpp"
#include "image/fits.hpp"
#include "moon/photometry.hpp"
#include "moon/plot.hpp"

namespace fs = std::filesystem;

namespace shadelab::app {

namespace {

using namespace shadelab::moon;

std::string num(double x, int digits = 6) {
    std::ostringstream s;
    s << std::setprecision(digits) << x;
    return s.str();
}

// "out/a.csv" -> "out/a" (the stem other outputs are named after).
std::string stem_of(const std::string& path) {
    const fs::path p(path);
    return (p.parent_path() / p.stem()).string();
}

std::string png_for(const std::string& csv, const std::string& explicit_png, const std::string& suffix = "") {
    return explicit_png.empty() ? stem_of(csv) + suffix + ".png" : explicit_png;
}

void parse_size(const std::string& s, int& w, int& h) {
    int a = 0, b = 0;
    char x = 0, extra = 0;
    if (std::sscanf(s.c_str(), "%d%c%d%c", &a, &x, &b, &extra) != 3 || (x != 'x' && x != 'X'))
        throw Error("--size expects WIDTHxHEIGHT such as 512x512, got '" + s + "'");
    if (a < 8 || b < 8 || a > 16384 || b > 16384) throw Error("--size " + s + ": each side must be in [8, 16384]");
    w = a;
    h = b;
}

glm::dvec2 parse_centre(const std::string& text) {
    double x = 0, y = 0;
    char c = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%lf%c%lf%c", &x, &c, &y, &extra) != 3 || c != ',' || !std::isfinite(x) ||
        !std::isfinite(y))
        throw Error("--centre expects x,y in pixels (pixel (i, j) is centred at (i + 0.5, j + 0.5)), got '" + text + "'");
    return {x, y};
}

std::map<std::string, double> parse_params(const std::vector<std::string>& ps) {
    std::map<std::string, double> out;
    for (const auto& p : ps) {
        const auto kv = parse_param(p);
        out[kv.first] = kv.second;
    }
    return out;
}

// ---------------------------------------------------------------- the disc's geometry on an image

// Options shared by the commands that read an image. Each may hold one value (for every image) or one per
// image; a FITS image written by `moon render` carries its own (keywords PHASE, POSANG, CENTX, CENTY, RADIUS)
// and those are used for what the command line leaves out.
struct GeometryArgs {
    std::vector<double> phase, pa, radius;
    std::vector<std::string> centre;
    bool allow_partial = false;

    void add_to(CLI::App* cmd) {
        cmd->add_option("--phase", phase, "Phase angle(s) in degrees, [0, 180]")->delimiter(',');
        cmd->add_option("--pa", pa, "Position angle(s) of the sun direction, degrees from image up (north) towards "
                                    "image left (east)")->delimiter(',');
        cmd->add_option("--centre,--center", centre, "Disc centre x,y in pixels (repeat per image)");
        cmd->add_option("--radius", radius, "Disc radius in pixels (one, or one per image)")->delimiter(',');
        cmd->add_flag("--allow-partial", allow_partial, "Accept a disc that extends past the image edge");
    }
};

struct ImageGeometry {
    Disc disc;
    SunGeometry sun;
    std::vector<std::string> from_header;   // what came from the FITS header
};

template <typename T>
const T* pick(const std::vector<T>& v, std::size_t i, std::size_t n, const std::string& option) {
    if (v.empty()) return nullptr;
    if (v.size() == 1) return &v[0];
    if (v.size() != n)
        throw Error(option + " has " + std::to_string(v.size()) + " values for " + std::to_string(n) +
                    " images: give one value, or one per image");
    return &v[i];
}

double header_number(const std::map<std::string, std::string>& kw, const std::string& key, const std::string& image,
                     const std::string& option) {
    auto it = kw.find(key);
    if (it == kw.end())
        throw Error("image '" + image + "': give " + option + " (it is not in the image" +
                    (kw.empty() ? std::string(")") : std::string("'s FITS header)")));
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (it->second.empty() || *end != '\0' || !std::isfinite(v))
        throw Error("image '" + image + "': FITS keyword " + key + " = '" + it->second + "' is not a number");
    return v;
}

ImageGeometry resolve_geometry(const GeometryArgs& g, std::size_t i, std::size_t n, const std::string& image,
                               const std::map<std::string, std::string>& kw) {
    ImageGeometry out;
    auto value = [&](const std::vector<double>& v, const char* option, const char* key) {
        if (const double* p = pick(v, i, n, option)) return *p;
        out.from_header.push_back(std::string(key));
        return header_number(kw, key, image, option);
    };
    const double phase = value(g.phase, "--phase", "PHASE");
    const double pa = value(g.pa, "--pa", "POSANG");
    out.disc.radius = value(g.radius, "--radius", "RADIUS");
    if (const std::string* c = pick(g.centre, i, n, "--centre")) {
        const glm::dvec2 cc = parse_centre(*c);
        out.disc.cx = cc.x;
        out.disc.cy = cc.y;
    } else {
        out.disc.cx = header_number(kw, "CENTX", image, "--centre");
        out.disc.cy = header_number(kw, "CENTY", image, "--centre");
        out.from_header.push_back("CENTX/CENTY");
    }
    out.sun = sun_geometry(phase, pa);
    return out;
}

struct LoadedImage {
    Image img;
    ImageGeometry geo;
};

LoadedImage load(const std::string& path, const GeometryArgs& g, std::size_t i, std::size_t n) {
    std::map<std::string, std::string> kw;
    LoadedImage li;
    li.img = read_any_image(path, &kw);
    li.geo = resolve_geometry(g, i, n, path, kw);
    check_disc(li.geo.disc, li.img.width, li.img.height, g.allow_partial);
    if (!li.geo.from_header.empty()) {
        shadelab::log_out() << "image " << path << ": from its FITS header:";
        for (const auto& k : li.geo.from_header) shadelab::log_out() << " " << k;
        shadelab::log_out() << "\n";
    }
    return li;
}

std::string geometry_text(const ImageGeometry& g) {
    return "phase " + num(g.sun.phase_deg) + " deg, pa " + num(g.sun.pa_deg) + " deg, centre (" + num(g.disc.cx) +
           ", " + num(g.disc.cy) + ") px, radius " + num(g.disc.radius) + " px";
}

// ---------------------------------------------------------------- models named on the command line

struct ModelArgs {
    std::vector<std::string> models{"minnaert"};
    std::vector<double> k{0.7};
    std::vector<double> lunar_l{0.5};
    std::vector<std::string> params;
    double albedo = 1.0;

    void add_to(CLI::App* cmd, bool many) {
        auto* m = cmd->add_option("-m,--model", models,
                                  "minnaert (1941, --k), lambert, lommel_seeliger, lunar_lambert (--lunar-l), or a "
                                  "catalogue model (see 'shadelab models') evaluated by its double reference");
        if (many) m->delimiter(',');
        m->capture_default_str();
        auto* ko = cmd->add_option("--k", k, "Minnaert 1941 k (closed form 'minnaert')");
        auto* lo = cmd->add_option("--lunar-l", lunar_l, "McEwen's Lunar-Lambert L in [0, 1]");
        if (many) {
            ko->delimiter(',');
            lo->delimiter(',');
        }
        ko->capture_default_str();
        lo->capture_default_str();
        cmd->add_option("-p,--param", params, "Catalogue model parameter name=value (repeatable)");
        cmd->add_option("--albedo,--b0", albedo, "B0 of the closed forms; grey albedo of catalogue models")
            ->capture_default_str();
    }

    // Every (model, k or L) combination.
    std::vector<PhotometricModel> expand() const {
        std::vector<PhotometricModel> out;
        const auto ps = parse_params(params);
        for (const auto& name : models) {
            std::string n = name;
            std::replace(n.begin(), n.end(), '-', '_');
            if (n == "minnaert")
                for (double kk : k) out.push_back(make_photometric_model(n, kk, 0.0, albedo));
            else if (n == "lunar_lambert")
                for (double l : lunar_l) out.push_back(make_photometric_model(n, 0.0, l, albedo));
            else
                out.push_back(make_photometric_model(name, 0.0, 0.0, albedo,
                                                     n == "lambert" || n == "lommel_seeliger" ? decltype(ps){} : ps));
        }
        return out;
    }
};

std::string column_name(const PhotometricModel& m) {
    if (m.kind == "minnaert") return "I_minnaert_k" + num(m.k);
    if (m.kind == "lunar_lambert") return "I_lunar_lambert_L" + num(m.lunar_l);
    if (m.kind == "catalogue") return "I_" + m.material.model;
    return "I_" + m.kind;
}

// ---------------------------------------------------------------- moon curve

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

// ---------------------------------------------------------------- moon render

struct RenderArgs {
    std::string model = "minnaert_1941";
    std::vector<std::string> params;
    double k = 0.7, lunar_l = 0.5;
    double albedo = 1.0;
    double phase = 0.0, pa = 0.0;
    std::string size = "512x512";
    std::string centre;
    std::string radius;                // empty: 0.45 of the smaller side
    int mesh_level = -1;
    double limb_mask = 0.0;
    double noise = 0.0;
    unsigned long long seed = 1;
    std::string output = "out/moon/disc.exr";
    bool quiet = false;
    std::string max_memory;            // overrides the memory limit (core/limits.hpp)
};

// Peak memory of a disc render per image pixel (geometry per pixel, the shaded values, the float image
// and the writer's copy). Measured (peak RSS over an idle process's, closed-form and catalogue models):
// 44 bytes/pixel at 2048x2048, 47 at 4096x4096; 55 leaves a margin.
constexpr double kDiscBytesPerPixel = 55.0;

void run_render(const RenderArgs& a) {
    DiscRenderOptions o;
    parse_size(a.size, o.width, o.height);
    if (!a.max_memory.empty()) set_memory_limit(parse_bytes(a.max_memory, "--max-memory"));
    check_memory("--size " + a.size, double(o.width) * double(o.height) * kDiscBytesPerPixel);
    double radius = 0.45 * std::min(o.width, o.height);
    if (!a.radius.empty()) {
        // Given, it is used or refused: never replaced by the default without a word.
        char* end = nullptr;
        radius = std::strtod(a.radius.c_str(), &end);
        if (*end != '\0' || !std::isfinite(radius) || !(radius > 0.0))
            throw Error("--radius '" + a.radius + "': the disc radius must be a finite number of pixels > 0 "
                        "(leave it out for 0.45 of the smaller side)");
    }
    in_range(a.albedo, "--albedo", 0.0, kMaxColour);
    o.disc = Disc{0.5 * o.width, 0.5 * o.height, radius};
    if (!a.centre.empty()) {
        const glm::dvec2 c = parse_centre(a.centre);
        o.disc.cx = c.x;
        o.disc.cy = c.y;
    }
    check_disc(o.disc, o.width, o.height, false);
    // The closed-form laws that are not catalogue models are drawn in double without a kernel.
    std::string law_name = a.model;
    std::replace(law_name.begin(), law_name.end(), '-', '_');
    const bool law = law_name == "minnaert" || law_name == "lommel_seeliger" || law_name == "lunar_lambert";
    PhotometricModel law_model;
    if (law) {
        law_model = make_photometric_model(law_name, a.k, a.lunar_l, a.albedo, parse_params(a.params));
    } else {
        Material mat;
        mat.model = a.model;
        mat.params = parse_params(a.params);
        mat.albedo = glm::dvec3(a.albedo);
        o.material = resolve_material(mat, "--model " + a.model);
    }
    o.sun = sun_geometry(a.phase, a.pa);
    o.mesh_level = a.mesh_level;
    o.limb_mask_mu = a.limb_mask;
    o.noise_sigma = a.noise;
    o.noise_seed = a.seed;
    if (!is_fits_path(a.output)) encoding_for(a.output);   // reject a bad extension before any work

    if (law && o.mesh_level >= 0) throw Error("--mesh needs a catalogue model; '" + a.model + "' is drawn in closed form");
    std::unique_ptr<Runtime> rt;
    DiscRenderReport rep;
    Image img;
    if (law) {
        img = render_law_disc(o, law_model, &rep);
    } else {
        rt = std::make_unique<Runtime>();
        img = render_disc(*rt, o, &rep);
    }
    std::map<std::string, std::string> kw{{"PHASE", num(a.phase, 10)},
                                          {"POSANG", num(a.pa, 10)},
                                          {"CENTX", num(o.disc.cx, 10)},
                                          {"CENTY", num(o.disc.cy, 10)},
                                          {"RADIUS", num(o.disc.radius, 10)},
                                          {"MODEL", a.model},
                                          {"ALBEDO", num(a.albedo, 10)},
                                          {"BUNIT", "I/F"},
                                          {"ORIGIN", "shadelab moon render"}};
    if (law_name == "minnaert") kw["P_K"] = num(a.k, 10);
    if (law_name == "lunar_lambert") kw["P_L"] = num(a.lunar_l, 10);
    for (const auto& [k, v] : o.material.params) {
        std::string key = "P_" + k;
        std::transform(key.begin(), key.end(), key.begin(), [](unsigned char c) { return char(std::toupper(c)); });
        if (key.size() <= 8) kw[key] = num(v, 10);
    }
    write_any_image(a.output, img, kw);
    if (!a.quiet) {
        shadelab::log_out() << "disc: " << o.width << "x" << o.height << ", centre (" << o.disc.cx << ", " << o.disc.cy
                  << ") px, radius " << o.disc.radius << " px; " << rep.method << "\n"
                  << "sun: phase " << a.phase << " deg, pa " << a.pa << " deg, L = (" << num(o.sun.L.x, 5) << ", "
                  << num(o.sun.L.y, 5) << ", " << num(o.sun.L.z, 5) << "); model " << a.model << "\n"
                  << "pixels " << rep.pixels << " (masked at the limb " << rep.masked << "), smallest mu "
                  << num(rep.min_mu, 4) << " (pixels with mu < 0.01: " << rep.limb_pixels << ", < 1e-3: "
                  << rep.guard_pixels << "), largest value " << num(rep.max_value, 6) << "\n"
                  << (rt ? "device " + rt->device_description() + ", build " + num(rep.build_ms, 3) + " ms, kernel " +
                               num(rep.kernel_ms, 3) + " ms\n"
                         : std::string());
        if (rep.guard_pixels > 0)
            shadelab::log_out() << "note: " << rep.guard_pixels << " pixels have mu < 1e-3, where the Minnaert kernels with k < 1 "
                         "replace the diverging mu^(k-1) by their limb guard (docs/models/minnaert.md); "
                         "--limb-mask MU leaves pixels below MU as background\n";
    }
    std::cout << a.output << "\n";
}

// ---------------------------------------------------------------- moon profile / compare

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

// ---------------------------------------------------------------- moon fit

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
    struct Row { double phase, k, se_k, B0, se_B0; };
    std::vector<Row> rows;
    for (std::size_t i = 0; i < n; ++i) {
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
        if (a.bins > 0) {
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
                               "Minnaert k by photometric longitude, phase " + num(sun.phase_deg) + " deg (" +
                                   b0_note + ")");
                std::cout << stem + "-bins" + tag + ".png" << "\n";
            }
        }
        if (a.grid > 0) {
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
            std::cout << "  k map: " << fitted << " of " << cells.size() << " cells fitted (" << b0_note << ")\n"
                      << gcsv << "\n";
            if (!a.no_plot) {
                plot_k_map(gcsv, stem + "-kmap" + tag + ".png", a.grid,
                           "Minnaert k map, phase " + num(sun.phase_deg) + " deg (" + std::to_string(a.grid) + "x" +
                               std::to_string(a.grid) + " cells)");
                std::cout << stem + "-kmap" + tag + ".png" << "\n";
            }
        }
    }
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

// ---------------------------------------------------------------- moon geometry

struct GeometryFigureArgs {
    double phase = 60.0, pa = 30.0, across_offset = 0.0;
    std::string output = "out/moon/geometry.png";
};

}  // namespace

void add_moon_command(CLI::App& app) {
    auto* moon = app.add_subcommand("moon", "Lunar limb darkening: analytic curves, rendered discs, profiles, "
                                            "Minnaert fits (docs/moon.md)");
    moon->require_subcommand(1);

    {
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
    {
        auto a = std::make_shared<RenderArgs>();
        auto* c = moon->add_subcommand("render", "Render a moon disc with a catalogue model -> .exr .png .fits .tif");
        c->add_option("-m,--model", a->model,
                      "A catalogue model (see 'shadelab models'), shaded by its kernel; or minnaert (--k), "
                      "lommel_seeliger, lunar_lambert (--lunar-l), drawn in closed form")->capture_default_str();
        c->add_option("-p,--param", a->params, "Model parameter name=value (repeatable)");
        c->add_option("--k", a->k, "k of the closed-form 'minnaert'")->capture_default_str();
        c->add_option("--lunar-l", a->lunar_l, "L of the closed-form 'lunar_lambert'")->capture_default_str();
        c->add_option("--albedo", a->albedo, "Grey albedo (linear)")->capture_default_str();
        c->add_option("--phase", a->phase, "Phase angle in degrees, [0, 180]")->capture_default_str();
        c->add_option("--pa", a->pa, "Position angle of the sun, degrees from image up towards image left")
            ->capture_default_str();
        c->add_option("--size", a->size, "Image size WIDTHxHEIGHT")->capture_default_str();
        c->add_option("--centre,--center", a->centre, "Disc centre x,y in pixels (default: the image centre)");
        c->add_option("--radius", a->radius, "Disc radius in pixels (default: 0.45 of the smaller side)");
        c->add_option("--max-memory", a->max_memory,
                      "Refuse sizes needing more memory than this (e.g. 32G; default: the machine's memory, or SHADELAB_MAX_MEMORY)");
        c->add_option("--mesh", a->mesh_level,
                      "Render an icosphere of this subdivision level instead of exact sphere normals (-1: exact)")
            ->capture_default_str();
        c->add_option("--limb-mask", a->limb_mask, "Leave pixels with mu below this as background (0: none)")
            ->capture_default_str();
        c->add_option("--noise", a->noise, "Add Gaussian noise of this sigma (I/F units) to the disc")->capture_default_str();
        c->add_option("--seed", a->seed, "Seed of the noise")->capture_default_str();
        c->add_option("-o,--output", a->output, std::string("Output image: ") + kOutputFormats)
            ->capture_default_str();
        c->add_flag("-q,--quiet", a->quiet, "Print only the output path");
        c->callback([a] { run_render(*a); });
    }
    for (bool compare : {false, true}) {
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
    {
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
    {
        auto a = std::make_shared<GeometryFigureArgs>();
        auto* c = moon->add_subcommand("geometry", "Draw the conventions: disc, sun direction, position angle, "
                                                   "terminator, equator -> PNG");
        c->add_option("--phase", a->phase, "Phase angle in degrees")->capture_default_str();
        c->add_option("--pa", a->pa, "Position angle in degrees")->capture_default_str();
        c->add_option("--across-offset", a->across_offset, "Across line offset (disc radii)")->capture_default_str();
        c->add_option("-o,--output", a->output, "PNG file")->capture_default_str();
        c->callback([a] {
            if (!std::isfinite(a->across_offset) || std::abs(a->across_offset) >= 1.0)
                throw Error("--across-offset must be strictly between -1 and 1");
            plot_geometry(a->output, sun_geometry(a->phase, a->pa), a->across_offset);
            std::cout << a->output << "\n";
        });
    }
}

}  // namespace shadelab::app
