// Charts drawn by gnuplot (Debian package gnuplot-nox), run as a child process with the pngcairo terminal, from
// CSV tables written first (core/csv.hpp), so a missing gnuplot costs only the picture: the error names the
// package and the table that was written. Used by moon, speed, fit and view.
#pragma once
#include <string>

namespace shadelab::plot {

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

}  // namespace shadelab::plot
