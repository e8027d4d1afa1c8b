#include "speed/chart.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>
#include <tuple>

#include "core/error.hpp"
#include "models/catalogue.hpp"
#include "speed/pareto.hpp"

namespace shadelab::speed {

namespace {

using plot::gp_string;
using plot::gnuplot_preamble;
using plot::gp_number;

// gnuplot double-quoted string: "\n" in `s` becomes a line break; quotes and backslashes are escaped.
std::string gp_dq(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '\n') out += "\\n";
        else if (c == '"' || c == '\\') out += std::string("\\") + c;
        else out += c;
    }
    return out + "\"";
}

// Text that gnuplot's enhanced mode would read as markup (_ ^ { } @ &), escaped to print as typed.
std::string plain(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '_' || c == '^' || c == '{' || c == '}' || c == '@' || c == '&') out += "\\";
        out += c;
    }
    return out;
}

std::string row_label(const Score& s) { return s.model + (s.precision == Precision::Fast ? " (fast)" : ""); }

double de_plotted(const Score& s) { return std::max(s.error.de_p99, kDeltaEFloor); }
double rel_plotted(const Score& s) { return std::max(s.error.rel_max, kRelativeFloor); }

// One panel: all points by mode, the front as a line, its members labelled. Labels follow the front's
// staircase (slowest first), each at least one text row above its point and one text row above the previous
// label, with a thin leader line down to its point; so no two labels share a row, whatever the spacing.
std::string speed_panel(const std::string& csv, const std::vector<ChartRow>& rows, bool de, const std::string& title) {
    std::vector<ParetoPoint> pts;
    std::vector<bool> on;
    double xlo = 1e300, xhi = 0, ylo = 1e300, yhi = 0;
    for (const auto& r : rows) {
        pts.push_back({r.score.fragments_per_s * 1e-6, de ? de_plotted(r.score) : rel_plotted(r.score)});
        on.push_back(de ? r.front_de : r.front_rel);
        xlo = std::min(xlo, pts.back().speed), xhi = std::max(xhi, pts.back().speed);
        ylo = std::min(ylo, pts.back().error), yhi = std::max(yhi, pts.back().error);
    }
    const auto order = front_in_speed_order(pts, on);
    // y range in decades: a decade of room below, and above for the labels. One text row is about 1/30 of
    // the panel's height.
    const double lo_dec = std::log10(ylo) - 1.0;
    double hi_dec = std::log10(yhi) + 0.9;
    const double row = (hi_dec - lo_dec) / 30.0;
    std::vector<double> label_dec;
    for (std::size_t k = 0; k < order.size(); ++k) {
        const double own = std::log10(pts[order[k]].error) + 2.5 * row;
        label_dec.push_back(k == 0 ? own : std::max(own, label_dec.back() + 1.3 * row));
    }
    if (!label_dec.empty()) hi_dec = std::max(hi_dec, label_dec.back() + 2.0 * row);
    const std::string col = de ? "plot_de2000_p99" : "plot_rel_max";
    std::ostringstream s;
    s << "set title " << gp_string(title) << "\n"
      << "set xlabel 'speed: million fragments per second (kernel device time, best of runs; log scale)'\n"
      << "set ylabel " << gp_string(de ? "p99 CIE Delta E 2000 against the double reference (log scale)"
                                       : "max relative error against the double reference (log scale)") << "\n"
      << "set logscale xy\nset format y '10^{%L}'\nset format x '%g'\nset key top left box opaque\n"
      << "set xrange [" << gp_number(xlo / 3.0) << ":" << gp_number(xhi * 3.0) << "]\nset yrange [" << gp_number(std::pow(10.0, lo_dec))
      << ":" << gp_number(std::pow(10.0, hi_dec)) << "]\nunset label\nunset arrow\nset style textbox opaque noborder\n";
    for (std::size_t k = 0; k < order.size(); ++k) {
        const auto& p = pts[order[k]];
        const double ly = std::pow(10.0, label_dec[k]);
        s << "set label " << (k + 1) << " " << gp_string(row_label(rows[order[k]].score)) << " at " << gp_number(p.speed, 9)
          << "," << gp_number(ly, 9) << " center boxed noenhanced font 'sans,10' tc rgb '#a00000' front\n"
          << "set arrow " << (k + 1) << " from " << gp_number(p.speed, 9) << "," << gp_number(ly, 9) << " to " << gp_number(p.speed, 9)
          << "," << gp_number(p.error * std::pow(10.0, 0.4 * row), 9) << " nohead lw 0.8 lc rgb '#c08080' back\n";
    }
    // The front line as an inline data block (the rows whose front_* column is 1, in speed order).
    const std::string block = de ? "$front_de" : "$front_rel";
    // Same layout as the CSV (comma-separated, a header line), since the datafile settings apply to it too.
    s << block << " << EOD\nmfrag_per_s,error\n";
    for (std::size_t i : order) s << gp_number(pts[i].speed, 9) << "," << gp_number(pts[i].error, 9) << "\n";
    s << "EOD\n";
    s << "plot " << gp_string(csv) << " using 'mfrag_per_s':(strcol('mode') eq 'precise' ? column('" << col
      << "') : NaN) with points pt 7 ps 1.1 lc rgb '#3060c0' title 'precise', "
      << gp_string(csv) << " using 'mfrag_per_s':(strcol('mode') eq 'fast' ? column('" << col
      << "') : NaN) with points pt 9 ps 1.2 lc rgb '#e08000' title 'fast', "
      << block << " using 1:2 with lines lw 1.5 dt 2 lc rgb '#a00000' notitle, "
      << block << " using 1:2 with points pt 6 ps 2.2 lw 1.5 lc rgb '#a00000' title 'Pareto front (labelled)'\n";
    return s.str();
}

