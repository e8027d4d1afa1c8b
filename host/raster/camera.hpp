// Perspective camera (right-handed, looks down -z in view space, like OpenGL).
#pragma once
#include <glm/glm.hpp>

#include "mesh/mesh.hpp"

namespace shadelab {

struct Camera {
    glm::dvec3 eye{0.0, 0.0, 3.0};
    glm::dvec3 target{0.0, 0.0, 0.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
    double fov_y_deg = 40.0;     // vertical field of view
    double z_near = 0.01;        // clip distances along the view axis, > 0
    double z_far = 1000.0;

    glm::dmat4 view() const;                      // world -> view
    glm::dmat4 projection(double aspect) const;   // view -> clip (OpenGL convention, w = -z_view)

    // A camera looking at the bounds from direction `from_dir` (world, need not be unit), framed so that
    // the bounding sphere fits the vertical and horizontal field of view for the given aspect.
    static Camera fit(const Bounds& b, glm::dvec3 from_dir, double fov_y_deg, double aspect);
};

}  // namespace shadelab
