// ISIS3's photometric models by their ISIS names, read from ISIS's own PVL parameter files, and evaluated at
// (phase, incidence, emission) in degrees - on PoCL (kernels/photometry.cl) or with the double references.
//
// ISIS name               shadelab model                 keywords (ISIS defaults)
// Lambert                 lambert                        -
// LommelSeeliger          lommel_seeliger                -
// LunarLambert            lunar_lambert                  L (1)
// LunarLambertMcEwen      lunar_lambert_mcewen_ratio     - (McEwen's M1..M3 are fixed in ISIS)
// Minnaert                minnaert_1941                  K (1)
// HapkeHen                hapke_hen                      Wh (0.5) B0 (0) Hh (0) Theta (0) Hg1 (0) Hg2 (0) ZeroB0Standard
// HapkeLeg                hapke_leg                      Wh (0.5) B0 (0) Hh (0) Theta (0) Bh (0) Ch (0) ZeroB0Standard
// MinnaertEmpirical       tables K(g), B(g)              PhaseList KList PhaseCurveList (no defaults)
// LunarLambertEmpirical   tables L(g), B(g)              PhaseList LList PhaseCurveList (no defaults)
// docs/photometry.md has the formulas and every difference from ISIS.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "cl/runtime.hpp"
#include "core/spline.hpp"
#include "models/material.hpp"
#include "photometry/pvl.hpp"
#include "shade/shader.hpp"

namespace shadelab::photometry {

// ISIS's interpolation of the empirical tables: the natural cubic spline of host/core/spline.hpp.
using shadelab::NaturalSpline;

// A photometric law as a PVL file or the command line describes it.
struct Law {
    std::string isis_name;      // "HapkeHen", or "" for a catalogue model given by name
    std::string source;         // the PVL file, for messages
    Material material;          // the catalogue model with albedo 1 (the empirical laws: their catalogue model and tables)
    int empirical = 0;          // 0: a catalogue model; 1: MinnaertEmpirical; 2: LunarLambertEmpirical
    std::vector<double> phases, params, brightness;   // the empirical tables
    NaturalSpline param_of_phase, brightness_of_phase;
    std::vector<std::string> warnings;                // keywords ISIS reads but that change nothing here, ...
    bool zero_b0_standard = true;                     // Hapke: B0 = 0 at the standard (reference) conditions
    std::string describe() const;                     // "HapkeHen -> hapke_hen wh=0.52 ..."
};

// The ISIS names this reader knows.
const std::vector<std::string>& isis_model_names();

// From the Algorithm group of the PhotometricModel object. Throws shadelab::Error, one line naming the file,
// the line, the keyword and its allowed range, for: no PhotometricModel object or Algorithm group, no Name, an
// unknown model, a value that is not a number, a value out of range, a missing table, tables of different
// lengths or fewer than 3 entries, a phase table not strictly increasing or outside [0, 180].
Law law_from_pvl(const pvl::Block& root, const std::string& file);
Law law_from_pvl_file(const std::string& path);
// The law at ISIS's standard conditions: for Hapke with ZeroB0Standard (ISIS's default) the opposition surge B0
// set to 0, as ISIS's SetStandardConditions does when it evaluates the reference value of a normalisation.
Law standard_conditions(const Law& law);
// A catalogue model by shadelab name with name=value parameters (--model hapke_hen -p wh=0.52).
// Tables (the empirical family's phase_list, k_list, ...) by name; its models then take ISIS's empirical path.
Law law_from_model(const std::string& model, const std::map<std::string, double>& params,
                   const std::map<std::string, std::vector<double>>& tables = {});

struct Geometry {
    double phase = 0.0, incidence = 0.0, emission = 0.0;   // degrees
};
// Each angle finite and in [0, 180] degrees; throws "<where>: phase 181 is out of range: allowed 0 to 180 degrees".
void check_geometry(const Geometry& g, const std::string& where);

// The law at every row, on the OpenCL device (float). Rows are checked first (check_geometry). Non-finite values
// (only from invalid input) are written as 0, except with `raw` (the tests: so that they can be counted).
std::vector<double> evaluate(Runtime& rt, const Law& law, const std::vector<Geometry>& rows,
                             Precision precision = Precision::Precise, bool raw = false);
// The seven per-row inputs of kernels/photometry.cl for rows[first, first + n), computed in double and stored as
// float: cos i, cos e, sin i, sin e, cos g, tan(g/2), tan(psi/2) (the empirical laws: cos i, cos e, K(g) or L(g),
// B(g) in the first four). Padded to `padded` rows with mu0 = mu = 0 (unlit: the kernels have no bounds check).
struct PhoArrays {
    std::vector<float> mu0, mu, sin_i, sin_e, cos_g, tan_half_g, tan_half_psi;
};
PhoArrays pho_arrays(const Law& law, const std::vector<Geometry>& rows, std::size_t first, std::size_t n,
                     std::size_t padded);
// The defines kernels/photometry.cl is built with for this law on a device of `device_width` lanes
// (Runtime::vector_width()).
std::vector<std::string> pho_defines(const Law& law, Precision precision, bool raw, std::size_t device_width);
// The rows a work-item of eval_photometric(_sets) evaluates for this law on a device of `device_width` lanes: the
// device's lanes times its catalogue model's chains (Shader::chains_for: 2 for hapke_hen and hapke_2012 on every
// device, and for McEwen's laws on AVX2 hosts; SHADELAB_CHAINS sets every law's), 1 for the empirical laws
// (eval_empirical); pho_defines builds the program with those chains. The photometric kernels keep the device's
// lanes where a model's shade kernel takes sixteen (Shader::lanes_for): measured no faster there.
std::size_t pho_rows_per_item(const Law& law, std::size_t device_width);

// Enqueues a kernel of kernels/photometry.cl, built for `law` (pho_defines), over `rows` rows (padded: a multiple
// of `local`, the work-group's rows, since the kernels have no bounds check) and `sets` parameter sets
// (eval_photometric_sets' second dimension; 0 for the one-dimensional kernels). eval_photometric and
// eval_photometric_sets take pho_rows_per_item(law, rt.vector_width()) rows a work-item (kernels/common.cl,
// SL_FRAGS_PER_ITEM), eval_empirical (an empirical law's) one.
void enqueue_rows(Runtime& rt, cl::Kernel& k, const Law& law, std::size_t rows, std::size_t local,
                  std::size_t sets = 0);

// The law at one geometry with the double-precision references (host/reference/).
double evaluate_reference(const Law& law, const Geometry& g);

// An empirical law (law.empirical != 0) at every row, in double: throws shadelab::Error naming the first row whose
// value a float cannot hold (ISIS continues the tables' spline beyond their last phase, where it can run away).
// Every evaluation of such a law runs it first, so such a row is refused, never written as a number.
void check_empirical_finite(const Law& law, const std::vector<Geometry>& rows);

}  // namespace shadelab::photometry
