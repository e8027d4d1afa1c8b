#include "speed/subdivision.hpp"

#include <algorithm>
#include <cmath>

// OpenMesh 9 trips GCC 12's -Wmaybe-uninitialized inside its own headers (see host/mesh/mesh.cpp).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wconversion"
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#pragma GCC diagnostic pop

#include "color/image_compare.hpp"
#include "core/error.hpp"
#include "image/image.hpp"
#include "pipeline/pipeline.hpp"
#include "raster/raster.hpp"
#include "reference/reference.hpp"
#include "shade/gouraud.hpp"

namespace shadelab::speed {

namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
using OMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

const glm::dvec4 kTransparent{0.0, 0.0, 0.0, 0.0};

// One mesh seen by the chart's camera, as a job of the render path (host/pipeline/), rasterised once.
struct View {
    pipeline::Job job;
    pipeline::Frame frame;
};

View subdivision_view(Mesh mesh, const Camera& cam, const SubdivisionOptions& o) {
    View v;
    v.job.meshes.push_back(pipeline::JobMesh{std::move(mesh), Material{}, false});
    v.job.camera = cam;
    v.job.width = o.width;
    v.job.height = o.height;
    v.job.lights = o.lights;
    v.job.ambient = o.ambient;
    v.job.background = kTransparent;
    v.job.precision = Precision::Precise;
    pipeline::StageTimes times;
    v.frame = pipeline::raster(v.job, times);
    return v;
}

// The kernel's image of a view: per pixel, or per vertex then interpolated.
Image kernel_render(Shader& shader, View& v, const Material& m, bool per_vertex) {
    v.job.meshes.front().material = m;
    v.job.per_vertex = per_vertex;
    pipeline::StageTimes times;
    return pipeline::compose(v.job, v.frame, pipeline::shade(shader, v.job, v.frame, times), times);
}

// The exact unit sphere at the origin, ray-cast through every pixel centre, shaded in double.
Image exact_sphere_image(const Camera& cam, const Material& m, const SubdivisionOptions& o) {
    Image img(o.width, o.height, 4);
    const glm::dmat4 inv = glm::inverse(cam.projection(double(o.width) / o.height) * cam.view());
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x) {
            // Pixel centre to normalised device coordinates (y = 0 is the top row), then to a world ray.
            const double nx = 2.0 * (x + 0.5) / o.width - 1.0, ny = 1.0 - 2.0 * (y + 0.5) / o.height;
            const glm::dvec4 a = inv * glm::dvec4(nx, ny, -1.0, 1.0), b = inv * glm::dvec4(nx, ny, 1.0, 1.0);
            const glm::dvec3 d = glm::normalize(glm::dvec3(b) / b.w - glm::dvec3(a) / a.w);
            const glm::dvec3 e = cam.eye;
            // |e + t d|^2 = 1: t^2 + 2 (e.d) t + |e|^2 - 1 = 0, nearest root.
            const double half_b = glm::dot(e, d), c = glm::dot(e, e) - 1.0, disc = half_b * half_b - c;
            if (disc < 0.0) continue;
            const double t = -half_b - std::sqrt(disc);
            if (t <= 0.0) continue;
            const glm::dvec3 P = e + t * d, N = glm::normalize(P);
            const glm::dvec3 v = ref::shade_point(P, N, glm::normalize(e - P), m, o.lights, o.ambient);
            for (int c3 = 0; c3 < 3; ++c3) img.at(x, y, c3) = float(v[c3]);
            img.at(x, y, 3) = 1.0f;
        }
    return img;
}

SubdivisionRow row_for(const std::string& surface, const std::string& reference, int level, const Mesh& mesh, const std::string& model, bool pv,
                       const ImageDiff& d) {
    SubdivisionRow r;
    r.surface = surface;
    r.reference = reference;
    r.level = level;
    r.triangles = mesh.triangles.size();
    r.vertices = mesh.positions.size();
    r.model = model;
    r.per_vertex = pv;
    r.error = d;   // figures only
    return r;
}

}  // namespace

