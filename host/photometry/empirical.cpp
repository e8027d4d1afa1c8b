#include "photometry/empirical.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/error.hpp"
#include "core/format.hpp"

namespace shadelab::photometry {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr int kRadius = 50;   // samples: the half disc x = -50..50, y = 0..50

// One sample of the sphere: its incidence and emission at phase g (degrees).
struct Sample {
    double x, z;   // in radii; y is not needed beyond the selection of the disc
};

std::vector<Sample> disc_samples() {
    std::vector<Sample> s;
    const double r = kRadius, r2 = r * r;
    for (int y = 0; y <= kRadius; ++y)
        for (int x = -kRadius; x <= kRadius; ++x) {
            const double s2 = double(x) * x + double(y) * y;
            if (s2 >= r2) continue;
            s.push_back({x / r, std::sqrt(r2 - s2) / r});
        }
    return s;
}

double incidence_deg(const Sample& s, double g) {
    return std::acos(std::clamp(std::cos(g * kDeg) * s.z - std::sin(g * kDeg) * s.x, -1.0, 1.0)) / kDeg;
}
double emission_deg(const Sample& s) { return std::acos(std::clamp(s.z, -1.0, 1.0)) / kDeg; }

// The simple laws with parameter p, as ISIS's Minnaert and LunarLambert return them (0 unlit or unseen).
double simple_law(int law, double p, double i_deg, double e_deg) {
    if (i_deg >= 90.0 || e_deg >= 90.0) return 0.0;
    const double mu0 = std::cos(i_deg * kDeg), mu = std::cos(e_deg * kDeg);
    if (law == 1) return mu0 * std::pow(mu0 * mu, p - 1.0);
    return mu0 * ((1.0 - p) + 2.0 * p / (mu0 + mu));
}

// The points of one phase: law inputs and Hapke values.
struct PhaseData {
    std::vector<double> inc, ema, hapke;
};

PhaseData phase_data(Runtime& rt, const Law& hapke, const EmpiricalOptions& o, double g, double emamax) {
    static const std::vector<Sample> disc = disc_samples();
    PhaseData d;
    std::vector<Geometry> rows;
    for (const Sample& s : disc) {
        const double i = incidence_deg(s, g), e = emission_deg(s);
        if (i >= o.incmin && i <= o.incmax && e >= o.emamin && e <= emamax) {
            d.inc.push_back(i);
            d.ema.push_back(e);
            rows.push_back({g, i, e});
        }
    }
    d.hapke = evaluate(rt, hapke, rows);
    return d;
}

struct Fit {
    bool ok = false;
    double rms = 0.0, c0 = 0.0, c1 = 0.0;
};

// The closed-form linear least squares of Hapke on the law at parameter p.
Fit linear_fit(const PhaseData& d, int law, double p, bool offset) {
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
    for (std::size_t k = 0; k < d.hapke.size(); ++k) {
        const double x = simple_law(law, p, d.inc[k], d.ema[k]), y = d.hapke[k];
        n += 1;
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
        syy += y * y;
    }
    Fit f;
    if (n < 1 || sxx <= 0 || (offset && n * sxx - sx * sx == 0)) return f;
    double arg;
    if (!offset) {
        f.c1 = sxy / sxx;
        arg = (syy - 2 * f.c1 * sxy + f.c1 * f.c1 * sxx) / n;
    } else {
        const double den = n * sxx - sx * sx;
        f.c0 = (sxx * sy - sx * sxy) / den;
        f.c1 = (n * sxy - sx * sy) / den;
        arg = (syy + 2 * (f.c0 * f.c1 * sx - f.c0 * sy - f.c1 * sxy) + f.c0 * f.c0 * n + f.c1 * f.c1 * sxx) / n;
    }
    f.rms = arg > 0 ? std::sqrt(arg) : 0.0;
    f.ok = std::isfinite(f.rms);
    return f;
}

// The parameter minimising the rms: a scan of [-2, 4] in steps of 0.01 (the laws' useful range with margin),
// then golden-section search in the bracket around the best step to 1e-10.
double minimise(const PhaseData& d, int law, bool offset) {
    auto rms = [&](double p) {
        const Fit f = linear_fit(d, law, p, offset);
        return f.ok ? f.rms : INFINITY;
    };
    double best = 0.0, best_r = INFINITY;
    for (int k = 0; k <= 600; ++k) {
        const double p = -2.0 + 0.01 * k, r = rms(p);
        if (r < best_r) { best_r = r; best = p; }
    }
    double a = best - 0.01, b = best + 0.01;
    const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
    double c = b - phi * (b - a), e = a + phi * (b - a), fc = rms(c), fe = rms(e);
    while (b - a > 1e-10) {
        if (fc < fe) { b = e; e = c; fe = fc; c = b - phi * (b - a); fc = rms(c); }
        else { a = c; c = e; fc = fe; e = a + phi * (b - a); fe = rms(e); }
    }
    return 0.5 * (a + b);
}

}  // namespace

