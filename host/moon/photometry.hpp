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

// --- Reflectance laws in mu0, mu (values are I/F for unit solar flux: a white Lambert surface lit and seen
// head-on gives 1, as everywhere in shadelab). Each returns 0 where mu0 <= 0 (unlit) or mu <= 0 (not seen).
//
// At the limb (mu -> 0) Minnaert's law with k < 1 grows without bound like mu^(k-1): these functions
// evaluate mu as max(mu, kMuFloor) so the result stays finite; kMuFloor = 1e-9 only matters for points
// within 1e-18 disc radii of the limb, never at a pixel centre of a sane image.
constexpr double kMuFloor = 1e-9;

// Minnaert (1941), ApJ 93:403: I = B0 mu0^k mu^(k-1). At zero phase I = B0 mu^(2k-1): k = 0.5 is a flat disc,
// k = 1 is Lambert.
double minnaert(double mu0, double mu, double k, double B0);
// Lambert: I = B0 mu0.
double lambert(double mu0, double B0);
// Lommel-Seeliger: I = B0 mu0 / (mu0 + mu) (flat disc at zero phase, value B0/2).
double lommel_seeliger(double mu0, double mu, double B0);
// Lunar-Lambert (McEwen 1991, Icarus 92:298): I = B0 mu0 ((1 - L) + 2 L / (mu0 + mu)).
// L = 0 is Lambert, L = 1 is twice Lommel-Seeliger.
double lunar_lambert(double mu0, double mu, double L, double B0);

// A reflectance law to draw curves of, or to compare an image with.
//  kind "minnaert" (param k), "lambert", "lommel_seeliger", "lunar_lambert" (param L): the closed forms above;
//  kind "catalogue": any model of the catalogue, evaluated with its double-precision reference
//  (host/reference/) on the exact sphere normal, grey albedo B0; `material` holds its parameters.
struct PhotometricModel {
    std::string kind = "minnaert";
    double k = 0.5;
    double lunar_l = 1.0;   // McEwen's L
    double B0 = 1.0;
    Material material;      // kind "catalogue" only (resolved)

    // The value at unit normal N for this sun (uses mu0, mu for the closed forms, N, L, V for catalogue models).
    double value(const glm::dvec3& N, const SunGeometry& sun) const;
    std::string describe() const;   // "minnaert k=0.7 B0=1", for plot titles and reports
};

// Builds a model from what the user typed: the four closed-form names (also "lommel-seeliger",
// "lunar-lambert"), else a catalogue model name (throws the catalogue's one-line error when unknown).
// `params` are name=value for catalogue models; k and L apply to the closed forms.
PhotometricModel make_photometric_model(const std::string& name, double k, double lunar_l, double B0,
                                        const std::map<std::string, double>& params = {});

// --- The catalogue's Minnaert family in photometric cosines, written from docs/models/minnaert.md (no code
// shared with the kernels or the references), and the 1941 law each one equals.
//   minnaert_1941 (k)        B0 mu0^k mu^(k-1)                  k_1941 = k,      B0 = albedo
//   minnaert_normalized (k)  albedo (k+1)/2 mu0^k mu^(k-1)      k_1941 = k,      B0 = albedo (k+1)/2
//   minnaert_unity (k)       albedo min(1, mu0^(k+1) mu^k)      k_1941 = k + 1,  B0 = albedo, where the law <= 1
//   minnaert_blender (d<=1)  albedo mu0 max(mu mu0, 0.1)^(d-1)  k_1941 = d,      B0 = albedo, where mu mu0 >= 0.1
//   minnaert_blender (d>1)   albedo mu0 (1.001 - mu)^(d-1)      no 1941 equivalent
//   minnaert_b (k)           albedo mu0^(1+k) (1 - mu)^(1-k)    no 1941 equivalent
//   lambert                  albedo mu0                         k_1941 = 1,      B0 = albedo
// The kernels' limb guard (mu or mu0 < 1e-3 with k < 1, docs/models/minnaert.md) is not part of these forms.
struct MinnaertEquivalent {
    bool exists = false;   // the model equals B0 mu0^k mu^(k-1) where `where` says
    double k = 0.0, B0 = 0.0;
    std::string where;     // the condition, or why there is no equivalent
};
MinnaertEquivalent minnaert_equivalent(const Material& resolved);
// The model's value for mu0, mu > 0 (0 otherwise). Throws for models outside the table above.
double minnaert_variant_value(const Material& resolved, double mu0, double mu);

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
