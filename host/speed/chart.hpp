// `shadelab chart`: the tables (CSV, core/csv.hpp) and pictures (PNG, drawn by gnuplot through host/plot/'s
// run_gnuplot) of speed against accuracy, and of error against tessellation / evaluation frequency.
#pragma once
#include <string>
#include <vector>

#include "core/csv.hpp"
#include "plot/gnuplot.hpp"
#include "speed/score.hpp"
#include "speed/subdivision.hpp"

namespace shadelab::speed {

// Log axes cannot show 0: errors below these floors are drawn at the floor (the CSV keeps the measured
// value in its own column and the drawn value in plot_*). Both are below anything float shading reaches
// (measured: p99 Delta E 2000 >= 2.6e-6, max relative >= 9.9e-8 for every model): a Delta E 2000 of 1e-7
// is 1e-7 of a just-noticeable difference; 1e-9 is below float's half-ulp (6e-8).
constexpr double kDeltaEFloor = 1e-7;
constexpr double kRelativeFloor = 1e-9;

struct ChartRow {
    Score score;
    bool front_de = false;    // on the Pareto front of speed against p99 Delta E 2000
    bool front_rel = false;   // on the Pareto front of speed against max relative error
};

// Marks both fronts (pareto_front on the measured, unclamped errors).
void mark_fronts(std::vector<ChartRow>& rows);

// One row per model x mode, every number (see the column list in chart.cpp). No NaN/Inf (CsvTable refuses).
CsvTable speed_table(const std::vector<ChartRow>& rows);

// Two panels (p99 Delta E 2000; max relative error) against Mfragments/s, log-log, precise and fast as two
// point sets, each panel's Pareto front drawn as a line with its members labelled.
void plot_speed_accuracy(const std::string& csv, const std::string& png, const std::vector<ChartRow>& rows,
                         const std::string& subtitle);

// Rows ordered surface, model, evaluation, level (so each plotted series is one contiguous block).
CsvTable subdivision_table(std::vector<SubdivisionRow> rows);

// Panels per surface: p99 Delta E 2000 (top) and mean Delta E 2000 (bottom) against the subdivision level,
// one line per model x evaluation (per pixel solid, per vertex dashed).
void plot_subdivision(const std::string& csv, const std::string& png, const std::vector<SubdivisionRow>& rows,
                      const std::string& subtitle);

}  // namespace shadelab::speed
