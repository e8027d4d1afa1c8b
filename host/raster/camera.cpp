#include "raster/camera.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace shadelab {

glm::dmat4 Camera::view() const { return glm::lookAt(eye, target, up); }

glm::dmat4 Camera::projection(double aspect) const {
    return glm::perspective(glm::radians(fov_y_deg), aspect, z_near, z_far);
}

Camera Camera::fit(const Bounds& b, glm::dvec3 from_dir, double fov_y_deg, double aspect) {
    Camera c;
    const double len = glm::length(from_dir);
    const glm::dvec3 dir = len > 0.0 ? from_dir / len : glm::dvec3(0, 0, 1);
    const double r = std::max(b.radius(), 1e-9);
    const double half_v = glm::radians(fov_y_deg) * 0.5;
    const double half_h = std::atan(std::tan(half_v) * aspect);
    // The bounding sphere fits a cone of half-angle h at distance r / sin(h); 5% margin.
    const double d = 1.05 * r / std::sin(std::min(half_v, half_h));
    c.target = b.centre();
    c.eye = c.target + dir * d;
    c.up = std::abs(glm::dot(dir, glm::dvec3(0, 1, 0))) > 0.999 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    c.fov_y_deg = fov_y_deg;
    c.z_near = std::max(d - 1.5 * r, d * 1e-3);
    c.z_far = d + 1.5 * r;
    return c;
}

}  // namespace shadelab
