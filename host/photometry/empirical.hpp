// Empirical phase tables from a Hapke surface, as ISIS3's phoempglobal makes them (McEwen 1991; Kirk et al. 2000):
// at each of nph phase angles from phmin to phmax, a Lunar-Lambert L or Minnaert K and a brightness are fitted
// to the Hapke law over part of the visible hemisphere of a uniform sphere; the table is written in ISIS's PVL
// form (Name = LunarLambertEmpirical / MinnaertEmpirical, PhaseList, LList / KList, PhaseCurveList), which
// ISIS's photomet and shadelab's `photometry eval` read back.
//
// The method, as phoempglobal's documentation and its Isis2 origin (pho_fit_global) define it:
//  - the sphere: the half disc of radius 50 samples, x = -50..50, y = 0..50 (51 x 101 samples), every sample
//    strictly inside the circle; at sample (x, y), z = sqrt(50^2 - x^2 - y^2), cos e = z/50 and, with the sun
//    tilted by the phase g towards -x, cos i = cos(g) z/50 - sin(g) x/50;
//  - the samples used: incmin <= i <= incmax and emamin <= e <= emamax + emamax_pcoeff * g;
//  - at a fixed parameter p (L or K), the least-squares fit Hapke = c1 * law_p (or c0 + c1 * law_p with
//    --offset) in closed form, and its rms residual; p is the minimiser of that rms;
//  - the brightness written is c1 / c1(g = 0) (the zero-phase fit with the emission limit not grown), a phase
//    curve normalised to 1 at opposition; with --offset the raw c1 (normalising would mix in c0), c0 reported
//    beside it.
// The Hapke values come from the PoCL kernel (photometry::evaluate); the simple laws are evaluated in double.
#pragma once
#include <string>
#include <vector>

#include "cl/runtime.hpp"
#include "photometry/isis.hpp"

namespace shadelab::photometry {

struct EmpiricalOptions {
    int law = 2;                 // 1: Minnaert K(g); 2: Lunar-Lambert L(g)
    int nph = 19;
    double phmin = 0.0, phmax = 180.0;
    double incmin = 0.0, incmax = 90.0;
    double emamin = 0.0, emamax = 90.0, emamax_pcoeff = 0.0;
    bool offset = false;         // phoempglobal's IORD: fit an additive offset too
};
// Throws one line naming the option and its allowed range.
void check_empirical_options(const EmpiricalOptions& o);

struct EmpiricalRow {
    double phase = 0.0;
    double param = 0.0;          // L or K
    double c1 = 0.0, c0 = 0.0;   // the multiplier and (with offset) the additive term of the fit
    double brightness = 0.0;     // c1 / c1(0), or c1 with offset
    double rms = 0.0;            // rms residual of the fit (the Hapke values' units)
    std::size_t samples = 0;
};

struct EmpiricalTable {
    std::vector<EmpiricalRow> rows;
    std::vector<std::string> warnings;   // phases without samples, dropped from the table
};

// The same fit on given samples (a user's disc image, at one phase): law 1 Minnaert K, 2 Lunar-Lambert L; values
// fitted as c1 * law_p (or c0 + c1 * law_p with offset), p minimising the rms. Throws when fewer than 3 samples.
struct SimpleFit {
    double param = 0.0, c1 = 0.0, c0 = 0.0, rms = 0.0;
    std::size_t samples = 0;
};
SimpleFit fit_simple_law(int law, const std::vector<double>& inc_deg, const std::vector<double>& ema_deg,
                         const std::vector<double>& values, bool offset);

// `hapke` is a Law of the hapke_hen or hapke_leg model (from a PVL file or by name).
EmpiricalTable fit_empirical(Runtime& rt, const Law& hapke, const EmpiricalOptions& o);

// The PVL text ISIS reads: Object PhotometricModel / Group Algorithm with the tables, and a Group Fit recording
// the controls, the Hapke law and per phase the rms, samples and (with offset) c0.
std::string empirical_pvl(const EmpiricalTable& t, const EmpiricalOptions& o, const Law& hapke);

}  // namespace shadelab::photometry
