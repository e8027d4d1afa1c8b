// The moon tools' charts: PNG plots drawn by gnuplot (host/plot/) from the CSV tables the commands write first.
#pragma once
#include <string>
#include <vector>

#include "moon/fit.hpp"
#include "moon/photometry.hpp"

namespace shadelab::moon {

// --- The charts. Each takes the CSV it draws from (already written) and the PNG to make.

// `moon curve`: two panels, the equator and the across profile; `value_columns` are the CSV column names of the
// curves (one per model or k), `labels` their legend entries. The CSV has a column "profile" (equator/across)
// and "s".
void plot_curves(const std::string& csv, const std::string& png, const std::vector<std::string>& value_columns,
                 const std::vector<std::string>& labels, const std::string& title);

// `moon profile` / `moon compare`: measured profile (column "I") against the model (column "model", when
// has_model) on top, relative error (column "rel_err") below, for the equator and the across profile.
void plot_profiles(const std::string& csv, const std::string& png, bool has_model, const std::string& title);

// `moon fit`: the Minnaert plot (CSV columns "x" = ln(mu mu0), "y" = ln(mu I)) with the fitted line.
void plot_minnaert(const std::string& csv, const std::string& png, const MinnaertFit& fit, const std::string& title);

// `moon fit --bins` (k against photometric longitude) and `moon fit` of several images (k against phase):
// column y against column x with error bars from column e; rows with an empty y are skipped.
void plot_errorbars(const std::string& csv, const std::string& png, const std::string& x, const std::string& y,
                    const std::string& e, const std::string& xlabel, const std::string& ylabel, const std::string& title);

// `moon fit --grid`: the k map (columns X, Y, k; empty k where no fit) as a heat map on the disc.
void plot_k_map(const std::string& csv, const std::string& png, int cells, const std::string& title);

// `moon geometry`: the convention figure - disc, lit part, terminator, intensity equator, across line, sun
// direction and position angle, north and east.
void plot_geometry(const std::string& png, const SunGeometry& sun, double across_offset);

}  // namespace shadelab::moon
