// Mesh loading with OpenMesh, validation and repair, icosphere, quad, area-uniform surface sampler.
#include "mesh/mesh.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <tuple>

// OpenMesh 9's PropertyT::push_back(T()) trips GCC 12's -Wmaybe-uninitialized inside the library's own
// templates (a default-constructed VectorT); nothing of ours is uninitialised.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "core/error.hpp"

namespace fs = std::filesystem;

namespace shadelab {

namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
using OMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

glm::dvec3 to_glm(const OpenMesh::Vec3d& v) { return {v[0], v[1], v[2]}; }

std::string lower_ext(const std::string& path) {
    std::string e = fs::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Area-weighted vertex normals: the sum of the unnormalised face normals (twice the face areas) of the
// faces around each vertex (Max 1999 compares weightings; area weighting is the usual default).
std::vector<glm::dvec3> area_weighted_normals(const Mesh& m) {
    std::vector<glm::dvec3> n(m.positions.size(), glm::dvec3(0.0));
    for (const auto& t : m.triangles) {
        const glm::dvec3 fn = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
        for (int k = 0; k < 3; ++k) n[t[k]] += fn;
    }
    return n;
}

// OpenMesh's OBJ reader drops a vertex it cannot parse ("nan", "inf") and then rejects the faces that use
// it, which would surface as a misleading "no triangles". Read the vertex lines first and name the problem.
void check_obj_coordinates(const std::string& path) {
    std::ifstream in(path);
    std::string line;
    std::size_t bad = 0, line_no = 0, first_bad = 0;
    while (std::getline(in, line)) {
        ++line_no;
        if (line.size() < 2 || line[0] != 'v' || (line[1] != ' ' && line[1] != '\t')) continue;
        std::istringstream s(line.substr(2));
        for (int k = 0; k < 3; ++k) {
            std::string tok;
            if (!(s >> tok)) break;
            char* end = nullptr;
            const double v = std::strtod(tok.c_str(), &end);
            if (*end != '\0' || !std::isfinite(v)) {
                if (!bad) first_bad = line_no;
                ++bad;
                break;
            }
        }
    }
    if (bad)
        throw Error("mesh '" + path + "' has " + std::to_string(bad) + " vertices with NaN/Inf or unreadable " +
                    "coordinates (first on line " + std::to_string(first_bad) + "): fix or remove them");
}

// How many vertices the file itself declares. OpenMesh appends duplicated vertices after them when it
// re-adds faces around non-manifold ("complex") edges, and those copies carry no normal from the file
// (their normal property is left uninitialised), so their normals must be computed.
std::size_t declared_vertex_count(const std::string& path, const std::string& ext) {
    std::ifstream in(path);
    std::string line;
    if (ext == ".obj") {
        std::size_t n = 0;
        while (std::getline(in, line))
            if (line.size() > 1 && line[0] == 'v' && (line[1] == ' ' || line[1] == '\t')) ++n;
        return n;
    }
    if (ext == ".ply") {
        while (std::getline(in, line)) {
            std::istringstream s(line);
            std::string a, b;
            std::size_t n = 0;
            if (s >> a >> b >> n && a == "element" && b == "vertex") return n;
            if (line.rfind("end_header", 0) == 0) break;
        }
    }
    if (ext == ".off") {
        std::size_t n = 0;
        while (std::getline(in, line)) {
            if (line.empty() || line[0] == '#') continue;
            std::istringstream s(line);
            std::string word;
            s >> word;
            if (word.find("OFF") != std::string::npos) {
                if (s >> n) return n;   // counts on the same line as the keyword
                continue;
            }
            std::istringstream c(line);
            if (c >> n) return n;
            break;
        }
    }
    return std::numeric_limits<std::size_t>::max();
}

}  // namespace

Bounds Mesh::bounds() const {
    Bounds b;
    bool any = false;
    auto add = [&](const glm::dvec3& p) {
        if (!any) { b.lo = b.hi = p; any = true; return; }
        b.lo = glm::min(b.lo, p);
        b.hi = glm::max(b.hi, p);
    };
    if (!triangles.empty()) {
        for (const auto& t : triangles)
            for (int k = 0; k < 3; ++k) add(positions[t[k]]);
    } else {
        for (const auto& p : positions) add(p);
    }
    return b;
}

void Mesh::transform(const glm::dmat4& m) {
    const glm::dmat3 nm = glm::transpose(glm::inverse(glm::dmat3(m)));
    for (auto& p : positions) p = glm::dvec3(m * glm::dvec4(p, 1.0));
    for (auto& n : normals) {
        const glm::dvec3 t = nm * n;
        const double len = glm::length(t);
        n = len > 0.0 ? t / len : n;
    }
}

Mesh load_mesh(const std::string& path, MeshLoadReport* report) {
    MeshLoadReport local;
    MeshLoadReport& r = report ? *report : local;
    r = MeshLoadReport{};

    std::error_code ec;
    if (!fs::exists(path, ec)) throw Error("mesh file '" + path + "' not found: check the path");
    if (fs::is_directory(path, ec)) throw Error("mesh path '" + path + "' is a folder: give a mesh file");
    const std::string ext = lower_ext(path);
    if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl")
        throw Error("mesh '" + path + "' has an unsupported format '" + ext + "': use .obj, .off, .ply or .stl");
    if (fs::file_size(path, ec) == 0) throw Error("mesh file '" + path + "' is empty: nothing to shade");

    if (ext == ".obj") check_obj_coordinates(path);

    OMesh om;
    om.request_vertex_normals();
    OpenMesh::IO::Options opt = OpenMesh::IO::Options::VertexNormal;
    // OpenMesh reports non-manifold input ("complex edge") on its own log stream; capture it as notes.
    std::ostringstream omlog;
    omerr().disconnect(std::cerr);
    omerr().connect(omlog);
    const bool ok = OpenMesh::IO::read_mesh(om, path, opt);
    omerr().disconnect(omlog);
    omerr().connect(std::cerr);
    if (!ok) throw Error("cannot read mesh '" + path + "': the file is not valid " + ext.substr(1) + " (OpenMesh refused it)");

    r.vertices_in = om.n_vertices();
    r.faces_in = om.n_faces();
    {
        std::istringstream log(omlog.str());
        std::string line;
        std::size_t complex_edges = 0;
        while (std::getline(log, line))
            if (line.find("complex edge") != std::string::npos) ++complex_edges;
        if (complex_edges)
            r.notes.push_back(std::to_string(complex_edges) +
                              " non-manifold ('complex') edges: OpenMesh re-added the faces with duplicated vertices");
    }

    Mesh m;
    m.source = path;
    m.positions.reserve(om.n_vertices());
    std::size_t bad = 0;
    for (auto vh : om.vertices()) {
        const glm::dvec3 p = to_glm(om.point(vh));
        bad += finite3(p) ? 0 : 1;
        m.positions.push_back(p);
    }
    if (bad)
        throw Error("mesh '" + path + "' has " + std::to_string(bad) +
                    " vertices with NaN/Inf coordinates: fix or remove them");

    // Scale for the degeneracy test: a triangle whose area is below (1e-12 * extent)^2 is degenerate.
    glm::dvec3 lo(0.0), hi(0.0);
    if (!m.positions.empty()) {
        lo = hi = m.positions.front();
        for (const auto& p : m.positions) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
    }
    const double extent = glm::length(hi - lo);
    const double min_area2 = std::pow(1e-12 * std::max(extent, 1e-300), 4);   // |cross|^2 threshold

    for (auto fh : om.faces()) {
        glm::u32vec3 t;
        int k = 0;
        for (auto vh : om.fv_range(fh)) {
            if (k < 3) t[k] = glm::u32(vh.idx());
            ++k;
        }
        if (k != 3) { ++r.degenerate_dropped; continue; }
        const glm::dvec3 c = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || glm::dot(c, c) <= min_area2) {
            ++r.degenerate_dropped;
            continue;
        }
        m.triangles.push_back(t);
    }
    if (r.degenerate_dropped)
        r.notes.push_back(std::to_string(r.degenerate_dropped) + " degenerate (zero-area) triangles dropped");
    r.triangles_out = m.triangles.size();
    if (m.triangles.empty())
        throw Error("mesh '" + path + "' has no triangles after loading: is it a point cloud or an empty file?");

