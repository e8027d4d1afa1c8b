// Lunar photometry: the geometry of a lit sphere seen from far away, and the classical disc-resolved
// reflectance laws written in the photometric angles (i, e, g; mu0 = cos i, mu = cos e).
//
// Conventions (docs/moon.md has the figure):
//  - World frame: x to the right of the image, y up the image, z towards the observer. The observer and the
//    sun are at infinity: V = (0, 0, 1) for every point (orthographic view), L is one direction.
//  - Image: row 0 is the top row, x grows to the right; pixel (i, j) has its centre at (i + 0.5, j + 0.5)
//    (the rasteriser's convention). "Up" in the image is north, "left" is east, as on the sky.
//  - Position angle (pa) of the sun: the direction from the disc centre towards the sun (the middle of the
//    bright limb), measured from image up (north) towards image left (east), counter-clockwise as displayed.
//  - From (phase alpha, pa): u = (-sin pa, cos pa, 0) is the projected sun direction on the image,
//    L = cos(alpha) V + sin(alpha) u. The photometric equator is the great circle through the sub-observer
//    and the sub-solar points; w = V x u completes the right-handed frame (u, w, V) and points at pa + 90 deg.
//  - Photometric longitude lambda (from the sub-observer meridian, positive towards the sun) and latitude beta
//    (positive towards w) of a unit normal N: N = cos(beta) sin(lambda) u + sin(beta) w + cos(beta) cos(lambda) V,
//    so mu = cos(beta) cos(lambda) and mu0 = cos(beta) cos(lambda - alpha).
#pragma once
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "models/material.hpp"

namespace shadelab::moon {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// Sun and observer for one disc. Built by sun_geometry(), which validates the angles.
struct SunGeometry {
    double phase_deg = 0.0;          // alpha, angle sun-object-observer, [0, 180]
    double pa_deg = 0.0;             // position angle of the sun direction on the image, any value (mod 360)
    glm::dvec3 V{0.0, 0.0, 1.0};     // to the observer
    glm::dvec3 L{0.0, 0.0, 1.0};     // to the sun
    glm::dvec3 u{0.0, 1.0, 0.0};     // projected sun direction on the image (world x right, y up)
    glm::dvec3 w{-1.0, 0.0, 0.0};    // V x u: in the image, 90 deg counter-clockwise from u
};

// Throws shadelab::Error (one line) when phase is outside [0, 180] degrees or either angle is not finite.
SunGeometry sun_geometry(double phase_deg, double pa_deg);

// Where a unit normal sits in photometric coordinates, with its angles. All angles in degrees.
struct PhotometricAngles {
    double mu0 = 0.0, mu = 0.0;           // cos(i), cos(e); negative when unlit / facing away
    double i_deg = 0.0, e_deg = 0.0, g_deg = 0.0;
    double lambda_deg = 0.0, beta_deg = 0.0;
};
PhotometricAngles photometric_angles(const glm::dvec3& N, const SunGeometry& sun);

// The unit normal at photometric longitude lambda and latitude beta (radians).
glm::dvec3 normal_at(double lambda, double beta, const SunGeometry& sun);

// --- Reflectance laws (values are I/F for unit solar flux: a white Lambert surface lit and seen head-on gives 1,
// as everywhere in shadelab); 0 where mu0 <= 0 (unlit) or mu <= 0 (not seen).
//
// Every law is a catalogue model evaluated by its double reference (host/reference/), the same definition the
// kernels compute; moon keeps four names for the classical laws, with its own parameter options:
//   minnaert (--k)          minnaert_1941, k:   B0 mu0^k mu^(k-1), Minnaert (1941) ApJ 93:403, with the
//                           catalogue's limb guard (k < 1: each cosine's power held below 1e-3, faded to 0 at 0)
//   lambert                 lambert:            B0 mu0
//   lommel_seeliger         lommel_seeliger:    B0 mu0 / (mu0 + mu) (albedo B0 / 2 of ISIS's 2 mu0 / (mu0 + mu))
//   lunar_lambert (--lunar-l) lunar_lambert, l: B0 mu0 ((1 - L) + 2 L / (mu0 + mu)), McEwen (1991) Icarus 92:298
// The parameter ranges are the catalogue's (k in [0, 2], L in [-1, 2]).
struct NamedLaw {
    std::string name;    // what the user types ("lommel-seeliger" also)
    std::string model;   // the catalogue model
    std::string param;   // its parameter moon fills from --k ("k") or --lunar-l ("l"), or empty
    std::string title;   // for plot titles and reports
    double b0_scale;     // catalogue albedo = B0 * b0_scale
};
const std::vector<NamedLaw>& named_laws();
// The named law `typed` ('-' read as '_'), or nullptr for any other name (a catalogue model's).
const NamedLaw* named_law(const std::string& typed);

// A reflectance law to draw curves of, or to compare an image with.
//  kind "minnaert" (param k), "lambert", "lommel_seeliger", "lunar_lambert" (param L): the named laws above;
//  kind "catalogue": any model of the catalogue, with grey albedo B0 and its parameters.
// Both are evaluated by `material`'s double-precision reference on the exact sphere normal.
struct PhotometricModel {
    std::string kind = "minnaert";
    double k = 0.5;
    double lunar_l = 1.0;   // McEwen's L
    double B0 = 1.0;
    Material material;      // the catalogue model (resolved) that defines the law

