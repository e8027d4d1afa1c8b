// shadelab photometry: ISIS3's photometric models at (phase, incidence, emission), from ISIS's own PVL parameter
// files or by catalogue name, on PoCL (docs/photometry.md).
//   photometry eval --pvl FILE --phase G --incidence I --emission E    the value, last number on stdout
//   photometry eval --pvl FILE --csv IN.csv -o OUT.csv                 every row of a table, a `value` column added
//   photometry empirical --pvl HAPKE.pvl --law lunar_lambert ... -o TABLE.pvl   ISIS phoempglobal's tables
//   photometry fit IMG... --phase G,... --radius R --model hapke_hen | --models a,b,c   fits, errors, ranking
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "app/commands.hpp"
#include "cl/runtime.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/text.hpp"
#include "core/atomic_file.hpp"
#include "photometry/csv.hpp"
#include "image/image.hpp"
#include "models/catalogue.hpp"
#include "moon/disc.hpp"
#include "moon/fit.hpp"
#include "photometry/empirical.hpp"
#include "photometry/fit.hpp"
#include "photometry/normalize.hpp"
#include "photometry/isis.hpp"

namespace shadelab::app {

namespace {

struct EvalArgs {
    std::string pvl, model, csv, out, precision = "precise";
    std::vector<std::string> params;
    double phase = NAN, incidence = NAN, emission = NAN;   // NaN: not given
    bool reference = false;
};

photometry::Law law_named(const std::string& pvl, const std::string& model, const std::vector<std::string>& params) {
    if (pvl.empty() == model.empty())
        throw Error("photometry eval: give the law either as --pvl FILE (ISIS's PhotometricModel form) or as --model NAME");
    if (!pvl.empty()) {
        if (!params.empty()) throw Error("photometry eval: -p/--param goes with --model, not with --pvl");
        return photometry::law_from_pvl_file(pvl);
    }
    Material m;
    for (const auto& s : params) add_param(m, s);
    return photometry::law_from_model(model, m.params, m.tables);
}

// The law the command line names (--pvl FILE, or --model NAME with -p), its warnings printed once here.
photometry::Law law_from_args(const std::string& pvl, const std::string& model, const std::vector<std::string>& params) {
    photometry::Law law = law_named(pvl, model, params);
    for (const auto& w : law.warnings) std::cerr << "shadelab: warning: " << w << "\n";
    return law;
}

void run_eval(const EvalArgs& a) {
    const photometry::Law law = law_from_args(a.pvl, a.model, a.params);
    const Precision precision = parse_precision(a.precision);
    const bool single = !std::isnan(a.phase) || !std::isnan(a.incidence) || !std::isnan(a.emission);
    if (single == !a.csv.empty())
        throw Error("photometry eval: give either --phase, --incidence and --emission (one geometry) or --csv IN.csv -o OUT.csv");
    if (single) {
        if (std::isnan(a.phase) || std::isnan(a.incidence) || std::isnan(a.emission))
            throw Error("photometry eval: --phase, --incidence and --emission are all needed (degrees, 0 to 180)");
        const std::pair<const char*, double> given[] = {
            {"--phase", a.phase}, {"--incidence", a.incidence}, {"--emission", a.emission}};
        for (const auto& [opt, v] : given)
            if (!std::isfinite(v) || v < 0.0 || v > 180.0) {
                std::ostringstream m;
                m << "photometry eval: " << opt << " " << v << " is out of range: allowed 0 to 180 degrees";
                throw Error(m.str());
            }
    }
    Runtime rt;
    log_out() << "law: " << law.describe() << "\n";
    if (single) {
        const photometry::Geometry g{a.phase, a.incidence, a.emission};
        const double v = photometry::evaluate(rt, law, {g}, precision)[0];
        log_out() << "geometry: phase " << g.phase << " deg, incidence " << g.incidence << " deg, emission "
                  << g.emission << " deg\n";
        if (a.reference)
            std::cout << "reference (double): " << std::setprecision(12) << photometry::evaluate_reference(law, g) << "\n";
        log_out() << "device: " << rt.device_description() << ", " << precision_name(precision) << " mode\n";
        std::cout << "value: " << std::setprecision(9) << v << "\n";
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
    log_out() << "rows: " << t.geometry.size() << " (read " << s(t1 - t0) << " s, evaluate " << s(t2 - t1)
              << " s incl. kernel build, write " << s(t3 - t2) << " s)\n";
    std::cout << a.out << "\n";   // the result on stdout, as every command writes its files
}

struct EmpiricalArgs {
    std::string pvl, model, law = "lunar_lambert", out;
    std::vector<std::string> params;
    photometry::EmpiricalOptions o;
};

void run_empirical(const EmpiricalArgs& a) {
    const photometry::Law hapke = law_from_args(a.pvl, a.model, a.params);
    photometry::EmpiricalOptions o = a.o;
    if (a.law == "lunar_lambert" || a.law == "lunarlambert") o.law = 2;
    else if (a.law == "minnaert") o.law = 1;
    else throw Error("photometry empirical: --law '" + a.law + "' is unknown: use lunar_lambert or minnaert");
    if (a.out.empty()) throw Error("photometry empirical: give the output table with -o TABLE.pvl");
    Runtime rt;
    const photometry::EmpiricalTable t = photometry::fit_empirical(rt, hapke, o);
    for (const auto& w : t.warnings) std::cerr << "shadelab: warning: " << w << "\n";
    std::cout << "law: " << hapke.describe() << "\n"
              << (o.law == 1 ? "Minnaert K(g)" : "Lunar-Lambert L(g)") << " fitted at " << t.rows.size()
              << " phases, " << (o.offset ? "with" : "without") << " an additive offset\n"
              << std::setw(10) << "phase" << std::setw(14) << (o.law == 1 ? "K" : "L") << std::setw(14) << "B"
              << std::setw(14) << "rms" << std::setw(9) << "samples" << "\n";
    for (const auto& r : t.rows)
        std::cout << std::setw(10) << r.phase << std::setw(14) << r.param << std::setw(14) << r.brightness
                  << std::setw(14) << r.rms << std::setw(9) << r.samples << "\n";
    write_text_atomically(a.out, "photometric table", photometry::empirical_pvl(t, o, hapke));
    std::cout << a.out << "\n";   // the result on stdout, as every command writes its files
}

struct NormalizeArgs {
    std::string pvl, model, image, out, backplanes, centre;
    std::vector<std::string> params;
    double phase = NAN, pa = 0.0, radius = 0.0;
    photometry::NormalizeOptions o;
};

void run_normalize(const NormalizeArgs& a) {
    const photometry::Law law = law_from_args(a.pvl, a.model, a.params);
    photometry::check_normalize_options(a.o);
    if (a.out.empty()) throw Error("photometry normalize: give the output image with -o OUT.exr");
    const Image img = read_image(a.image);
    std::vector<photometry::Geometry> geo;
    std::vector<double> dn;
    std::vector<std::pair<int, int>> where;
    if (!a.backplanes.empty()) {
        photometry::PixelGeometry pg = photometry::geometry_from_backplanes(img, a.image, split(a.backplanes, ','));
        geo = std::move(pg.geometry);
        dn = std::move(pg.dn);
        where = std::move(pg.xy);
    } else {
        if (std::isnan(a.phase))
            throw Error("photometry normalize: give the geometry as --phase G [--pa P] --radius R [--centre x,y] (a "
                        "disc) or as --backplanes PHASE,INCIDENCE,EMISSION");
        if (!(a.radius > 0.0)) throw Error("photometry normalize: --radius (the disc's radius in pixels) is needed with --phase");
        moon::Disc d{0.5 * img.width, 0.5 * img.height, a.radius};
        if (!a.centre.empty()) {
            const glm::dvec3 c = parse_vec3(a.centre + ",0", "--centre");
            d.cx = c.x;
            d.cy = c.y;
        }
        const moon::SunGeometry sun = moon::sun_geometry(a.phase, a.pa);
        for (const auto& p : moon::disc_pixels(img, d, sun)) {
            geo.push_back({p.a.g_deg, p.a.i_deg, p.a.e_deg});
            dn.push_back(p.I);
            where.push_back({p.x, p.y});
        }
    }
    Runtime rt;
    const photometry::Normalized n = photometry::normalize(rt, law, geo, dn, a.o);
    Image out(img.width, img.height, 4);
    for (std::size_t k = 0; k < where.size(); ++k) {
        if (!n.valid[k]) continue;
        for (int c = 0; c < 3; ++c) out.at(where[k].first, where[k].second, c) = float(n.value[k]);
        out.at(where[k].first, where[k].second, 3) = 1.0f;
    }
    write_image(a.out, out);
    std::cout << "law: " << law.describe() << "\n"
              << "mode: " << a.o.mode << ", reference (pharef, incref, emaref) = (" << a.o.pharef << ", " << a.o.incref
              << ", " << a.o.emaref << ") deg, law there " << n.psurf_ref << "\n"
              << "pixels: " << where.size() << " normalised, " << n.nulled << " left without a value (thresh "
              << a.o.thresh << ")\n"
              << "wrote: " << a.out << "\n";
}

struct FitDiscArgs {
    std::string image, law = "lunar_lambert", centre;
    double phase = NAN, pa = 0.0, radius = 0.0, incmax = 89.0, emamax = 89.0;
    bool offset = false;
};

// Lunar-Lambert L or Minnaert K and the brightness fitted to the pixels of a disc image at its phase, by the fit
// photometry empirical makes to a Hapke sphere (host/photometry/empirical.hpp).
void run_fit_disc(const FitDiscArgs& a) {
    const int law = a.law == "minnaert" ? 1 : (a.law == "lunar_lambert" || a.law == "lunarlambert" ? 2 : 0);
    if (!law) throw Error("photometry fit-disc: --law '" + a.law + "' is unknown: use lunar_lambert or minnaert");
    if (std::isnan(a.phase) || !(a.radius > 0.0))
        throw Error("photometry fit-disc: the disc geometry needs --phase G and --radius R (and --pa, --centre)");
    const Image img = read_image(a.image);
    moon::Disc d{0.5 * img.width, 0.5 * img.height, a.radius};
    if (!a.centre.empty()) {
        const glm::dvec3 c = parse_vec3(a.centre + ",0", "--centre");
        d.cx = c.x;
        d.cy = c.y;
    }
    const moon::SunGeometry sun = moon::sun_geometry(a.phase, a.pa);
    std::vector<double> inc, ema, val;
    for (const auto& p : moon::disc_pixels(img, d, sun)) {
        if (p.a.i_deg > a.incmax || p.a.e_deg > a.emamax) continue;
        inc.push_back(p.a.i_deg);
        ema.push_back(p.a.e_deg);
        val.push_back(p.I);
    }
    const photometry::SimpleFit f = photometry::fit_simple_law(law, inc, ema, val, a.offset);
    std::cout << "image: " << a.image << ", phase " << a.phase << " deg, " << f.samples << " pixels with i <= "
              << a.incmax << ", e <= " << a.emamax << "\n"
              << (law == 1 ? "K" : "L") << ": " << f.param << "\nB: " << f.c1 << "\n";
    if (a.offset) std::cout << "offset: " << f.c0 << "\n";
    std::cout << "rms: " << f.rms << "\n";
}

struct FitArgs {
    std::vector<std::string> images, backplanes, params, models;
    std::vector<double> phase, pa, radius;
    std::vector<std::string> centre;
    std::string model, free;
    double incmax = 89.0, emamax = 89.0;
    int max_iterations = 200;
    std::string precision = "precise";
};

// The k-th of a per-image list given once (for all images) or once per image.
template <class T>
T per_image(const std::vector<T>& v, std::size_t k, const char* opt, std::size_t images, T fallback) {
    if (v.empty()) return fallback;
    if (v.size() != 1 && v.size() != images)
        throw Error(std::string("photometry fit: ") + opt + " is given " + std::to_string(v.size()) + " times for " +
                    std::to_string(images) + " images: give it once (for all) or once per image");
    return v.size() == 1 ? v[0] : v[k];
}

// The pixels of every image with their geometry: a disc (--phase, --pa, --radius, --centre per image) or
// backplanes (--backplanes PHASE,INCIDENCE,EMISSION per image); pixels beyond --incmax or --emamax are left out.
photometry::FitData fit_data_from_args(const FitArgs& a) {
    if (a.images.empty()) throw Error("photometry fit: give one or more images");
    const std::size_t n = a.images.size();
    if (!a.backplanes.empty() && a.backplanes.size() != n)
        throw Error("photometry fit: --backplanes is given " + std::to_string(a.backplanes.size()) + " times for " +
                    std::to_string(n) + " images: one PHASE,INCIDENCE,EMISSION triple per image");
    if (a.backplanes.empty() && a.phase.size() != n)
        throw Error("photometry fit: --phase is given " + std::to_string(a.phase.size()) + " times for " +
                    std::to_string(n) + " images: one phase per image (--phase 20,45,70), or --backplanes");
    photometry::FitData d;
    d.images = int(n);
    for (std::size_t m = 0; m < n; ++m) {
        const Image img = read_image(a.images[m]);
        d.image_names.push_back(a.images[m]);
        auto add = [&](const photometry::Geometry& g, double v) {
            if (g.incidence > a.incmax || g.emission > a.emamax) return;
            d.geometry.push_back(g);
            d.value.push_back(v);
            d.image.push_back(int(m));
        };
        if (!a.backplanes.empty()) {
            const photometry::PixelGeometry pg =
                photometry::geometry_from_backplanes(img, a.images[m], split(a.backplanes[m], ','));
            for (std::size_t k = 0; k < pg.dn.size(); ++k) add(pg.geometry[k], pg.dn[k]);
            continue;
        }
        const double radius = per_image(a.radius, m, "--radius", n, 0.0);
        if (!(radius > 0.0)) throw Error("photometry fit: --radius (the disc's radius in pixels) is needed with --phase");
        moon::Disc disc{0.5 * img.width, 0.5 * img.height, radius};
        const std::string centre = per_image(a.centre, m, "--centre", n, std::string());
        if (!centre.empty()) {
            const glm::dvec3 c = parse_vec3(centre + ",0", "--centre");
            disc.cx = c.x;
            disc.cy = c.y;
        }
        const double g = a.phase[m];
        if (!std::isfinite(g) || g < 0.0 || g > 180.0)
            throw Error("photometry fit: --phase " + std::to_string(g) + " is out of range: allowed 0 to 180 degrees");
        const moon::SunGeometry sun = moon::sun_geometry(g, per_image(a.pa, m, "--pa", n, 0.0));
        for (const auto& p : moon::disc_pixels(img, disc, sun)) add({p.a.g_deg, p.a.i_deg, p.a.e_deg}, p.I);
    }
    return d;
}

void run_fit(const FitArgs& a) {
    if (a.model.empty() == a.models.empty())
        throw Error("photometry fit: give one law as --model NAME or several to rank as --models a,b,c");
    photometry::FitOptions o;
    o.max_iterations = a.max_iterations;
    o.precision = parse_precision(a.precision);
    std::map<std::string, double> start;
    for (const auto& s : a.params) start.insert(parse_param(s));
    const photometry::FitData d = fit_data_from_args(a);
    std::cout << "pixels: " << d.value.size() << " from " << d.images << " image(s), i <= " << a.incmax << ", e <= "
              << a.emamax << " deg\n";
    Runtime rt;
    log_out() << "device: " << rt.device_description() << "\n";
    if (!a.model.empty()) {
        photometry::FitSpec s{a.model, start, a.free.empty() ? std::vector<std::string>{} : split(a.free, ',')};
        std::cout << photometry::describe_fit(photometry::fit_law(rt, d, s, o));
        return;
    }
    if (!a.free.empty()) throw Error("photometry fit: --free goes with --model (--models fits each law's defaults)");
    std::vector<photometry::FitSpec> specs;
    for (const auto& name : a.models) {
        photometry::FitSpec s;
        s.model = photometry::fit_model_name(name);
        // -p values apply to the laws that have that parameter
        for (const auto& [k, v] : start)
            for (const auto& p : find_model(s.model).params)
                if (p.name == k) s.start[k] = v;
        specs.push_back(s);
    }
    const auto ranked = photometry::rank_laws(rt, d, specs, o);
    for (const auto& r : ranked) std::cout << photometry::describe_fit(r) << "\n";
    std::cout << photometry::describe_ranking(ranked);
    std::cout << "best: " << ranked[0].model << "\n";
}

// photometry eval
void add_eval(CLI::App* cmd) {
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

// photometry empirical
void add_empirical(CLI::App* cmd) {
    auto b = std::make_shared<EmpiricalArgs>();
    auto* em = cmd->add_subcommand("empirical", "Fit Lunar-Lambert L(g) or Minnaert K(g) and a phase curve to a Hapke "
                                                "sphere, as ISIS's phoempglobal; write the PVL table ISIS reads");
    em->add_option("--pvl", b->pvl, "Hapke parameters: ISIS PVL with Name = HapkeHen or HapkeLeg");
    em->add_option("--model", b->model, "or hapke_hen / hapke_leg by name, with -p");
    em->add_option("-p,--param", b->params, "name=value parameter of --model (repeatable)");
    em->add_option("--law", b->law, "lunar_lambert | minnaert")->capture_default_str();
    em->add_option("--nph", b->o.nph, "number of phase angles")->capture_default_str();
    em->add_option("--phmin", b->o.phmin, "first phase angle, degrees")->capture_default_str();
    em->add_option("--phmax", b->o.phmax, "last phase angle, degrees")->capture_default_str();
    em->add_option("--incmin", b->o.incmin, "smallest incidence fitted, degrees")->capture_default_str();
    em->add_option("--incmax", b->o.incmax, "largest incidence fitted, degrees")->capture_default_str();
    em->add_option("--emamin", b->o.emamin, "smallest emission fitted, degrees")->capture_default_str();
    em->add_option("--emamax", b->o.emamax, "largest emission fitted at zero phase, degrees")->capture_default_str();
    em->add_option("--emamax-pcoeff", b->o.emamax_pcoeff, "the emission limit grows by this times the phase")
        ->capture_default_str();
    em->add_flag("--offset", b->o.offset, "fit an additive offset too (phoempglobal's IORD); B is then not normalised");
    em->add_option("-o,--out", b->out, "output PVL table");
    em->callback([b] { run_empirical(*b); });
}

// photometry normalize
void add_normalize(CLI::App* cmd) {
    auto c = std::make_shared<NormalizeArgs>();
    auto* nm = cmd->add_subcommand("normalize", "Normalise an image to a standard geometry with a photometric law "
                                                "(ISIS photomet's albedo and shade modes)");
    nm->add_option("image", c->image, "the image (linear: .exr, .fits, ...)")->required();
    nm->add_option("--pvl", c->pvl, "the photometric law: ISIS PVL (Object = PhotometricModel)");
    nm->add_option("--model", c->model, "or a catalogue model by name, with -p");
    nm->add_option("-p,--param", c->params, "name=value parameter of --model (repeatable)");
    nm->add_option("--mode", c->o.mode, "albedo | shade")->capture_default_str();
    nm->add_option("--incref", c->o.incref, "reference incidence, degrees")->capture_default_str();
    nm->add_option("--emaref", c->o.emaref, "reference emission, degrees")->capture_default_str();
    nm->add_option("--pharef", c->o.pharef, "reference phase, degrees")->capture_default_str();
    nm->add_option("--thresh", c->o.thresh, "albedo mode: no value where the law is below 1/thresh of the reference")
        ->capture_default_str();
    nm->add_option("--albedo", c->o.albedo, "shade mode: the uniform albedo")->capture_default_str();
    nm->add_option("--phase", c->phase, "disc geometry: phase angle, degrees");
    nm->add_option("--pa", c->pa, "disc geometry: position angle of the sun, degrees (docs/moon.md)");
    nm->add_option("--radius", c->radius, "disc geometry: disc radius, pixels");
    nm->add_option("--centre,--center", c->centre, "disc geometry: centre x,y in pixels (default: the image centre)");
    nm->add_option("--backplanes", c->backplanes, "or per-pixel PHASE,INCIDENCE,EMISSION images in degrees");
    nm->add_option("-o,--out", c->out, "output image (.exr: linear float; alpha 0 where there is no value)");
    nm->callback([c] { run_normalize(*c); });
}

// photometry fit-disc
void add_fit_disc(CLI::App* cmd) {
    auto f = std::make_shared<FitDiscArgs>();
    auto* fd = cmd->add_subcommand("fit-disc", "Fit Lunar-Lambert L or Minnaert K and the brightness to a disc image at "
                                               "its phase (phoempglobal's fit, on a user's pixels)");
    fd->add_option("image", f->image, "the disc image (linear)")->required();
    fd->add_option("--law", f->law, "lunar_lambert | minnaert")->capture_default_str();
    fd->add_option("--phase", f->phase, "phase angle, degrees");
    fd->add_option("--pa", f->pa, "position angle of the sun, degrees (docs/moon.md)");
    fd->add_option("--radius", f->radius, "disc radius, pixels");
    fd->add_option("--centre,--center", f->centre, "disc centre x,y in pixels (default: the image centre)");
    fd->add_option("--incmax", f->incmax, "largest incidence used, degrees")->capture_default_str();
    fd->add_option("--emamax", f->emamax, "largest emission used, degrees")->capture_default_str();
    fd->add_flag("--offset", f->offset, "fit an additive offset too");
    fd->callback([f] { run_fit_disc(*f); });
}

// photometry fit
void add_fit(CLI::App* cmd) {
    auto h = std::make_shared<FitArgs>();
    auto* ft = cmd->add_subcommand("fit", "Fit Hapke or a simpler law to one or several images at different phases "
                                          "(bounded least squares on PoCL, standard errors, correlations); --models "
                                          "ranks several laws by BIC");
    ft->add_option("images", h->images, "the images (linear I/F), one per phase")->required();
    ft->add_option("--model", h->model, "the law: hapke_hen, hapke_leg, hapke_2012, lunar_lambert, minnaert_1941, "
                                        "lommel_seeliger, lambert, lunar_lambert_mcewen (or ISIS's names)");
    ft->add_option("--models", h->models, "several laws to fit and rank, comma-separated")->delimiter(',');
    ft->add_option("-p,--param", h->params, "name=value: the start of a fitted parameter, or the value of a fixed one");
    ft->add_option("--free", h->free, "the parameters fitted, comma-separated (default: Hapke wh,b0,hh,theta,hg1 "
                                      "(hapke_leg: bh,ch); other laws all theirs)");
    ft->add_option("--phase", h->phase, "disc geometry: phase angle per image, degrees")->delimiter(',');
    ft->add_option("--pa", h->pa, "disc geometry: sun position angle, once or per image (docs/moon.md)")->delimiter(',');
    ft->add_option("--radius", h->radius, "disc geometry: radius in pixels, once or per image")->delimiter(',');
    ft->add_option("--centre,--center", h->centre, "disc geometry: centre x,y, once or per image (repeat the option)");
    ft->add_option("--backplanes", h->backplanes, "or PHASE,INCIDENCE,EMISSION images per image (repeat the option)");
    ft->add_option("--incmax", h->incmax, "largest incidence used, degrees")->capture_default_str();
    ft->add_option("--emamax", h->emamax, "largest emission used, degrees")->capture_default_str();
    ft->add_option("--max-iterations", h->max_iterations, "Levenberg-Marquardt iterations")->capture_default_str();
    ft->add_option("--precision", h->precision, "precise | fast (docs/precision.md)")->capture_default_str();
    ft->callback([h] { run_fit(*h); });
}

}  // namespace

void add_photometry_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("photometry", "ISIS3's photometric models (Hapke, Lunar-Lambert, Minnaert, ...) "
                                                 "at photometric angles, from ISIS PVL files (docs/photometry.md)");
    cmd->require_subcommand(1);
    add_eval(cmd);
    add_empirical(cmd);
    add_normalize(cmd);
    add_fit_disc(cmd);
    add_fit(cmd);
}

}  // namespace shadelab::app
