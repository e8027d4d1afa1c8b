// The moon subcommands (host/app/cmd_moon_*.cpp, one file per subcommand) and what they share: the disc's
// geometry on an image, models named on the command line, output names. docs/moon.md is the manual.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/glm.hpp>

#include "core/csv.hpp"
#include "image/image.hpp"
#include "moon/disc.hpp"
#include "moon/fit.hpp"
#include "moon/photometry.hpp"

namespace shadelab::app::moon_cli {

using namespace shadelab::moon;

// "out/a.csv" -> "out/a" (the stem other outputs are named after).
std::string stem_of(const std::string& path);
// The PNG beside a CSV (or the one given).
std::string png_for(const std::string& csv, const std::string& explicit_png, const std::string& suffix = "");
glm::dvec2 parse_centre(const std::string& text);
std::map<std::string, double> parse_params(const std::vector<std::string>& ps);

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

struct LoadedImage {
    Image img;
    ImageGeometry geo;
};

LoadedImage load(const std::string& path, const GeometryArgs& g, std::size_t i, std::size_t n);
std::string geometry_text(const ImageGeometry& g);

// ---------------------------------------------------------------- models named on the command line

struct ModelArgs {
    std::vector<std::string> models{"minnaert"};
    std::vector<double> k{0.7};
    std::vector<double> lunar_l{0.5};
    std::vector<std::string> params;
    double albedo = 1.0;

    void add_to(CLI::App* cmd, bool many) {
        auto* m = cmd->add_option("-m,--model", models,
                                  "minnaert (minnaert_1941, --k), lambert, lommel_seeliger, lunar_lambert (--lunar-l), "
                                  "or a catalogue model (see 'shadelab models'); each is its catalogue model's double "
                                  "reference");
        if (many) m->delimiter(',');
        m->capture_default_str();
        auto* ko = cmd->add_option("--k", k, "Minnaert 1941 k of 'minnaert', in [0, 2]");
        auto* lo = cmd->add_option("--lunar-l", lunar_l, "McEwen's Lunar-Lambert L of 'lunar_lambert', in [-1, 2]");
        if (many) {
            ko->delimiter(',');
            lo->delimiter(',');
        }
        ko->capture_default_str();
        lo->capture_default_str();
        cmd->add_option("-p,--param", params, "Catalogue model parameter name=value (repeatable)");
        cmd->add_option("--albedo,--b0", albedo, "B0 of the named laws; grey albedo of catalogue models")
            ->capture_default_str();
    }

    // Every (model, k or L) combination.
    std::vector<PhotometricModel> expand() const {
        std::vector<PhotometricModel> out;
        const auto ps = parse_params(params);
        for (const auto& name : models) {
            const NamedLaw* l = named_law(name);
            if (l && l->param == "k")
                for (double kk : k) out.push_back(make_photometric_model(name, kk, 0.0, albedo));
            else if (l && l->param == "l")
                for (double ll : lunar_l) out.push_back(make_photometric_model(name, 0.0, ll, albedo));
            else
                out.push_back(make_photometric_model(name, 0.0, 0.0, albedo, l ? decltype(ps){} : ps));
        }
        return out;
    }
};

std::string column_name(const PhotometricModel& m);

// ---------------------------------------------------------------- the subcommands, each in its own file

void add_curve(CLI::App* moon);                  // cmd_moon_curve.cpp
void add_render(CLI::App* moon);                 // cmd_moon_render.cpp
void add_profile(CLI::App* moon, bool compare);  // cmd_moon_profile.cpp: `profile`, and `compare` against a model
void add_fit(CLI::App* moon);                    // cmd_moon_fit.cpp
void add_geometry(CLI::App* moon);               // cmd_moon_geometry.cpp

}  // namespace shadelab::app::moon_cli
