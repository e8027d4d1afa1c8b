// bench_e2e's vertex stage: world-space position and normal pass through to the fragment stage (OpenGL
// interpolates them perspective-correctly); the position goes to clip space with shadelab's camera matrices
// (host/raster/camera.cpp: glm::perspective * glm::lookAt, computed in double on the host, sent as float).
// The program inserts "#version 330 core" above this file.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;

uniform mat4 u_view_projection;

out vec3 v_position;
out vec3 v_normal;

void main() {
    v_position = a_position;
    v_normal = a_normal;
    gl_Position = u_view_projection * vec4(a_position, 1.0);
}
