// Perspective camera: view and projection matrices (glm, OpenGL conventions) and framing of a bounding box.
#include "raster/camera.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"

namespace shadelab {

namespace {

std::string str(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

std::string str(const glm::dvec3& v) { return "(" + str(v.x) + ", " + str(v.y) + ", " + str(v.z) + ")"; }

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

// Right-handed look-at: the camera sits at eye, looks along target - eye (view-space -z), up is view +y.
glm::dmat4 Camera::view() const { return glm::lookAt(eye, target, up); }

// OpenGL perspective: maps view-space z = -z_near to NDC z = -1 and z = -z_far to +1; clip w = -z_view.
glm::dmat4 Camera::projection(double aspect) const {
    return glm::perspective(glm::radians(fov_y_deg), aspect, z_near, z_far);
}

Camera Camera::fit(const Bounds& b, glm::dvec3 from_dir, double fov_y_deg, double aspect) {
    if (!(fov_y_deg > 0.0 && fov_y_deg < 180.0))
        throw Error("camera fit: field of view " + str(fov_y_deg) + " deg is out of range: must be in (0, 180)");
    if (!(aspect > 0.0) || !std::isfinite(aspect))
        throw Error("camera fit: aspect ratio " + str(aspect) + " is out of range: must be finite and > 0");
    if (!finite(b.lo) || !finite(b.hi))
        throw Error("camera fit: bounds " + str(b.lo) + " - " + str(b.hi) + " are not finite");
    const double len = glm::length(from_dir);
    if (!(len > 0.0) || !std::isfinite(len))
        throw Error("camera fit: view direction " + str(from_dir) + " must be a finite, non-zero vector");
    const glm::dvec3 dir = from_dir / len;

    // A sphere of radius r seen from distance d subtends a half-angle asin(r / d); it fits a field of view
    // of half-angle h when r / d <= sin(h), i.e. d >= r / sin(h). The horizontal half-angle follows from
    // the vertical one through the image plane: tan(h_x) = aspect * tan(h_y). Take the tighter of the two
    // and leave a 5% margin.
    const double r = std::max(b.radius(), 1e-9);
    const double half_v = glm::radians(fov_y_deg) * 0.5;
    const double half_h = std::atan(std::tan(half_v) * aspect);
    const double d = 1.05 * r / std::sin(std::min(half_v, half_h));

    Camera c;
    c.target = b.centre();
    c.eye = c.target + dir * d;
    // World up, unless we look (almost) straight along it; then world z serves as up.
    c.up = std::abs(glm::dot(dir, glm::dvec3(0, 1, 0))) > 0.999 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    c.fov_y_deg = fov_y_deg;
    // The sphere occupies view depths [d - r, d + r]; 1.5 r leaves slack on both sides, and the near plane
    // never comes closer than d / 1000 (depth precision; the sphere is never that close when it fits).
    c.z_near = std::max(d - 1.5 * r, d * 1e-3);
    c.z_far = d + 1.5 * r;
    return c;
}

}  // namespace shadelab