// The error figures of a comparison, as CSV columns: the names, and one row's values (same order).
const std::vector<std::string> kFigureColumns = {"rel_max",    "rel_p99",  "de2000_mean", "de2000_p99",
                                                 "de2000_max", "abs_max", "pixels",      "coverage_mismatch"};
CsvTable& add_figures(CsvTable& t, const DiffFigures& e) {
    return t.add(e.rel_max, 4)
        .add(e.rel_p99, 4)
        .add(e.de_mean, 4)
        .add(e.de_p99, 4)
        .add(e.de_max, 4)
        .add(e.abs_max, 4)
        .add(double(e.pixels))
        .add(double(e.coverage_mismatch));
}

// Column names: `head`, the figures, `tail`.
std::vector<std::string> columns(std::vector<std::string> head, const std::vector<std::string>& tail) {
    head.insert(head.end(), kFigureColumns.begin(), kFigureColumns.end());
    head.insert(head.end(), tail.begin(), tail.end());
    return head;
}
}  // namespace

void mark_fronts(std::vector<ChartRow>& rows) {
    std::vector<ParetoPoint> de, rel;
    for (const auto& r : rows) {
        de.push_back({r.score.fragments_per_s, r.score.error.de_p99});
        rel.push_back({r.score.fragments_per_s, r.score.error.rel_max});
    }
    const auto fde = pareto_front(de), frel = pareto_front(rel);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        rows[i].front_de = fde[i];
        rows[i].front_rel = frel[i];
    }
}

CsvTable speed_table(const std::vector<ChartRow>& rows) {
    CsvTable t(columns({"model", "family", "mode", "mfrag_per_s", "kernel_ms", "timed_fragments"},
                             {"front_de2000_p99", "front_rel_max", "plot_de2000_p99", "plot_rel_max"}));
    for (const auto& r : rows) {
        const Score& s = r.score;
        t.row()
            .add(s.model)
            .add(find_model(s.model).family)
            .add(precision_name(s.precision))
            .add(s.fragments_per_s * 1e-6, 6)
            .add(s.kernel_ms, 6)
            .add(double(s.timed_fragments));
        add_figures(t, s.error)
            .add(r.front_de ? 1.0 : 0.0)
            .add(r.front_rel ? 1.0 : 0.0)
            .add(de_plotted(s), 4)
            .add(rel_plotted(s), 4);
    }
    return t;
}

void plot_speed_accuracy(const std::string& csv, const std::string& png, const std::vector<ChartRow>& rows,
                         const std::string& subtitle) {
    if (rows.empty()) throw Error("chart: nothing to plot (no model was scored)");
    std::ostringstream s;
    s << gnuplot_preamble(png, 1800, 820, 11);
    s << "set multiplot layout 1,2 title "
      << gp_dq("Speed against accuracy: every model x precision mode (precise, fast)\n{/*0.8 " + plain(subtitle) + "}")
      << " font 'sans,14'\n";
    s << speed_panel(csv, rows, true, "p99 Delta E 2000 over all covered pixels (< 1e-7 drawn at 1e-7)");
    s << speed_panel(csv, rows, false, "max relative error (linear values where the reference >= 1e-3; < 1e-9 drawn at 1e-9)");
    s << "unset multiplot\n";
    plot::run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
}

