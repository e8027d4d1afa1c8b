#include "view/view.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/error.hpp"
#include "image/image.hpp"
#include "moon/disc.hpp"
#include "core/csv.hpp"
#include "plot/gnuplot.hpp"
#include "reference/reference.hpp"

namespace shadelab::view {

namespace {

namespace fs = std::filesystem;
using glm::dvec3;
constexpr double kDeg = M_PI / 180.0;
const dvec3 kN{0.0, 0.0, 1.0};

// pi * f_r: the value divided by NoL (0 below either horizon, where the value is 0 by convention).
double pi_fr(const Material& m, const dvec3& L, const dvec3& V) {
    const double NoL = L.z, NoV = V.z;
    if (NoL <= 1e-9 || NoV <= 0.0) return 0.0;
    const dvec3 v = ref::eval_material(kN, L, V, dvec3(0.0), m);
    const double grey = (v.x + v.y + v.z) / 3.0;
    return std::isfinite(grey) ? grey / NoL : 0.0;
}

// The direction at polar angle theta (degrees, signed: negative on the -x side) in the x-z (incidence) plane.
dvec3 in_plane(double theta_deg) { return {std::sin(theta_deg * kDeg), 0.0, std::cos(theta_deg * kDeg)}; }

std::string col(std::size_t i) { return "m" + std::to_string(i); }

// Incidence-plane lobes: the light at -theta_i (on the -x side), the viewer swept from -90 to 90 degrees, so
// forward scattering (the mirror direction) is at +theta_i.
void polar(const std::vector<ViewModel>& ms, const std::string& dir, const ViewOptions& o, ViewFiles& f) {
    std::vector<std::string> cols{"theta_i", "theta_r"};
    for (std::size_t i = 0; i < ms.size(); ++i) cols.push_back(col(i));
    CsvTable t(cols);
    double rmax = 0.0;
    for (double ti : o.incidence_deg) {
        const dvec3 L = in_plane(-ti);
        for (int s = 0; s < o.polar_steps; ++s) {
            const double tr = -90.0 + 180.0 * s / (o.polar_steps - 1);
            t.row().add(ti).add(tr);
            for (const auto& m : ms) {
                const double v = pi_fr(m.material, L, in_plane(tr));
                rmax = std::max(rmax, v);
                t.add(v);
            }
        }
    }
    const std::string csv = (fs::path(dir) / "polar.csv").string(), png = (fs::path(dir) / "polar.png").string();
    t.write(csv);
    f.written.push_back(csv);
    std::ostringstream s;
    const int panels = int(o.incidence_deg.size());
    s << plot::gnuplot_preamble(png, 420 * panels, 460, 10)
      << "set multiplot layout 1," << panels << " title 'pi f_r in the incidence plane (light from the left; "
      << "radius = value / NoL; 1 = Lambert)'\nset size ratio -1\nset key top right font ',8'\n"
      << "set xrange [-" << plot::gp_number(rmax * 1.05) << ":" << plot::gp_number(rmax * 1.05) << "]\n"
      << "set yrange [0:" << plot::gp_number(rmax * 1.05) << "]\n";
    for (double ti : o.incidence_deg) {
        s << "set title 'theta_i = " << plot::gp_number(ti) << " deg'\nplot ";
        for (std::size_t i = 0; i < ms.size(); ++i) {
            const std::string c = "column('" + col(i) + "')", sel = "(column('theta_i') == " + plot::gp_number(ti) + ")";
            s << (i ? ", " : "") << plot::gp_string(csv) << " using (" << sel << " ? " << c
              << " * sin(column('theta_r') * pi / 180) : 1/0):(" << sel << " ? " << c
              << " * cos(column('theta_r') * pi / 180) : 1/0) with lines lw 2 title " << plot::gp_string(ms[i].label) << " noenhanced";
        }
        s << ", " << "'+' using (-sin(" << plot::gp_number(ti) << " * pi / 180) * " << plot::gp_number(rmax * 0.95)
          << "):(cos(" << plot::gp_number(ti) << " * pi / 180) * " << plot::gp_number(rmax * 0.95)
          << ") with points pt 7 ps 1.5 lc rgb '#e0a000' title 'light'\n";
    }
    s << "unset multiplot\n";
    plot::run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
    f.written.push_back(png);
}

// Directional albedo by the midpoint rule on (cos theta_r, phi): d omega = d(cos theta_r) d phi, so the
// integral of (pi f_r) cos theta_r / pi is a mean over the grid times 2 (the hemisphere's measure 2 pi over pi).
double directional_albedo(const Material& m, double theta_i_deg, int q) {
    const dvec3 L = in_plane(-theta_i_deg);
    double sum = 0.0;
    for (int a = 0; a < q; ++a) {
        const double mu = (a + 0.5) / q, st = std::sqrt(1.0 - mu * mu);
        for (int b = 0; b < 2 * q; ++b) {
            const double phi = M_PI * (b + 0.5) / q;
            sum += pi_fr(m, L, {st * std::cos(phi), st * std::sin(phi), mu}) * mu;
        }
    }
    return 2.0 * sum / (2.0 * q * q);
}

void albedo(const std::vector<ViewModel>& ms, const std::string& dir, const ViewOptions& o, ViewFiles& f) {
    std::vector<std::string> cols{"theta_i"};
    for (std::size_t i = 0; i < ms.size(); ++i) cols.push_back(col(i));
    CsvTable t(cols);
    for (int s = 0; s < o.albedo_steps; ++s) {
        const double ti = 89.0 * s / (o.albedo_steps - 1);
        t.row().add(ti);
        for (const auto& m : ms) t.add(directional_albedo(m.material, ti, o.quadrature));
    }
    const std::string csv = (fs::path(dir) / "albedo.csv").string(), png = (fs::path(dir) / "albedo.png").string();
    t.write(csv);
    f.written.push_back(csv);
    std::ostringstream s;
    s << plot::gnuplot_preamble(png, 800, 500, 11)
      << "set title 'directional albedo (albedo 1)'\nset xlabel 'theta_i (deg)'\nset ylabel 'rho'\n"
      << "set xrange [0:90]\nset yrange [0:*]\nset key bottom left\nplot ";
    for (std::size_t i = 0; i < ms.size(); ++i)
        s << (i ? ", " : "") << plot::gp_string(csv) << " using 'theta_i':'" << col(i) << "' with lines lw 2 title "
          << plot::gp_string(ms[i].label) << " noenhanced";
    s << "\n";
    plot::run_gnuplot(s.str(), png, "the CSV " + csv + " was written");
    f.written.push_back(png);
}

// Rusinkiewicz (1998) half/difference coordinates: H at theta_h in the x-z plane, D at (theta_d, phi_d) in H's
// frame; L = D rotated into the world, V its mirror about H.
void half_diff_dirs(double th, double td, double pd, dvec3& L, dvec3& V) {
    const dvec3 D{std::sin(td) * std::cos(pd), std::sin(td) * std::sin(pd), std::cos(td)};
    const dvec3 H{std::sin(th), 0.0, std::cos(th)};
    L = {D.x * std::cos(th) + D.z * std::sin(th), D.y, -D.x * std::sin(th) + D.z * std::cos(th)};
    V = 2.0 * glm::dot(H, L) * H - L;
}

void slices(const std::vector<ViewModel>& ms, const std::string& dir, const ViewOptions& o, ViewFiles& f) {
    const int n = o.slice_size;
    std::vector<std::string> csvs;
    double vmax = 0.0;
    for (std::size_t i = 0; i < ms.size(); ++i) {
        CsvTable t({"theta_h", "theta_d", "value"});
        for (int a = 0; a < n; ++a)
            for (int b = 0; b < n; ++b) {
                const double th = 90.0 * (a + 0.5) / n, td = 90.0 * (b + 0.5) / n;
                dvec3 L, V;
                half_diff_dirs(th * kDeg, td * kDeg, o.slice_phi_d_deg * kDeg, L, V);
                const double v = pi_fr(ms[i].material, L, V);
                vmax = std::max(vmax, v);
                t.row().add(th, 6).add(td, 6).add(v, 7);
            }
        csvs.push_back((fs::path(dir) / ("slice_" + std::to_string(i) + ".csv")).string());
        t.write(csvs.back());
        f.written.push_back(csvs.back());
    }
    const std::string png = (fs::path(dir) / "slices.png").string();
    std::ostringstream s;
    s << plot::gnuplot_preamble(png, 380 * int(ms.size()) + 80, 420, 10)
      << "set multiplot layout 1," << ms.size() << " title 'pi f_r over theta_h x theta_d (phi_d = "
      << plot::gp_number(o.slice_phi_d_deg) << " deg; log scale)'\n"
      << "set size ratio 1\nset xrange [0:90]\nset yrange [0:90]\nset xlabel 'theta_h'\nset ylabel 'theta_d'\n"
      << "set logscale cb\nset cbrange [" << plot::gp_number(std::max(vmax * 1e-3, 1e-6)) << ":"
      << plot::gp_number(std::max(vmax, 2e-6)) << "]\nset palette rgb 33,13,10\nunset key\n";
    for (std::size_t i = 0; i < ms.size(); ++i)
        s << "set title " << plot::gp_string(ms[i].label) << " noenhanced\nplot " << plot::gp_string(csvs[i])
          << " using 'theta_h':'theta_d':(column('value') > 0 ? column('value') : 1/0) with image\n";
    s << "unset multiplot\n";
    plot::run_gnuplot(s.str(), png, "the CSVs slice_*.csv were written");
    f.written.push_back(png);
}

// The lit sphere of each model by its kernel (the moon disc renderer: orthographic view, one directional light
// at the given phase), and all of them side by side in one strip.
void spheres(Runtime& rt, const std::vector<ViewModel>& ms, const std::string& dir, const ViewOptions& o,
             ViewFiles& f) {
    const int n = o.sphere_size;
    Image strip(n * int(ms.size()), n, 4);
    for (std::size_t i = 0; i < ms.size(); ++i) {
        moon::DiscRenderOptions ro;
        ro.width = ro.height = n;
        ro.material = ms[i].material;
        ro.sun = moon::sun_geometry(o.sphere_phase_deg, 45.0);
        ro.background = {0.0, 0.0, 0.0, 1.0};
        const Image img = moon::render_disc(rt, ro);
        const std::string png = (fs::path(dir) / ("sphere_" + std::to_string(i) + ".png")).string();
        write_image(png, img);
        f.written.push_back(png);
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                for (int c = 0; c < 4; ++c) strip.at(int(i) * n + x, y, c) = img.at(x, y, c);
    }
    const std::string png = (fs::path(dir) / "spheres.png").string();
    write_image(png, strip);
    f.written.push_back(png);
}

}  // namespace

ViewFiles write_views(Runtime& rt, const std::vector<ViewModel>& models, const std::string& dir,
                      const ViewOptions& o) {
    if (models.empty()) throw Error("view: give at least one model");
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw Error("cannot create the output folder '" + dir + "': " + ec.message() + ": choose a writable folder");
    plot::find_gnuplot();   // before any work
    ViewFiles f;
    polar(models, dir, o, f);
    albedo(models, dir, o, f);
    slices(models, dir, o, f);
    spheres(rt, models, dir, o, f);
    return f;
}

}  // namespace shadelab::view
