#include "moon/plot.hpp"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "core/error.hpp"
#include "core/format.hpp"
#include "plot/gnuplot.hpp"

namespace fs = std::filesystem;

namespace shadelab::moon {

using plot::gnuplot_preamble;
using plot::gp_number;
using plot::gp_string;
using plot::run_gnuplot;

namespace {
// The column of `col` where column "profile" equals `which`, else NaN (so one CSV feeds both panels).
std::string where_profile(const std::string& which, const std::string& col) {
    return "(strcol('profile') eq '" + which + "' ? column('" + col + "') : NaN)";
}
}  // namespace

// --------------------------------------------------------------------------------------------- charts

void plot_curves(const std::string& csv, const std::string& png, const std::vector<std::string>& value_columns,
                 const std::vector<std::string>& labels, const std::string& title) {
    std::ostringstream s;
    s << gnuplot_preamble(png, 900, 900);
    s << "set multiplot layout 2,1 title " << gp_string(title) << "\n"
      << "set key top left\nset yrange [0:*]\nset ylabel 'I/F'\n";
    const char* panels[2][2] = {{"equator", "position along the intensity equator (disc radii, + towards the sun)"},
                                {"across", "position across the disc, perpendicular to the equator (disc radii)"}};
    for (auto& p : panels) {
        s << "set title " << gp_string(std::string("profile: ") + p[0]) << "\nset xlabel " << gp_string(p[1]) << "\n";
        s << "set xrange [-1:1]\nplot ";
        for (std::size_t i = 0; i < value_columns.size(); ++i)
            s << (i ? ", " : "") << gp_string(csv) << " using 's':" << where_profile(p[0], value_columns[i])
              << " with lines lw 2 title " << gp_string(labels[i]);
        s << "\n";
    }
    s << "unset multiplot\n";
    run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
}

void plot_profiles(const std::string& csv, const std::string& png, bool has_model, const std::string& title) {
    std::ostringstream s;
    s << gnuplot_preamble(png, 1200, has_model ? 900 : 500);
    s << "set multiplot layout " << (has_model ? 2 : 1) << ",2 title " << gp_string(title) << "\n"
      << "set key top left\nset xrange [-1:1]\n";
    const char* names[2] = {"equator", "across"};
    for (const char* p : names) {
        s << "set title " << gp_string(std::string("profile: ") + p) << "\nset xlabel 'position (disc radii)'\n"
          << "set ylabel 'I/F'\nset yrange [0:*]\n";
        s << "plot " << gp_string(csv) << " using 's':" << where_profile(p, "I") << " with points pt 7 ps 0.4 title 'image'";
        if (has_model)
            s << ", " << gp_string(csv) << " using 's':" << where_profile(p, "model") << " with lines lw 2 title 'model'";
        s << "\n";
    }
    if (has_model) {
        for (const char* p : names) {
            s << "set title " << gp_string(std::string("relative error (image - model) / model: ") + p)
              << "\nset ylabel 'relative error'\nset yrange [*:*]\nset format y '%.1e'\n";
            s << "plot " << gp_string(csv) << " using 's':" << where_profile(p, "rel_err")
              << " with points pt 7 ps 0.4 title 'used (mu, mu0 above thresholds)'\nset format y '%g'\n";
        }
    }
    s << "unset multiplot\n";
    run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
}

void plot_minnaert(const std::string& csv, const std::string& png, const MinnaertFit& f, const std::string& title) {
    std::ostringstream s;
    s << gnuplot_preamble(png, 900, 700);
    s << "set title " << gp_string(title) << "\n"
      << "set xlabel 'ln(mu mu0)'\nset ylabel 'ln(mu I)'\nset key top left\n"
      << "f(x) = " << num(f.ln_B0, 12) << " + " << num(f.k, 12) << " * x\n"
      << "set label 1 \"k = " << gp_number(f.k) << " +- " << gp_number(f.se_k, 2) << "\\nB0 = " << gp_number(f.B0) << " +- "
      << gp_number(f.se_B0, 2) << "\\nrms residual " << gp_number(f.rms, 3) << "\\n" << f.used << " pixels\""
      << " at graph 0.6, graph 0.25\n"
      << "plot " << gp_string(csv) << " using 'x':'y' with dots lc rgb '#3060c0' title 'pixels', "
      << "f(x) with lines lw 2 lc rgb '#c03030' title 'fit: ln B0 + k ln(mu mu0)'\n";
    run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
}

void plot_errorbars(const std::string& csv, const std::string& png, const std::string& x, const std::string& y,
                    const std::string& e, const std::string& xlabel, const std::string& ylabel, const std::string& title) {
    std::ostringstream s;
    s << gnuplot_preamble(png, 900, 600);
    s << "set title " << gp_string(title) << "\nset xlabel " << gp_string(xlabel) << "\nset ylabel "
      << gp_string(ylabel) << "\nset key top left\nset offsets graph 0.05, graph 0.05, graph 0.1, graph 0.1\n"
      << "plot " << gp_string(csv) << " using " << gp_string(x) << ":" << gp_string(y) << ":" << gp_string(e)
      << " with yerrorbars pt 7 title " << gp_string(ylabel + " +- 1 sigma") << "\n";
    run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
}

void plot_k_map(const std::string& csv, const std::string& png, int cells, const std::string& title) {
    std::ostringstream s;
    s << gnuplot_preamble(png, 800, 720);
    const double h = 1.0 / cells;   // half cell width in disc radii
    s << "set title " << gp_string(title) << "\n"
      << "set size ratio -1\nset xrange [-1.05:1.05]\nset yrange [-1.05:1.05]\n"
      << "set xlabel 'X (disc radii, image right)'\nset ylabel 'Y (disc radii, image up)'\n"
      << "set palette rgbformulae 33,13,10\nset cblabel 'Minnaert k'\n"
      << "set object 1 circle at 0,0 size 1 fs empty border lc rgb 'black' front\n"
      << "plot " << gp_string(csv) << " using 'X':'Y':(" << h << "):(" << h
      << "):'k' with boxxy fs solid 1.0 noborder lc palette notitle\n";
    run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
}

void plot_geometry(const std::string& png, const SunGeometry& sun, double across_offset) {
    // Everything in disc radii, x right and y up, as the image is displayed.
    auto P = [&](double a, double b) {   // point a u + b w
        const glm::dvec3 p = a * sun.u + b * sun.w;
        return gp_number(p.x) + "," + gp_number(p.y);
    };
    const double alpha = sun.phase_deg * kDeg;
    std::ostringstream s;
    s << gnuplot_preamble(png, 800, 800);
    s << "unset grid\nset size ratio -1\nset xrange [-1.6:1.6]\nset yrange [-1.6:1.6]\nunset xtics\nunset ytics\n"
      << "unset border\nunset key\n"
      << "set title " << gp_string("phase " + gp_number(sun.phase_deg) + " deg, position angle " + gp_number(sun.pa_deg) +
                                   " deg (from north towards east)") << "\n";
    // The lit part: the bright limb (the half of the rim towards the sun) closed by the terminator.
    s << "set object 1 polygon from ";
    const int n = 90;
    for (int j = 0; j <= n; ++j) {
        const double phi = -0.5 * kPi + kPi * j / n;
        s << (j ? " to " : "") << P(std::cos(phi), std::sin(phi));
    }
    for (int j = 0; j <= n; ++j) {
        const double tau = kPi * j / n;   // terminator: a = -sin(tau) cos(alpha), b = cos(tau)
        s << " to " << P(-std::sin(tau) * std::cos(alpha), std::cos(tau));
    }
    s << " fs solid 1.0 noborder fc rgb '#f3e6a6' behind\n";
    s << "set object 2 circle at 0,0 size 1 fs empty border lc rgb 'black' lw 2 front\n";
    // Equator, across line, sun direction, compass.
    s << "set arrow 1 from " << P(-1, 0) << " to " << P(1, 0) << " nohead lw 2 lc rgb '#c03030' front\n"
      << "set arrow 2 from " << P(across_offset, -std::sqrt(1 - across_offset * across_offset)) << " to "
      << P(across_offset, std::sqrt(1 - across_offset * across_offset)) << " nohead lw 2 dt 2 lc rgb '#3060c0' front\n"
      << "set arrow 3 from " << P(1.0, 0) << " to " << P(1.45, 0) << " head filled lw 2 lc rgb '#d08000' front\n"
      << "set label 1 'to the sun' at " << P(1.5, 0) << " center tc rgb '#d08000' front\n"
      << "set label 2 'intensity equator (u)' at " << P(0.55, -0.08) << " center tc rgb '#c03030' front\n"
      << "set label 3 'across (w)' at " << P(across_offset + 0.08, 0.75) << " left tc rgb '#3060c0' front\n"
      << "set arrow 4 from -1.1,1.1 to -1.1,1.5 head filled lw 1.5 front\n"
      << "set label 4 'N (up)' at -1.1,1.56 center front\n"
      << "set arrow 5 from -1.1,1.1 to -1.5,1.1 head filled lw 1.5 front\n"
      << "set label 5 'E (left)' at -1.5,1.02 left front\n";
    // Position angle: the arc from north to the sun direction, counter-clockwise.
    const double pa = std::fmod(std::fmod(sun.pa_deg, 360.0) + 360.0, 360.0);
    if (pa > 0.5)
        s << "set object 3 circle at 0,0 size 0.35 arc [90:" << 90.0 + pa << "] fs empty border lc rgb '#d08000' lw 1.5 front\n"
          << "set arrow 8 from 0,0 to 0,0.45 nohead dt 3 lc rgb 'black' front\n"
          << "set label 6 'pa' at " << gp_number(0.45 * std::cos((90.0 + 0.5 * pa) * kDeg)) << ","
          << gp_number(0.45 * std::sin((90.0 + 0.5 * pa) * kDeg)) << " center tc rgb '#d08000' front\n";
    // Sub-solar point (seen when phase <= 90) and the sub-observer point (the centre).
    if (sun.phase_deg <= 90.0)
        s << "set label 7 '' at " << P(std::sin(alpha), 0) << " point pt 3 ps 2 lc rgb '#d08000' front\n"
          << "set label 8 'sub-solar' at " << P(std::sin(alpha), 0.1) << " center front\n";
    s << "set label 9 '' at 0,0 point pt 7 ps 1 front\nset label 10 'sub-observer' at 0,-0.1 center front\n"
      << "set label 11 'terminator' at " << P(-std::sin(0.75 * kPi) * std::cos(alpha) - 0.2, std::cos(0.75 * kPi))
      << " center front\n"
      << "set label 12 'bright limb' at " << P(0.8, 0.85) << " center tc rgb '#806000' front\n"
      << "plot NaN notitle\n";
    run_gnuplot(s.str(), png, "");
}

}  // namespace shadelab::moon
