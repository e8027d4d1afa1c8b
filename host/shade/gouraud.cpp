#include "shade/gouraud.hpp"

#include "core/error.hpp"

namespace shadelab {

std::vector<float> shade_vertices(Shader& shader, const Mesh& mesh, const ShadeSetup& setup, ShadeTiming* timing) {
    FragmentBuffer vb;
    vb.reserve(mesh.positions.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const glm::dvec3& p = mesh.positions[i];
        const glm::dvec3& n = mesh.normals[i];
        vb.push_back(float(p.x), float(p.y), float(p.z), float(n.x), float(n.y), float(n.z), -1, 0.0f);
    }
    return shader.shade(vb, setup, timing);
}

std::vector<float> interpolate_to_fragments(const FragmentBuffer& fb, const Mesh& mesh, const std::vector<float>& vp) {
    const std::size_t n = fb.size(), nv = mesh.positions.size();
    if (fb.triangle.size() != n || fb.b1.size() != n || fb.b2.size() != n)
        throw Error("per-vertex evaluation needs a fragment buffer from the rasteriser (triangle ids and barycentrics)");
    if (vp.size() != 3 * nv) throw Error("per-vertex colours do not match the mesh's vertex count");
    std::vector<float> out(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        const auto& t = mesh.triangles[std::size_t(fb.triangle[i])];
        const float w1 = fb.b1[i], w2 = fb.b2[i], w0 = 1.0f - w1 - w2;
        for (std::size_t c = 0; c < 3; ++c)
            out[c * n + i] = w0 * vp[c * nv + t[0]] + w1 * vp[c * nv + t[1]] + w2 * vp[c * nv + t[2]];
    }
    return out;
}

}  // namespace shadelab