Mesh loop_subdivide(const Mesh& mesh, int times) {
    if (times < 0 || times > 6) throw Error("Loop subdivision level " + std::to_string(times) + " is out of range: use 0..6");
    OMesh om;
    std::vector<OMesh::VertexHandle> vh;
    vh.reserve(mesh.positions.size());
    for (const auto& p : mesh.positions) vh.push_back(om.add_vertex(OMesh::Point(p.x, p.y, p.z)));
    for (const auto& t : mesh.triangles)
        if (!om.add_face(vh[t[0]], vh[t[1]], vh[t[2]]).is_valid())
            throw Error("cannot subdivide '" + mesh.source + "': it is not a manifold triangle mesh (OpenMesh rejected a face)");
    if (times > 0) {
        OpenMesh::Subdivider::Uniform::LoopT<OMesh, double> loop;
        if (!loop.attach(om) || !loop(std::size_t(times)))
            throw Error("cannot subdivide '" + mesh.source + "': OpenMesh's Loop subdivider failed");
        loop.detach();
    }
    om.request_face_normals();
    om.request_vertex_normals();
    om.update_normals();
    Mesh out;
    out.source = mesh.source + " Loop x" + std::to_string(times);
    out.positions.reserve(om.n_vertices());
    for (const auto v : om.vertices()) {
        const auto p = om.point(v);
        auto n = om.normal(v);
        out.positions.emplace_back(p[0], p[1], p[2]);
        const double len = n.norm();
        out.normals.push_back(len > 0.0 && std::isfinite(len) ? glm::dvec3(n[0], n[1], n[2]) / len : glm::dvec3(0, 0, 1));
    }
    for (const auto f : om.faces()) {
        glm::u32vec3 t;
        int k = 0;
        for (const auto v : om.fv_range(f)) t[k++] = glm::u32(v.idx());
        out.triangles.push_back(t);
    }
    return out;
}

std::vector<SubdivisionRow> sphere_subdivision(Runtime& rt, const std::vector<std::string>& models,
                                               const std::vector<int>& levels, const SubdivisionOptions& o) {
    Shader shader(rt);
    Bounds unit;
    unit.lo = glm::dvec3(-1.0);
    unit.hi = glm::dvec3(1.0);
    const Camera cam = Camera::fit(unit, o.view_from, 35.0, double(o.width) / o.height);
    std::vector<SubdivisionRow> rows;
    for (const auto& name : models) {
        const Material m = chart_material(name);
        const Image truth = exact_sphere_image(cam, m, o);
        for (int level : levels) {
            View v = subdivision_view(make_icosphere(level), cam, o);
            for (bool pv : {false, true}) {
                const Image k = kernel_render(shader, v, m, pv);
                rows.push_back(row_for("icosphere", "exact sphere", level, v.job.meshes.front().mesh, name, pv,
                                       compare_images(k, truth, o.rel_floor)));
            }
        }
    }
    return rows;
}

std::vector<SubdivisionRow> mesh_subdivision(Runtime& rt, const std::string& surface, const Mesh& mesh,
                                             const std::vector<std::string>& models, const std::vector<int>& levels,
                                             int reference_level, const SubdivisionOptions& o) {
    Shader shader(rt);
    const Camera cam = Camera::fit(mesh.bounds(), o.view_from, 35.0, double(o.width) / o.height);
    RasterOptions ro;
    ro.width = o.width;
    ro.height = o.height;
    const Mesh finest = loop_subdivide(mesh, reference_level);
    const FragmentBuffer ref_fb = rasterize(finest, cam, ro);
    std::vector<View> views;
    for (int level : levels) views.push_back(subdivision_view(level == reference_level ? finest : loop_subdivide(mesh, level), cam, o));
    std::vector<SubdivisionRow> rows;
    for (const auto& name : models) {
        const Material m = chart_material(name);
        const Image truth = compose_image(ref_fb, ref::shade_fragments(ref_fb, m, o.lights, o.ambient, cam.eye), kTransparent);
        for (std::size_t i = 0; i < levels.size(); ++i)
            for (bool pv : {false, true}) {
                const Image k = kernel_render(shader, views[i], m, pv);
                rows.push_back(row_for(surface, "Loop level " + std::to_string(reference_level), levels[i],
                                       views[i].job.meshes.front().mesh, name, pv, compare_images(k, truth, o.rel_floor)));
            }
    }
    return rows;
}

}  // namespace shadelab::speed