CsvTable subdivision_table(std::vector<SubdivisionRow> rows) {
    std::stable_sort(rows.begin(), rows.end(), [](const SubdivisionRow& a, const SubdivisionRow& b) {
        return std::tie(a.surface, a.model, a.per_vertex, a.level) < std::tie(b.surface, b.model, b.per_vertex, b.level);
    });
    CsvTable t(columns({"surface", "reference", "level", "triangles", "vertices", "model", "evaluation", "per_vertex"},
                             {"plot_de2000_p99", "plot_de2000_mean"}));
    for (const auto& r : rows) {
        t.row()
            .add(r.surface)
            .add(r.reference)
            .add(double(r.level))
            .add(double(r.triangles))
            .add(double(r.vertices))
            .add(r.model)
            .add(r.per_vertex ? "per_vertex" : "per_pixel")
            .add(r.per_vertex ? 1.0 : 0.0);
        add_figures(t, r.error)
            .add(std::max(r.error.de_p99, kDeltaEFloor), 4)
            .add(std::max(r.error.de_mean, kDeltaEFloor), 4);
    }
    return t;
}

void plot_subdivision(const std::string& csv, const std::string& png, const std::vector<SubdivisionRow>& rows,
                      const std::string& subtitle) {
    if (rows.empty()) throw Error("chart: nothing to plot (no subdivision row)");
    std::vector<std::string> surfaces, models;
    for (const auto& r : rows) {
        if (std::find(surfaces.begin(), surfaces.end(), r.surface) == surfaces.end()) surfaces.push_back(r.surface);
        if (std::find(models.begin(), models.end(), r.model) == models.end()) models.push_back(r.model);
    }
    static const char* colours[] = {"#3060c0", "#c03030", "#209050", "#9040b0", "#d08000", "#404040"};
    std::ostringstream s;
    s << gnuplot_preamble(png, 700 * int(surfaces.size()) + 100, 1000, 11);
    s << "set multiplot layout 2," << surfaces.size() << " columnsfirst title "
      << gp_dq("Error against tessellation, per pixel and per vertex (precise kernels)\n{/*0.8 " + plain(subtitle) + "}")
      << " font 'sans,14'\n";
    for (const auto& surf : surfaces) {
        int lo = 1 << 30, hi = -1;
        for (const auto& r : rows)
            if (r.surface == surf) lo = std::min(lo, r.level), hi = std::max(hi, r.level);
        const bool sphere = surf == "icosphere";
        const std::string xl = sphere ? "icosphere subdivision level (20 x 4^{level} triangles)"
                                      : "Loop subdivision level of " + plain(surf) + " (x4 triangles per level)";
        const std::string against = sphere ? "against the exact sphere" : "against its finest Loop level";
        for (int metric = 0; metric < 2; ++metric) {
            const std::string col = metric == 0 ? "plot_de2000_p99" : "plot_de2000_mean";
            s << "set title " << gp_string(plain(surf) + ": " + (metric == 0 ? "p99 Delta E 2000 " : "mean Delta E 2000 ") + against)
              << "\nset xlabel " << gp_string(xl) << "\nset ylabel "
              << gp_string(metric == 0 ? "p99 Delta E 2000 (log scale)"
                                       : "mean Delta E 2000 (log scale)")
              << "\nset logscale y\nunset logscale x\nset format y '10^{%L}'\nset xtics 1\nset xrange ["
              << lo - 0.2 << ":" << hi + 0.2 << "]\nset key bottom left box opaque\nplot ";
            bool first = true;
            for (std::size_t mi = 0; mi < models.size(); ++mi)
                for (int pv = 0; pv < 2; ++pv) {
                    const std::string cond = "(strcol('surface') eq " + gp_string(surf) + " && strcol('model') eq " +
                                             gp_string(models[mi]) + " && column('per_vertex') == " + std::to_string(pv) +
                                             " ? column('" + col + "') : NaN)";
                    s << (first ? "" : ", ") << gp_string(csv) << " using 'level':" << cond << " with linespoints lw 2 pt "
                      << (pv ? 6 : 7) << " dt " << (pv ? 2 : 1) << " lc rgb '" << colours[mi % 6] << "' title "
                      << gp_string(models[mi] + (pv ? ", per vertex" : ", per pixel")) << " noenhanced";
                    first = false;
                }
            s << "\n";
        }
    }
    s << "unset multiplot\n";
    plot::run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
}

}  // namespace shadelab::speed