    std::vector<char> used(m.positions.size(), 0);
    for (const auto& t : m.triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
    r.unused_vertices = std::size_t(std::count(used.begin(), used.end(), 0));

    // Normals: from the file where present and valid, else area-weighted; a vertex whose computed normal
    // cancels to zero (opposite faces meeting) takes the normal of one of its faces.
    const auto computed = area_weighted_normals(m);
    // STL stores facet normals only (OpenMesh may still flag vertex normals): compute them for STL.
    r.normals_from_file = opt.check(OpenMesh::IO::Options::VertexNormal) && ext != ".stl";
    const std::size_t declared = r.normals_from_file ? declared_vertex_count(path, ext) : 0;
    m.normals.resize(m.positions.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        glm::dvec3 n(0.0);
        if (r.normals_from_file && i < declared) {
            n = to_glm(om.normal(OMesh::VertexHandle(int(i))));
            const double len = glm::length(n);
            if (finite3(n) && len > 1e-12) {
                m.normals[i] = n / len;
                continue;
            }
            if (used[i]) ++r.normals_repaired;
        }
        n = computed[i];
        const double len = glm::length(n);
        m.normals[i] = len > 0.0 ? n / len : glm::dvec3(0.0, 0.0, 1.0);
    }
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k)
            if (glm::length(computed[t[k]]) == 0.0) {
                const glm::dvec3 c = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
                if (!r.normals_from_file) m.normals[t[k]] = glm::normalize(c);
            }
    // Copies OpenMesh made for complex edges take the file normal of the vertex they duplicate.
    if (r.normals_from_file && m.positions.size() > declared) {
        std::map<std::tuple<double, double, double>, std::size_t> original;
        for (std::size_t i = 0; i < declared; ++i)
            original.emplace(std::make_tuple(m.positions[i].x, m.positions[i].y, m.positions[i].z), i);
        std::size_t copied = 0;
        for (std::size_t i = declared; i < m.positions.size(); ++i) {
            auto it = original.find(std::make_tuple(m.positions[i].x, m.positions[i].y, m.positions[i].z));
            if (it != original.end()) { m.normals[i] = m.normals[it->second]; ++copied; }
        }
        if (copied)
            r.notes.push_back(std::to_string(copied) + " vertices duplicated by OpenMesh took the file normal of their original");
    }
    if (r.normals_repaired)
        r.notes.push_back(std::to_string(r.normals_repaired) + " zero or NaN normals in the file recomputed (area-weighted)");
    if (r.unused_vertices)
        r.notes.push_back(std::to_string(r.unused_vertices) + " vertices used by no triangle (ignored)");
    return m;
}