SimpleFit fit_simple_law(int law, const std::vector<double>& inc, const std::vector<double>& ema,
                         const std::vector<double>& values, bool offset) {
    if (inc.size() != values.size() || ema.size() != values.size()) throw Error("internal: fit_simple_law sizes");
    if (values.size() < 3) throw Error("photometry: fewer than 3 samples to fit the law to");
    PhaseData d;
    d.inc = inc;
    d.ema = ema;
    d.hapke = values;
    SimpleFit f;
    f.samples = values.size();
    f.param = minimise(d, law, offset);
    const Fit lf = linear_fit(d, law, f.param, offset);
    if (!lf.ok) throw Error("photometry: the law cannot be fitted to these samples (all zero?)");
    f.c1 = lf.c1;
    f.c0 = lf.c0;
    f.rms = lf.rms;
    return f;
}

void check_empirical_options(const EmpiricalOptions& o) {
    auto in = [](double v, double lo, double hi, const char* name) {
        if (!std::isfinite(v) || v < lo || v > hi)
            throw Error(std::string("photometry empirical: --") + name + " " + num(v) + " is out of range: allowed " +
                        num(lo) + " to " + num(hi) + " degrees");
    };
    if (o.law != 1 && o.law != 2) throw Error("photometry empirical: --law must be lunar_lambert or minnaert");
    if (o.nph < 2 || o.nph > 100000)
        throw Error("photometry empirical: --nph " + std::to_string(o.nph) + " is out of range: allowed 2 to 100000");
    in(o.phmin, 0, 180, "phmin");
    in(o.phmax, 0, 180, "phmax");
    in(o.incmin, 0, 180, "incmin");
    in(o.incmax, 0, 180, "incmax");
    in(o.emamin, 0, 90, "emamin");
    in(o.emamax, 0, 180, "emamax");
    if (!(o.phmax > o.phmin)) throw Error("photometry empirical: --phmax must be greater than --phmin");
    if (!(o.incmax > o.incmin)) throw Error("photometry empirical: --incmax must be greater than --incmin");
    if (!(o.emamax > o.emamin)) throw Error("photometry empirical: --emamax must be greater than --emamin");
    if (!std::isfinite(o.emamax_pcoeff) || o.emamax_pcoeff < 0 || o.emamax_pcoeff > 10)
        throw Error("photometry empirical: --emamax-pcoeff " + num(o.emamax_pcoeff) + " is out of range: allowed 0 to 10");
}

