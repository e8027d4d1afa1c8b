// Mesh loading with OpenMesh, validation and repair, icosphere, quad, area-uniform surface sampler.
#include "mesh/mesh.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <mutex>
#include <random>
#include <sstream>
#include <tuple>

// OpenMesh 9's PropertyT::push_back(T()) trips GCC 12's -Wmaybe-uninitialized inside the library's own
// templates (a default-constructed VectorT); nothing of ours is uninitialised.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "core/error.hpp"
#include "core/format.hpp"
#include "mesh/mesh_check.hpp"

namespace fs = std::filesystem;

namespace shadelab {

namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
using OMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

glm::dvec3 to_glm(const OpenMesh::Vec3d& v) { return {v[0], v[1], v[2]}; }


bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Unit vector along v, robust to tiny and huge magnitudes (scaled by the largest component first).
// False for a zero or non-finite v.
bool unit(const glm::dvec3& v, glm::dvec3& out) {
    const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    if (!(m > 0.0) || !std::isfinite(m)) return false;
    const glm::dvec3 s = v / m;
    out = s / glm::length(s);
    return true;
}

// A value OpenMesh cannot hold: NaN, +-Inf, or beyond the range of a float (its readers parse coordinates
// as 32-bit floats, so 1e39 would become Inf -- or make the reader drop the vertex without a word).
bool non_finite_value(double v) { return !std::isfinite(v) || std::abs(v) > double(FLT_MAX); }

// A token that parses completely as such a number ("nan", "-inf", "1e999", "1e39").
bool non_finite_number(const std::string& tok) {
    if (tok.empty()) return false;
    char* end = nullptr;
    const double v = std::strtod(tok.c_str(), &end);
    return end != tok.c_str() && *end == '\0' && non_finite_value(v);
}

// OBJ facts OpenMesh does not give back, read from the file in one pass before OpenMesh reads it:
//  - OpenMesh's OBJ reader drops a vertex it cannot parse ("nan", "inf") and then rejects the faces that
//    use it, which would surface as a misleading "no triangles": such vertices are counted here.
//  - it silently removes repeated indices from a face, and drops the face when fewer than 3 remain.
//  - it sets a vertex's normal only when some face corner names a 'vn' for it; the other vertices' normal
//    property is left uninitialised (not zero), so which vertices really have a file normal is taken
//    from the face lines.
struct ObjScan {
    std::size_t vertices = 0;          // 'v' lines (OpenMesh keeps their order: vertex i = i-th 'v')
    std::size_t bad_vertices = 0;      // NaN/Inf/unreadable coordinates
    std::size_t first_bad_line = 0;
    std::vector<char> has_normal;      // per 'v': some face corner gives it a valid 'vn'
    std::size_t collapsed_faces = 0;   // fewer than 3 distinct vertices: dropped by OpenMesh without a word
    std::size_t reduced_faces = 0;     // a vertex repeated among >= 3 distinct ones: the repeat is removed
};

// Resolves a 1-based (or negative, relative) OBJ index against the `count` elements seen so far.
std::size_t obj_index(const std::string& tok, std::size_t count) {
    if (tok.empty()) return kNone;
    char* end = nullptr;
    const long long v = std::strtoll(tok.c_str(), &end, 10);
    if (*end != '\0' || v == std::numeric_limits<long long>::min()) return kNone;   // -v below would overflow
    if (v > 0 && std::size_t(v) <= count) return std::size_t(v - 1);
    if (v < 0 && std::size_t(-v) <= count) return count - std::size_t(-v);
    return kNone;
}

ObjScan scan_obj(const std::string& path) {
    ObjScan s;
    std::ifstream in(path);
    std::string line, kw, tok;
    std::size_t line_no = 0, normals = 0;
    std::vector<std::size_t> corner_v, corner_n;
    while (std::getline(in, line)) {
        ++line_no;
        std::istringstream ls(line);
        if (!(ls >> kw)) continue;
        if (kw == "v") {
            ++s.vertices;
            s.has_normal.push_back(0);
            bool bad = false;
            for (int k = 0; k < 3 && !bad; ++k) {
                char* end = nullptr;
                if (!(ls >> tok)) { bad = true; break; }
                const double v = std::strtod(tok.c_str(), &end);
                bad = *end != '\0' || non_finite_value(v);
            }
            if (bad) {
                if (!s.bad_vertices) s.first_bad_line = line_no;
                ++s.bad_vertices;
            }
        } else if (kw == "vn") {
            ++normals;
        } else if (kw == "f") {
            corner_v.clear();
            corner_n.clear();
            bool all_valid = true;
            while (ls >> tok) {
                const std::size_t slash1 = tok.find('/');
                const std::size_t v = obj_index(tok.substr(0, slash1), s.vertices);
                std::size_t n = kNone;
                if (slash1 != std::string::npos) {
                    const std::size_t slash2 = tok.find('/', slash1 + 1);
                    if (slash2 != std::string::npos) n = obj_index(tok.substr(slash2 + 1), normals);
                }
                all_valid = all_valid && v != kNone;
                corner_v.push_back(v);
                corner_n.push_back(n);
            }
            std::vector<std::size_t> distinct = corner_v;
            std::sort(distinct.begin(), distinct.end());
            distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
            if (distinct.size() < 3) {
                ++s.collapsed_faces;
                continue;
            }
            if (distinct.size() < corner_v.size()) ++s.reduced_faces;
            if (!all_valid) continue;   // OpenMesh rejects the face (and says so on its log)
            for (std::size_t k = 0; k < corner_v.size(); ++k)
                if (corner_n[k] != kNone) s.has_normal[corner_v[k]] = 1;
        }
    }
    return s;
}

std::uint32_t little_endian_u32(const unsigned char* b) {
    return std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
}

// A binary STL is an 80-byte header, a facet count n and n 50-byte facets; its size says so. kNone if the
// file is not binary STL (then it is ASCII, "solid ... facet ... vertex ...").
std::size_t binary_stl_facets(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char head[84] = {};
    if (!in.read(reinterpret_cast<char*>(head), sizeof head)) return kNone;
    const std::size_t n = little_endian_u32(head + 80);
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    return !ec && size == 84 + 50 * std::uintmax_t(n) ? n : kNone;
}

// Binary STL facets with a NaN/Inf vertex coordinate: OpenMesh's STL reader merges vertices by position,
// and a NaN position then vanishes with its facets instead of reaching the post-load check.
// Returns the number of such facets and the first one (0-based).
std::pair<std::size_t, std::size_t> scan_binary_stl_non_finite(const std::string& path, std::size_t facets) {
    std::ifstream in(path, std::ios::binary);
    in.seekg(84);
    unsigned char f[50];
    std::size_t bad = 0, first = 0;
    for (std::size_t i = 0; i < facets && in.read(reinterpret_cast<char*>(f), sizeof f); ++i) {
        bool here = false;
        for (int k = 3; k < 12; ++k) {   // floats 0..2 are the facet normal (unused), 3..11 the corners
            const std::uint32_t bits = little_endian_u32(f + 4 * k);
            float v;
            std::memcpy(&v, &bits, sizeof v);
            here = here || !std::isfinite(v);
        }
        if (here && !bad++) first = i;
    }
    return {bad, first};
}

// NaN/Inf in the text formats other than OBJ. OpenMesh's OFF and PLY readers stop at a "nan" token and
// the load ends in a misleading "no triangles"; a binary file's NaN is caught after loading instead.
// Returns the number of lines holding a NaN/Inf number and the first such line (1-based).
std::pair<std::size_t, std::size_t> scan_text_non_finite(const std::string& path, const std::string& ext) {
    std::ifstream in(path, std::ios::binary);
    std::string line, tok, first;
    std::size_t line_no = 0, bad = 0, first_bad = 0;
    bool body = false;
    if (ext == ".stl" && binary_stl_facets(path) != kNone) return {0, 0};
    while (std::getline(in, line)) {
        ++line_no;
        std::istringstream ls(line);
        if (!(ls >> first)) continue;
        if (!body) {
            if (ext == ".ply") {
                std::string format;
                if (first == "format" && ls >> format && format != "ascii") return {0, 0};   // binary PLY
                body = first == "end_header";
                continue;
            }
            if (ext == ".off") {
                if (first[0] == '#') continue;
                if (line.find("BINARY") != std::string::npos) return {0, 0};
                body = true;
                if (first.find("OFF") != std::string::npos) continue;   // the keyword line
            }
            if (ext == ".stl") body = true;
        }
        if (first[0] == '#') continue;
        bool here = false;
        if (ext == ".stl") {
            if (first != "vertex") continue;   // facet normals are not used; names may be any word
        } else {
            here = non_finite_number(first);
        }
        while (!here && ls >> tok) here = non_finite_number(tok);
        if (here) {
            if (!bad) first_bad = line_no;
            ++bad;
        }
    }
    return {bad, first_bad};
}

// How many vertices a PLY or OFF file itself declares. OpenMesh appends duplicated vertices after them
// when it re-adds faces around non-manifold ("complex") edges, and those copies carry no normal from the
// file (their normal property is left uninitialised), so their normals come from their originals.
std::size_t declared_vertex_count(const std::string& path, const std::string& ext) {
    std::ifstream in(path);
    std::string line;
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
    return kNone;
}

// OpenMesh writes its warnings ("complex edge", "Face has equal vertices", ...) to its global omerr()
// stream. While a file is read they are captured here (one reader at a time: the stream is global, and
// batch runs load meshes on a second thread), then turned into report notes instead of raw stderr lines.
//
// omerr() is re-routed once for the life of the process, through a forwarder that hands what it gets to
// the capture in progress, or to std::cerr when there is none. (Connecting and disconnecting a capture per
// load leaked 16 bytes each time: OpenMesh 9's mostream::disconnect erases its target without deleting it.)
class OpenMeshLog {
public:
    OpenMeshLog() : lock_(mutex()) { router().capture = &log_; }
    ~OpenMeshLog() { restore(); }
    OpenMeshLog(const OpenMeshLog&) = delete;
    OpenMeshLog& operator=(const OpenMeshLog&) = delete;

