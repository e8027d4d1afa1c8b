// fit --all: every catalogue model fitted to one target, with its measured speed on this device; the table
// sorted by model error, the Pareto front of speed against model error, and the chart (two panels: model error
// against speed, and each model's own numeric error, float kernel against its double reference, against speed).
#pragma once
#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fit/fit.hpp"

namespace shadelab::fit {

struct AllOptions {
    FitOptions fit;
    std::vector<std::string> models;        // empty: the whole catalogue
    double model_specular = -1.0;           // < 0: the target's
    std::string out_dir;                    // table and chart; empty: none written
    std::string metric = "rel-rms";         // the error the table is sorted by and the chart plots
    std::size_t timed_fragments = std::size_t(1) << 18;
    int timing_repeats = 3;
};

struct AllRow {
    FitResult fit;
    double mfrag_per_s = 0.0;     // the model's shading kernel on timed_fragments fragments, best of the repeats
    double speedup = 0.0;         // mfrag_per_s / the target's
    double numeric_rel_rms = 0.0; // float kernel against its own double reference at the fitted parameters
    bool front = false;           // on the Pareto front of speed against model error
    bool is_target = false;       // the target's own model (fitted to itself)
};

struct AllResult {
    std::string target;           // "oren_nayar(sigma=0.4)"
    std::string target_model;
    std::string target_name;      // the target model's name, or the image's file
    std::map<std::string, double> target_params;
    double target_mfrag_per_s = 0.0;
    std::string speed_reference;  // the model speed-ups are over: the target's, or lambert's for a measured target
    std::string domain, domain_description;
    std::string device;
    std::size_t timed_fragments = 0;
    std::string metric = "rel-rms";
    std::vector<AllRow> rows;     // sorted by `metric`, smallest first
    std::vector<std::string> files;
    double seconds = 0.0, fit_seconds = 0.0, timing_seconds = 0.0;
};

// Kernel device time of `m`'s shading kernel (one directional light) on `fragments` fragments spread over a
// lit sphere, best of up to `repeats` runs (fewer once 60 ms of kernel time were spent: a slow model's single
// run is long enough to time), in million fragments per second.
double measure_mfrag_per_s(Runtime& rt, const Material& m, std::size_t fragments, int repeats);

// Fits every model; progress lines go to `log`. Writes fit_all.csv and fit_all.png into out_dir when given.
AllResult fit_all(Runtime& rt, Problem& problem, const AllOptions& o, std::ostream& log);

std::string all_table_text(const AllResult& r);
nlohmann::json to_json(const AllResult& r);

}  // namespace shadelab::fit