Mesh make_icosphere(int subdivisions, double radius) {
    if (subdivisions < 0 || subdivisions > 9)
        throw Error("icosphere subdivision " + std::to_string(subdivisions) + " is out of range: use 0..9");
    if (!(radius > 0.0) || !std::isfinite(radius)) throw Error("icosphere radius must be finite and > 0");
    // Icosahedron (golden-ratio rectangles), then 4-to-1 midpoint subdivision with projection to the sphere.
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<glm::dvec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                 {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (auto& p : v) p = glm::normalize(p);
    std::vector<glm::u32vec3> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                   {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                                   {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<glm::u32, glm::u32>, glm::u32> mid;
        auto midpoint = [&](glm::u32 a, glm::u32 b) {
            const auto key = std::make_pair(std::min(a, b), std::max(a, b));
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(glm::normalize(v[a] + v[b]));
            const glm::u32 idx = glm::u32(v.size() - 1);
            mid.emplace(key, idx);
            return idx;
        };
        std::vector<glm::u32vec3> nf;
        nf.reserve(f.size() * 4);
        for (const auto& tri : f) {
            const glm::u32 a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
            nf.push_back({tri[0], a, c});
            nf.push_back({tri[1], b, a});
            nf.push_back({tri[2], c, b});
            nf.push_back({a, b, c});
        }
        f.swap(nf);
    }
    // Through an OpenMesh mesh, as every mesh in shadelab: it checks the connectivity is a valid manifold.
    OMesh om;
    std::vector<OMesh::VertexHandle> vh;
    vh.reserve(v.size());
    for (const auto& p : v) vh.push_back(om.add_vertex(OMesh::Point(p.x * radius, p.y * radius, p.z * radius)));
    for (const auto& tri : f) {
        if (!om.add_face(vh[tri[0]], vh[tri[1]], vh[tri[2]]).is_valid())
            throw Error("internal: icosphere face rejected by OpenMesh");
    }
    Mesh m;
    m.source = "icosphere(" + std::to_string(subdivisions) + ")";
    for (auto h : om.vertices()) {
        const glm::dvec3 p = to_glm(om.point(h));
        m.positions.push_back(p);
        m.normals.push_back(glm::normalize(p));
    }
    for (auto fh : om.faces()) {
        glm::u32vec3 tri;
        int k = 0;
        for (auto h : om.fv_range(fh)) tri[k++] = glm::u32(h.idx());
        m.triangles.push_back(tri);
    }
    return m;
}

Mesh make_quad(double half) {
    Mesh m;
    m.source = "quad";
    m.positions = {{-half, -half, 0}, {half, -half, 0}, {half, half, 0}, {-half, half, 0}};
    m.normals.assign(4, glm::dvec3(0, 0, 1));
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

FragmentBuffer sample_surface(const Mesh& mesh, std::size_t count, std::uint64_t seed) {
    FragmentBuffer fb;
    if (mesh.triangles.empty()) throw Error("cannot sample '" + mesh.source + "': it has no triangles");
    std::vector<double> cdf(mesh.triangles.size());
    double total = 0.0;
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const auto& t = mesh.triangles[i];
        total += 0.5 * glm::length(glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]],
                                              mesh.positions[t[2]] - mesh.positions[t[0]]));
        cdf[i] = total;
    }
    if (!(total > 0.0)) throw Error("cannot sample '" + mesh.source + "': its surface area is zero");
    std::mt19937_64 g(seed);
    auto u01 = [&g] { return double(g() >> 11) * (1.0 / 9007199254740992.0); };
    fb.reserve(count);
    for (std::size_t s = 0; s < count; ++s) {
        const double pick = u01() * total;
        const std::size_t i = std::min(std::size_t(std::upper_bound(cdf.begin(), cdf.end(), pick) - cdf.begin()),
                                       cdf.size() - 1);
        const auto& t = mesh.triangles[i];
        // Uniform barycentrics (Osada et al. 2002): sqrt of the first variate.
        const double r1 = std::sqrt(u01()), r2 = u01();
        const double b0 = 1.0 - r1, b1 = r1 * (1.0 - r2), b2 = r1 * r2;
        const glm::dvec3 p = b0 * mesh.positions[t[0]] + b1 * mesh.positions[t[1]] + b2 * mesh.positions[t[2]];
        glm::dvec3 n = b0 * mesh.normals[t[0]] + b1 * mesh.normals[t[1]] + b2 * mesh.normals[t[2]];
        const double len = glm::length(n);
        n = len > 0.0 ? n / len
                      : glm::normalize(glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]));
        fb.push_back(float(p.x), float(p.y), float(p.z), float(n.x), float(n.y), float(n.z), -1, 0.0f);
    }
    return fb;
}

}  // namespace shadelab