    // The value at unit normal N for this sun: the reference of `material` at N, L, V.
    double value(const glm::dvec3& N, const SunGeometry& sun) const;
    std::string describe() const;   // "Minnaert 1941 k=0.7 B0=1", for plot titles and reports
};

// Builds a model from what the user typed: a named law (k and L its parameters, -p refused), else a catalogue
// model name with `params` name=value (throws the catalogue's one-line error when unknown or out of range).
PhotometricModel make_photometric_model(const std::string& name, double k, double lunar_l, double B0,
                                        const std::map<std::string, double>& params = {});

// --- The catalogue's Minnaert family in photometric cosines (docs/models/minnaert.md), and the 1941 law each
// one equals (what a fitted k of an image rendered with that model should come back as; tests/test_moon.cpp).
//   minnaert_1941 (k)        B0 mu0^k mu^(k-1)                  k_1941 = k,      B0 = albedo
//   minnaert_normalized (k)  albedo (k+1)/2 mu0^k mu^(k-1)      k_1941 = k,      B0 = albedo (k+1)/2
//   minnaert_unity (k)       albedo min(1, mu0^(k+1) mu^k)      k_1941 = k + 1,  B0 = albedo, where the law <= 1
//   minnaert_blender (d<=1)  albedo mu0 max(mu mu0, 0.1)^(d-1)  k_1941 = d,      B0 = albedo, where mu mu0 >= 0.1
//   minnaert_blender (d>1)   albedo mu0 (1.001 - mu)^(d-1)      no 1941 equivalent
//   minnaert_b (k)           albedo mu0^(1+k) (1 - mu)^(1-k)    no 1941 equivalent
//   lambert                  albedo mu0                         k_1941 = 1,      B0 = albedo
// The catalogue's limb guard (mu or mu0 < 1e-3 with k < 1, docs/models/minnaert.md) aside.
struct MinnaertEquivalent {
    bool exists = false;   // the model equals B0 mu0^k mu^(k-1) where `where` says
    double k = 0.0, B0 = 0.0;
    std::string where;     // the condition, or why there is no equivalent
};
MinnaertEquivalent minnaert_equivalent(const Material& resolved);

// --- Analytic profiles of a sphere of radius 1 (positions in disc radii).
struct CurvePoint {
    double s = 0.0;        // position along the profile, disc radii; equator: + towards the sun; across: + along w
    double lambda_deg = 0.0, beta_deg = 0.0;
    double mu0 = 0.0, mu = 0.0;
    double value = 0.0;
};

// n points at s = -1 + (j + 0.5) 2 / n (strictly inside the disc, like pixel centres) along the intensity
// equator (the line through the centre along u).
std::vector<CurvePoint> equator_curve(const PhotometricModel& m, const SunGeometry& sun, int n);
// n points along the chord perpendicular to the equator that crosses it at `offset` disc radii (0: through the
// centre, along w), |offset| < 1.
std::vector<CurvePoint> across_curve(const PhotometricModel& m, const SunGeometry& sun, double offset, int n);

}  // namespace shadelab::moon