EmpiricalTable fit_empirical(Runtime& rt, const Law& hapke, const EmpiricalOptions& o) {
    check_empirical_options(o);
    if (hapke.empirical || (hapke.material.model != "hapke_hen" && hapke.material.model != "hapke_leg"))
        throw Error((hapke.source.empty() ? std::string("photometry empirical") : hapke.source) +
                    ": the law to fit to must be Hapke (HapkeHen or HapkeLeg), not " +
                    (hapke.isis_name.empty() ? hapke.material.model : hapke.isis_name));
    EmpiricalTable t;
    // The zero-phase multiplier that normalises the phase curve (without offset): at g = 0, emission limit emamax.
    double c1_0 = 0.0;
    if (!o.offset) {
        const PhaseData d0 = phase_data(rt, hapke, o, 0.0, o.emamax);
        const double p0 = minimise(d0, o.law, false);
        c1_0 = linear_fit(d0, o.law, p0, false).c1;
        if (!(c1_0 > 0)) throw Error("photometry empirical: no fit at zero phase to normalise the phase curve (check the angle limits)");
    }
    const double dph = (o.phmax - o.phmin) / double(o.nph - 1);
    for (int k = 0; k < o.nph; ++k) {
        EmpiricalRow row;
        row.phase = o.phmin + dph * k;
        const double emamax = o.emamax + o.emamax_pcoeff * row.phase;
        const PhaseData d = phase_data(rt, hapke, o, row.phase, emamax);
        row.samples = d.hapke.size();
        row.param = minimise(d, o.law, o.offset);
        const Fit f = linear_fit(d, o.law, row.param, o.offset);
        if (!f.ok || row.samples < 3) {
            t.warnings.push_back("phase " + num(row.phase) + " deg: " + std::to_string(row.samples) +
                                 " samples inside the limits, no fit: the row is left out of the table");
            continue;
        }
        row.c0 = f.c0;
        row.c1 = f.c1;
        row.rms = f.rms;
        row.brightness = o.offset ? f.c1 : f.c1 / c1_0;
        t.rows.push_back(row);
    }
    if (t.rows.size() < 3) throw Error("photometry empirical: fewer than 3 phases could be fitted (check the angle limits)");
    return t;
}

std::string empirical_pvl(const EmpiricalTable& t, const EmpiricalOptions& o, const Law& hapke) {
    std::ostringstream s;
    auto list = [&](const char* key, auto get) {
        s << "    " << key << " = (";
        for (std::size_t k = 0; k < t.rows.size(); ++k) {
            s << (k ? ", " : "") << (k && k % 4 == 0 ? "\n        " : "") << num(get(t.rows[k]), 14);
        }
        s << ")\n";
    };
    s << "/* Written by shadelab photometry empirical: " << (o.law == 1 ? "Minnaert K(g)" : "Lunar-Lambert L(g)")
      << " fitted to " << hapke.describe() << " (docs/photometry.md) */\n";
    s << "Object = PhotometricModel\n  Group = Algorithm\n    Name = "
      << (o.law == 1 ? "MinnaertEmpirical" : "LunarLambertEmpirical") << "\n";
    list("PhaseList", [](const EmpiricalRow& r) { return r.phase; });
    list(o.law == 1 ? "KList" : "LList", [](const EmpiricalRow& r) { return r.param; });
    list("PhaseCurveList", [](const EmpiricalRow& r) { return r.brightness; });
    s << "  End_Group\n  Group = Fit\n"
      << "    NPH = " << o.nph << "\n    PHMIN = " << o.phmin << "\n    PHMAX = " << o.phmax << "\n    INCMIN = "
      << o.incmin << "\n    INCMAX = " << o.incmax << "\n    EMAMIN = " << o.emamin << "\n    EMAMAX = " << o.emamax
      << "\n    EMAMAX_PCOEFF = " << o.emamax_pcoeff << "\n    IORD = " << (o.offset ? "TRUE" : "FALSE") << "\n";
    list("RmsList", [](const EmpiricalRow& r) { return r.rms; });
    list("SampleList", [](const EmpiricalRow& r) { return double(r.samples); });
    if (o.offset) list("OffsetList", [](const EmpiricalRow& r) { return r.c0; });
    s << "  End_Group\nEnd_Object\nEnd\n";
    return s.str();
}

}  // namespace shadelab::photometry