    std::string finish() {
        omerr().flush();
        restore();
        return log_.str();
    }

private:
    class Router : public std::streambuf {
    public:
        std::atomic<std::ostream*> capture{nullptr};   // set only while the mutex is held
        Router() : stream_(this) {
            omerr().disconnect(std::cerr);   // leaks OpenMesh's 16-byte target once (see above)
            omerr().connect(stream_);
        }

    protected:
        int overflow(int c) override {
            if (c != traits_type::eof()) out().put(char(c));
            return traits_type::not_eof(c);
        }
        std::streamsize xsputn(const char* s, std::streamsize n) override {
            out().write(s, n);
            return n;
        }

    private:
        std::ostream& out() {
            std::ostream* c = capture.load();
            return c ? *c : std::cerr;
        }
        std::ostream stream_;
    };
    // Never destroyed: omerr() may still be written to while static objects are destroyed at exit.
    static Router& router() {
        static Router* r = new Router;
        return *r;
    }
    static std::mutex& mutex() {
        static std::mutex m;
        return m;
    }
    void restore() {
        if (restored_) return;
        restored_ = true;
        router().capture = nullptr;
    }
    std::lock_guard<std::mutex> lock_;
    std::ostringstream log_;
    bool restored_ = false;
};

// "1 line", "3 lines".
std::string counted(std::size_t n, const std::string& one, const std::string& many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string format_name(const std::string& ext) {
    std::string f = ext.substr(1);
    std::transform(f.begin(), f.end(), f.begin(), [](unsigned char c) { return char(std::toupper(c)); });
    return f;
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
        glm::dvec3 t;
        if (unit(nm * n, t)) n = t;   // a singular m leaves the normal as it was
    }
}

namespace {

// The path names a readable, non-empty mesh file of a supported format whose grammar OpenMesh can take;
// returns its lower-case extension. OpenMesh must never see a file it would abort, crash or loop on.
std::string check_mesh_path(const std::string& path) {
    const std::string ext = check_mesh_opens(path);
    check_mesh_file(path, ext);
    return ext;
}

// Rejects NaN/Inf and beyond-float-range numbers before OpenMesh reads them; for OBJ also returns what the
// scan learnt about normals and faces OpenMesh drops or reduces without a word (ObjScan).
ObjScan scan_non_finite(const std::string& path, const std::string& ext) {
    ObjScan obj;
    if (ext == ".obj") {
        obj = scan_obj(path);
        if (obj.bad_vertices)
            throw Error("mesh '" + path + "' has " + counted(obj.bad_vertices, "vertex", "vertices") + " with NaN/Inf, beyond-float-range or " +
                        "unreadable coordinates (first on line " + std::to_string(obj.first_bad_line) +
                        "): fix or remove them");
    } else if (const std::size_t facets = ext == ".stl" ? binary_stl_facets(path) : kNone; facets != kNone) {
        const auto [bad, first] = scan_binary_stl_non_finite(path, facets);
        if (bad)
            throw Error("mesh '" + path + "' has NaN/Inf coordinates in " + counted(bad, "facet", "facets") +
                        " (first: facet " + std::to_string(first + 1) + "): fix or remove them");
    } else {
        const auto [bad, first] = scan_text_non_finite(path, ext);
        if (bad)
            throw Error("mesh '" + path + "' has NaN/Inf or beyond-float-range numbers on " + counted(bad, "line", "lines") + " (first on line " +
                        std::to_string(first) + "): fix or remove them");
    }
    return obj;
}

// OpenMesh reads the file into om (with vertex normals when it has them, flagged in opt); returns the
// warnings it printed meanwhile.
std::string read_with_openmesh(OMesh& om, OpenMesh::IO::Options& opt, const std::string& path,
                               const std::string& ext) {
    om.request_vertex_normals();
    opt = OpenMesh::IO::Options::VertexNormal;
    bool ok = false;
    std::string log;
    {
        OpenMeshLog capture;
        try {
            ok = OpenMesh::IO::read_mesh(om, path, opt);
        } catch (const std::exception& e) {   // e.g. a corrupt header asking for billions of elements
            throw Error("cannot read mesh '" + path + "': OpenMesh failed (" + e.what() + "): check that it is a valid " +
                        format_name(ext) + " file");
        }
        log = capture.finish();
    }
    if (!ok)
        throw Error("cannot read mesh '" + path + "': OpenMesh could not parse it as " + format_name(ext) +
                    ": check that it is a valid " + format_name(ext) + " file (re-export it)");
    return log;
}

// OpenMesh's warnings, counted by kind into the report's notes (faces it dropped as having equal vertices
// count as degenerate), and the OBJ faces the scan saw reduced.
void note_openmesh_log(const std::string& log, const ObjScan& obj, MeshLoadReport& r) {
    std::istringstream ls(log);
    std::string line, first_other;
    std::size_t complex_edges = 0, invalid_index = 0, other = 0;
    while (std::getline(ls, line)) {
        if (line.find("complex edge") != std::string::npos) ++complex_edges;
        else if (line.find("equal vertices") != std::string::npos) ++r.degenerate_dropped;
        else if (line.find("invalid vertex index") != std::string::npos) ++invalid_index;
        else if (line.find_first_not_of(" \t\r") != std::string::npos) {
            if (!other++) first_other = line.substr(0, 120);
        }
    }
    if (complex_edges)
        r.notes.push_back(counted(complex_edges, "non-manifold ('complex') edge", "non-manifold ('complex') edges") +
                          ": OpenMesh re-added the faces with duplicated vertices");
    if (invalid_index)
        r.notes.push_back(counted(invalid_index, "face", "faces") + " naming a vertex that does not exist: dropped");
    if (obj.reduced_faces)
        r.notes.push_back(counted(obj.reduced_faces, "face", "faces") +
                          " listing a vertex twice: kept without the repeat");
    if (other)
        r.notes.push_back(counted(other, "other OpenMesh warning", "other OpenMesh warnings") + " (first: '" + first_other + "')");
}

std::vector<glm::dvec3> finite_positions(const OMesh& om, const std::string& path) {
    std::vector<glm::dvec3> positions;
    positions.reserve(om.n_vertices());
    std::size_t bad = 0;
    for (auto vh : om.vertices()) {
        const glm::dvec3 p = to_glm(om.point(vh));
        bad += finite3(p) ? 0 : 1;
        positions.push_back(p);
    }
    if (bad)
        throw Error("mesh '" + path + "' has " + counted(bad, "vertex", "vertices") +
                    " with NaN/Inf coordinates: fix or remove them");
    return positions;
}

// Geometry tests run on positions scaled to the bounding box (extent 1), so they mean the same at any
// scale and cannot underflow: a triangle is degenerate when |cross| <= 1e-24, i.e. its area is below
// (1e-12 * extent)^2 -- far below what double coordinates can resolve as a real sliver.
std::vector<glm::dvec3> unit_box_positions(const std::vector<glm::dvec3>& positions) {
    const std::size_t nv = positions.size();
    glm::dvec3 lo(0.0), hi(0.0);
    if (nv) {
        lo = hi = positions.front();
        for (const auto& p : positions) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
    }
    const double extent = glm::length(hi - lo);
    const double inv = extent > 0.0 ? 1.0 / extent : 0.0;
    std::vector<glm::dvec3> q(nv);
    for (std::size_t i = 0; i < nv; ++i) q[i] = (positions[i] - lo) * inv;
    return q;
}

// The unnormalised normal (twice the area) of triangle t on the unit-box positions q.
glm::dvec3 face_cross(const std::vector<glm::dvec3>& q, const glm::u32vec3& t) {
    return glm::cross(q[t[1]] - q[t[0]], q[t[2]] - q[t[0]]);
}

// The faces OpenMesh read that are triangles with three distinct vertices and a non-zero area go into
// m.triangles; the others are counted into the report and noted. Throws when none is left.
void keep_triangles(const OMesh& om, const std::vector<glm::dvec3>& q, Mesh& m, MeshLoadReport& r) {
    std::size_t zero_area = 0;
    for (auto fh : om.faces()) {
        glm::u32vec3 t(0);
        int k = 0;
        for (auto vh : om.fv_range(fh)) {
            if (k < 3) t[k] = glm::u32(vh.idx());
            ++k;
        }
        if (k != 3 || t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || !(glm::length(face_cross(q, t)) > 1e-24)) {
            ++zero_area;
            continue;
        }
        m.triangles.push_back(t);
    }
    r.degenerate_dropped += zero_area;
    if (r.degenerate_dropped)
        r.notes.push_back(counted(r.degenerate_dropped, "degenerate (zero-area or repeated-vertex) triangle",
                                  "degenerate (zero-area or repeated-vertex) triangles") +
                          " dropped");
    r.triangles_out = m.triangles.size();
    if (m.triangles.empty())
        throw Error("mesh '" + m.source + "' has no triangles after loading: is it a point cloud or an empty file?");
}

// Per vertex: whether a triangle uses it, the first that does, and the sum of its faces' unnormalised normals.
struct VertexUse {
    std::vector<char> used;
    std::vector<std::size_t> first_face;
    std::vector<glm::dvec3> area_sum;
};

VertexUse vertex_use(const std::vector<glm::u32vec3>& triangles, const std::vector<glm::dvec3>& q) {
    const std::size_t nv = q.size();
    VertexUse u{std::vector<char>(nv, 0), std::vector<std::size_t>(nv, kNone),
                std::vector<glm::dvec3>(nv, glm::dvec3(0.0))};
    for (std::size_t j = 0; j < triangles.size(); ++j) {
        const auto& t = triangles[j];
        const glm::dvec3 c = face_cross(q, t);
        for (int k = 0; k < 3; ++k) {
            u.used[t[k]] = 1;
            u.area_sum[t[k]] += c;
            if (u.first_face[t[k]] == kNone) u.first_face[t[k]] = j;
        }
    }
    return u;
}

// Computed normal: area-weighted (the sum of the unnormalised face normals, i.e. twice the face areas,
// of the faces around the vertex; Max 1999 compares weightings, area weighting is the usual default).
// Where that sum cancels to zero (faces of opposite orientation meeting at the vertex) the vertex takes
// the normal of the first triangle that uses it. A vertex no triangle uses gets +z: nothing reads it.
glm::dvec3 computed_normal(const VertexUse& u, std::size_t i, const std::vector<glm::u32vec3>& triangles,
                           const std::vector<glm::dvec3>& q) {
    glm::dvec3 n;
    if (unit(u.area_sum[i], n)) return n;
    if (u.first_face[i] != kNone && unit(face_cross(q, triangles[u.first_face[i]]), n)) return n;
    return glm::dvec3(0.0, 0.0, 1.0);
}

// File normals, where present and valid. STL stores facet normals only (OpenMesh may still flag vertex
// normals), so STL vertex normals are always computed. OBJ vertices take a file normal only when a face
// corner names one for them (see ObjScan); PLY/OFF normals are per vertex, all or none.
// Returns how many leading vertices the file declared normals for.
std::size_t assign_normals(const OMesh& om, const OpenMesh::IO::Options& opt, const std::string& ext,
                           const ObjScan& obj, const std::vector<glm::dvec3>& q, Mesh& m, MeshLoadReport& r) {
    const std::size_t nv = m.positions.size();
    const VertexUse use = vertex_use(m.triangles, q);
    r.unused_vertices = std::size_t(std::count(use.used.begin(), use.used.end(), 0));
    const bool file_has_normals = opt.check(OpenMesh::IO::Options::VertexNormal) && ext != ".stl";
    std::size_t declared = 0;
    if (file_has_normals) declared = std::min(nv, ext == ".obj" ? obj.vertices : declared_vertex_count(m.source, ext));
    m.normals.resize(nv);
    std::size_t taken = 0;
    for (std::size_t i = 0; i < nv; ++i) {
        if (i < declared && (ext != ".obj" || obj.has_normal[i])) {
            const glm::dvec3 n = to_glm(om.normal(OMesh::VertexHandle(int(i))));
            if (finite3(n) && glm::length(n) > 1e-12 && unit(n, m.normals[i])) {
                ++taken;
                continue;
            }
        }
        if (i < declared && use.used[i]) ++r.normals_repaired;   // the file has normals, this one is unusable
        m.normals[i] = computed_normal(use, i, m.triangles, q);
    }
    r.normals_from_file = taken > 0;
    return declared;
}

// Copies OpenMesh made for complex edges (past the `declared` vertices of the file) take the normal of the
// vertex they duplicate (same position).
void copy_duplicated_normals(std::size_t declared, Mesh& m, MeshLoadReport& r) {
    const std::size_t nv = m.positions.size();
    std::map<std::tuple<double, double, double>, std::size_t> original;
    for (std::size_t i = 0; i < declared; ++i)
        original.emplace(std::make_tuple(m.positions[i].x, m.positions[i].y, m.positions[i].z), i);
    std::size_t copied = 0;
    for (std::size_t i = declared; i < nv; ++i) {
        auto it = original.find(std::make_tuple(m.positions[i].x, m.positions[i].y, m.positions[i].z));
        if (it != original.end()) { m.normals[i] = m.normals[it->second]; ++copied; }
    }
    if (copied)
        r.notes.push_back(counted(copied, "vertex", "vertices") + " duplicated by OpenMesh took the normal of their original");
}

}  // namespace

Mesh load_mesh_uncached(const std::string& path, MeshLoadReport* report) {
    MeshLoadReport local;
    MeshLoadReport& r = report ? *report : local;
    r = MeshLoadReport{};

    const std::string ext = check_mesh_path(path);
    const ObjScan obj = scan_non_finite(path, ext);
    OMesh om;
    OpenMesh::IO::Options opt;
    const std::string log = read_with_openmesh(om, opt, path, ext);

    r.vertices_in = om.n_vertices();
    r.faces_in = om.n_faces();
    r.degenerate_dropped = obj.collapsed_faces;
    note_openmesh_log(log, obj, r);

    Mesh m;
    m.source = path;
    m.positions = finite_positions(om, path);
    const std::vector<glm::dvec3> q = unit_box_positions(m.positions);
    keep_triangles(om, q, m, r);
    const std::size_t declared = assign_normals(om, opt, ext, obj, q, m, r);
    if (r.normals_from_file && m.positions.size() > declared) copy_duplicated_normals(declared, m, r);
    if (r.normals_repaired)
        r.notes.push_back(counted(r.normals_repaired, "vertex normal", "vertex normals") +
                          " in the file zero, NaN or missing: recomputed (area-weighted)");
    if (r.unused_vertices)
        r.notes.push_back(counted(r.unused_vertices, "vertex", "vertices") + " used by no triangle (ignored)");
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
    const std::size_t nv = mesh.positions.size();
    // A hand-built mesh may lack per-vertex normals: then each sample takes its triangle's normal.
    const bool vertex_normals = mesh.normals.size() == nv;
    std::vector<double> cdf(mesh.triangles.size());
    double total = 0.0;
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const auto& t = mesh.triangles[i];
        if (t[0] >= nv || t[1] >= nv || t[2] >= nv)
            throw Error("cannot sample '" + mesh.source + "': triangle " + std::to_string(i) +
                        " names a vertex beyond its " + std::to_string(nv) + " vertices: fix the mesh");
        total += 0.5 * glm::length(glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]],
                                              mesh.positions[t[2]] - mesh.positions[t[0]]));
        cdf[i] = total;
    }
    if (!(total > 0.0) || !std::isfinite(total))
        throw Error("cannot sample '" + mesh.source + "': its surface area is zero or not finite");
    // Single-threaded on purpose: one mt19937_64 stream, so the samples depend on the seed only. Uniform
    // doubles are made from the top 53 bits (std::uniform_real_distribution's output is
    // implementation-defined, so it would not be reproducible across standard libraries).
    std::mt19937_64 g(seed);
    auto u01 = [&g] { return double(g() >> 11) * (1.0 / 9007199254740992.0); };
    fb.reserve(count);
    for (std::size_t s = 0; s < count; ++s) {
        // Area-uniform triangle choice: the first cumulative area above u * total (zero-area triangles,
        // whose entry equals the previous one, are never chosen).
        const double pick = u01() * total;
        const std::size_t i = std::min(std::size_t(std::upper_bound(cdf.begin(), cdf.end(), pick) - cdf.begin()),
                                       cdf.size() - 1);
        const auto& t = mesh.triangles[i];
        // Uniform barycentrics (Osada et al. 2002): sqrt of the first variate.
        const double r1 = std::sqrt(u01()), r2 = u01();
        const double b0 = 1.0 - r1, b1 = r1 * (1.0 - r2), b2 = r1 * r2;
        const glm::dvec3 p = b0 * mesh.positions[t[0]] + b1 * mesh.positions[t[1]] + b2 * mesh.positions[t[2]];
        glm::dvec3 n(0.0, 0.0, 1.0);
        const bool interpolated =
            vertex_normals && unit(b0 * mesh.normals[t[0]] + b1 * mesh.normals[t[1]] + b2 * mesh.normals[t[2]], n);
        if (!interpolated)
            unit(glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]), n);
        fb.push_back(float(p.x), float(p.y), float(p.z), float(n.x), float(n.y), float(n.z), -1, 0.0f);
    }
    return fb;
}

}  // namespace shadelab
