// shadelab compare: how far is one image from another (the reference), in CIEDE2000 and relative error.
#include <fstream>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "color/image_compare.hpp"
#include "image/image.hpp"

namespace shadelab::app {

void add_compare_command(CLI::App& app) {
    struct Args {
        std::string a, b, map, json;
        double scale = 5.0;
        double rel_floor = 1e-3;
        bool ignore_nonfinite = false;
    };
    auto args = std::make_shared<Args>();
    auto* cmd = app.add_subcommand("compare", "Compare an image with a reference: Delta E 2000 map, mean/p99/max, relative error");
    cmd->add_option("image", args->a, "Image to judge (.exr, .png, ...)")->required();
    cmd->add_option("reference", args->b, "Reference image of the same size")->required();
    cmd->add_option("--map", args->map, "Write the per-pixel Delta E 2000 map here (.png colour-mapped, .exr raw)");
    cmd->add_option("--map-scale", args->scale, "Delta E shown as full scale in a .png map")->capture_default_str();
    cmd->add_option("--rel-floor", args->rel_floor, "Relative error only where the reference is >= this")->capture_default_str();
    cmd->add_option("--json", args->json, "Also write the figures as JSON here");
    cmd->add_flag("--ignore-nonfinite", args->ignore_nonfinite,
                  "Leave pixels holding NaN/Inf (in either image) out of every figure and say how many; "
                  "without it such pixels are an error");
    cmd->callback([args] {
        const Image a = read_image(args->a), b = read_image(args->b);
        // NaN/Inf pixels are named with their file here (compare_images would refuse them without it).
        for (const auto& [img, path] : {std::pair{&a, &args->a}, std::pair{&b, &args->b}}) {
            const NonFinitePixels n = find_non_finite(*img);
            if (n.count && !args->ignore_nonfinite)
                throw Error("image '" + *path + "' has " + std::to_string(n.count) + " pixel" + (n.count == 1 ? "" : "s") +
                            " holding NaN or Inf, the first at (x, y) = (" + std::to_string(n.x) + ", " + std::to_string(n.y) + ")" +
                            ": fix what produced it, or leave such pixels out with --ignore-nonfinite");
        }
        const ImageDiff d = compare_images(a, b, args->rel_floor, args->ignore_nonfinite);
        std::cout << "pixels compared     " << d.pixels << "\n"
                  << "coverage mismatch   " << d.coverage_mismatch << "\n"
                  << "Delta E 2000        mean " << d.de_mean << "  p99 " << d.de_p99 << "  max " << d.de_max << "\n"
                  << "relative error      p99 " << d.rel_p99 << "  max " << d.rel_max << "  (where reference >= "
                  << args->rel_floor << ")\n"
                  << "absolute error max  " << d.abs_max << "\n";
        if (args->ignore_nonfinite)
            std::cout << "NaN/Inf excluded    " << d.nonfinite_excluded << (d.nonfinite_excluded == 1 ? " pixel" : " pixels")
                      << " (NaN or Inf in either image; left out of every figure)\n";
        if (!args->map.empty()) {
            const bool raw = encoding_for(args->map) == Encoding::Linear;
            write_image(args->map, raw ? d.de_map : colourise_delta_e(d.de_map, args->scale));
            std::cout << "Delta E map         " << args->map << "\n";
        }
        if (!args->json.empty()) {
            nlohmann::json j = {{"image", args->a}, {"reference", args->b}, {"pixels", d.pixels},
                                {"coverage_mismatch", d.coverage_mismatch},
                                {"delta_e2000", {{"mean", d.de_mean}, {"p99", d.de_p99}, {"max", d.de_max}}},
                                {"relative_error", {{"p99", d.rel_p99}, {"max", d.rel_max}, {"floor", args->rel_floor}}},
                                {"absolute_error_max", d.abs_max},
                                {"nonfinite_excluded", d.nonfinite_excluded}};
            // File names need not be UTF-8: replace what is not rather than fail after the work is done.
            write_text_atomically(args->json, "report", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
        }
    });
}

}  // namespace shadelab::app
