// Double-precision references of the planetary family (kernels/models/planetary.cl), in photometric angles as
// well as vectors: ISIS3's models are functions of (phase, incidence, emission), which need not be a geometry one
// facet can have (ISIS's unit tests use phase > incidence + emission), so the references take the angles.
#pragma once
#include <string>

#include <glm/glm.hpp>

#include "models/material.hpp"

namespace shadelab::ref {

// The photometric quantities a law reads. psi: the azimuth between the planes of incidence and emission, radians,
// whose cosine is (cos g - mu0 mu) / (sin i sin e) clamped to [-1, 1] (as ISIS), 0 when either sine is 0. It is
// computed without going through that cosine (see angles_from_degrees): near psi = 0 at grazing, Hapke's
// shadowing S(i, e, psi) changes by ~1% for psi = 1e-8 rad, the uncertainty acos(cos psi) leaves in double.
struct PhotometricAngles {
    double mu0 = 1.0, mu = 1.0, sin_i = 0.0, sin_e = 0.0;
    double g_deg = 0.0, psi = 0.0;
};

// From degrees. cos and sin are exact at multiples of 90 degrees (cos 90 = 0, not 6e-17), so a surface at
// i = 90 is unlit and at e = 90 unseen. psi = 2 atan2(sqrt(s), sqrt(c)) with the half-angle products
// s = sin((g+i-e)/2) sin((g-i+e)/2), c = sin((i+e+g)/2) sin((i+e-g)/2) (proportional to sin^2(psi/2), cos^2(psi/2));
// a phase no facet can have gives s < 0 (psi = 0) or c < 0 (psi = pi), ISIS's clamps.
PhotometricAngles angles_from_degrees(double phase_deg, double incidence_deg, double emission_deg);
// From unit vectors (renormalised in double).
PhotometricAngles angles_from_vectors(const glm::dvec3& N, const glm::dvec3& L, const glm::dvec3& V);

// True for the models with a form in photometric angles (their reference registers one: reference.hpp, Table;
// their kernel has a `<name>_pho` function, kernels/photometry.cl's SL_PHO_EVAL): the planetary family's laws and
// those written like them (the Lunar-Lambert family).
bool is_planetary_model(const std::string& model);

// The law's value for albedo 1 (the catalogue's value divided by the albedo) at these angles; 0 where
// mu0 <= 0 or mu <= 0. `m` is a resolved material of such a model; throws shadelab::Error otherwise.
double planetary_value(const Material& m, const PhotometricAngles& a);

// cos and sin of an angle in degrees, exact at multiples of 90 (what angles_from_degrees uses).
double cos_deg(double deg);
double sin_deg(double deg);

}  // namespace shadelab::ref
