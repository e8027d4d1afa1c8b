// Charts for the moon tools: CSV tables and PNG plots drawn by gnuplot (Debian package gnuplot-nox), run as a
// child process with the pngcairo terminal. Tables are always written first, so a missing gnuplot costs only
// the picture: the error names the package and the table that was written.
#pragma once
#include <string>
#include <vector>

#include "moon/fit.hpp"
#include "moon/photometry.hpp"

namespace shadelab::moon {

// --- CSV: a header line, then rows of numbers (or short words). Never writes NaN/Inf: a non-finite number
// is an internal error (callers write an empty field for "no value" with CsvRow::blank()).
class CsvTable {
public:
    explicit CsvTable(std::vector<std::string> columns) : columns_(std::move(columns)) {}
    CsvTable& row();                          // starts a new row
    CsvTable& add(double v, int digits = 9);  // throws on NaN/Inf
    CsvTable& add(const std::string& word);
    CsvTable& blank();
    void write(const std::string& path) const;   // atomic; creates the folder
    std::size_t rows() const { return rows_.size(); }

private:
    std::vector<std::string> columns_;
    std::vector<std::vector<std::string>> rows_;
};

// The gnuplot executable: $SHADELAB_GNUPLOT if set, else "gnuplot" on PATH. Throws shadelab::Error
// "gnuplot not found ...: install the Debian package gnuplot-nox" when there is none.
std::string find_gnuplot();

// Runs gnuplot on `script` (fed on its standard input) and checks that `png` was produced. Throws one line
// with gnuplot's first error message otherwise. `what_was_written` is added to the errors
// ("the CSV out/a.csv was written").
void run_gnuplot(const std::string& script, const std::string& png, const std::string& what_was_written);

// gnuplot string literal for a file name or a title.
std::string gp_string(const std::string& s);

// A number for a gnuplot script, with `digits` significant digits.
std::string gp_number(double x, int digits = 6);

// The preamble every chart shares: pngcairo of width x height with a sans font of `font_size` points, the
// output file, CSV read with its header line as column names, a light grid.
std::string gnuplot_preamble(const std::string& png, int width, int height, int font_size = 10);

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
