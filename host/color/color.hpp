// Colour: linear sRGB -> CIE XYZ (D65) -> CIE L*a*b*, and the colour differences Delta E*ab (CIE 1976)
// and CIEDE2000. Double precision; used to score rendered images against their references.
#pragma once
#include <glm/glm.hpp>

namespace shadelab {

// IEC 61966-2-1 (sRGB) primaries, D65 white, Y of white = 1.
glm::dvec3 xyz_from_linear_srgb(const glm::dvec3& rgb);
glm::dvec3 linear_srgb_from_xyz(const glm::dvec3& xyz);

// CIE 1976 L*a*b* relative to the D65 white of the sRGB space (Xn, Yn, Zn) = (0.95047, 1, 1.08883).
glm::dvec3 lab_from_xyz(const glm::dvec3& xyz);
glm::dvec3 xyz_from_lab(const glm::dvec3& lab);
glm::dvec3 lab_from_linear_srgb(const glm::dvec3& rgb);

double delta_e76(const glm::dvec3& lab1, const glm::dvec3& lab2);

// CIEDE2000 with kL = kC = kH = 1, following Sharma, Wu & Dalal (2005), eqs. (1)-(22).
double delta_e2000(const glm::dvec3& lab1, const glm::dvec3& lab2);

}  // namespace shadelab
