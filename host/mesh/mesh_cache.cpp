// The mesh cache (see mesh_cache.hpp), and load_mesh, which goes through it.
#include "mesh/mesh_cache.hpp"

#include <OpenMesh/Core/System/config.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <set>
#include <vector>

#include "core/atomic_file.hpp"
#include "core/bytes.hpp"
#include "core/cache_file.hpp"
#include "core/error.hpp"
#include "core/limits.hpp"
#include "core/log.hpp"
#include "mesh/mesh_check.hpp"

// The SHA-256 of the loader's sources (host/mesh/mesh.cpp, mesh_check.cpp and their headers), computed by the
// build (CMakeLists.txt): an edited loader never takes the entries an older one wrote. A build that does not
// define it (the fuzz build, which runs with the cache off) keys by kMeshLoaderVersion alone.
#ifndef SHADELAB_MESH_LOADER_DIGEST
#define SHADELAB_MESH_LOADER_DIGEST "none"
#endif

namespace fs = std::filesystem;

namespace shadelab {

namespace {

constexpr char kMagic[4] = {'S', 'L', 'M', 'C'};
constexpr std::uint32_t kFormat = 1;
using cache_file::kDigest;
using cache_file::kHeader;
constexpr std::size_t kCounts = 10;   // u64 fields before the notes (encode_head)

static_assert(sizeof(glm::dvec3) == 3 * sizeof(double) && sizeof(glm::u32vec3) == 3 * sizeof(std::uint32_t),
              "the entry stores positions, normals and triangles as they lie in memory");
// A field added to Mesh or MeshLoadReport must be stored in the entry too (encode_head, decode_payload, with kFormat
// bumped), or a hit would return it empty while the full load fills it: these fail to compile until it is.
static_assert(sizeof(Mesh) == 3 * sizeof(std::vector<glm::dvec3>) + sizeof(std::string),
              "Mesh changed: store the new field in the mesh cache entry");
static_assert(sizeof(MeshLoadReport) == 7 * sizeof(std::size_t) + sizeof(std::vector<std::string>),   // 6 counts, 1 flag
              "MeshLoadReport changed: store the new field in the mesh cache entry");

using cache_file::Sha256;

using bytes::get_le;
using bytes::hex;
using bytes::put_u64;

// The arrays are stored in the machine's byte order, which is therefore part of the key.
const char* byte_order() {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    return "big-endian";
#else
    return "little-endian";
#endif
}

// The report's counts, the mesh's sizes and the notes: everything of the payload before the arrays.
std::string encode_head(const Mesh& m, const MeshLoadReport& r) {
    std::string s;
    for (std::uint64_t v : {std::uint64_t(m.positions.size()), std::uint64_t(m.triangles.size()),
                            std::uint64_t(r.vertices_in), std::uint64_t(r.faces_in), std::uint64_t(r.triangles_out),
                            std::uint64_t(r.degenerate_dropped), std::uint64_t(r.unused_vertices),
                            std::uint64_t(r.normals_repaired), std::uint64_t(r.normals_from_file ? 1 : 0),
                            std::uint64_t(r.notes.size())})
        put_u64(s, v);
    for (const std::string& note : r.notes) {
        put_u64(s, note.size());
        s += note;
    }
    return s;
}

// Reads a payload from `at` on, never past the end of `s`: every read that would is refused (ok() false).
class Reader {
public:
    Reader(const std::string& s, std::size_t at) : s_(s), at_(at) {}
    std::uint64_t u64() {
        if (!ok_ || left() < 8) return fail();
        const std::uint64_t v = get_le(s_, at_, 8);
        at_ += 8;
        return v;
    }
    bool bytes(void* out, std::uint64_t n) {
        if (!ok_ || n > left()) return fail() != 0;
        if (n) std::memcpy(out, s_.data() + at_, std::size_t(n));
        at_ += std::size_t(n);
        return true;
    }
    std::size_t left() const { return s_.size() - at_; }
    bool ok() const { return ok_; }

private:
    std::uint64_t fail() {
        ok_ = false;
        return 0;
    }
    const std::string& s_;
    std::size_t at_;
    bool ok_ = true;
};

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// What load_mesh promises of a mesh: at least one triangle, every index in range, a normal per vertex, every
// number finite. Empty when `m` is so, else what is wrong.
std::string malformed(const Mesh& m, const MeshLoadReport& r) {
    if (m.triangles.empty() || r.triangles_out != m.triangles.size()) return "no triangles, or not the report's count";
    if (m.normals.size() != m.positions.size()) return "not one normal per vertex";
    const std::uint64_t nv = m.positions.size();
    for (const auto& t : m.triangles)
        if (t[0] >= nv || t[1] >= nv || t[2] >= nv) return "a triangle names a vertex that does not exist";
    for (std::size_t i = 0; i < m.positions.size(); ++i)
        if (!finite(m.positions[i]) || !finite(m.normals[i])) return "a NaN/Inf position or normal";
    return {};
}

// The payload (after the header) into `m` and `r`; false with the reason when it is not well formed.
bool decode_payload(const std::string& f, Mesh& m, MeshLoadReport& r, std::string& why) {
    Reader in(f, kHeader);
    std::uint64_t c[kCounts];
    for (std::uint64_t& v : c) v = in.u64();
    const std::uint64_t nv = c[0], nt = c[1], notes = c[9];
    if (!in.ok() || c[8] > 1 || notes > in.left() / 8) return (why = "the payload's counts are malformed"), false;
    r.vertices_in = std::size_t(c[2]);
    r.faces_in = std::size_t(c[3]);
    r.triangles_out = std::size_t(c[4]);
    r.degenerate_dropped = std::size_t(c[5]);
    r.unused_vertices = std::size_t(c[6]);
    r.normals_repaired = std::size_t(c[7]);
    r.normals_from_file = c[8] == 1;
    r.notes.resize(std::size_t(notes));
    for (std::string& note : r.notes) {
        const std::uint64_t len = in.u64();
        if (!in.ok() || len > in.left()) return (why = "a note runs past the payload"), false;
        note.resize(std::size_t(len));
        in.bytes(note.data(), len);
    }
    const std::size_t left = in.left();
    if (nv > left / 48 || nt > left / 12 || nv * 48 + nt * 12 != left)
        return (why = "the vertex and triangle counts do not match the payload's size"), false;
    m.positions.resize(std::size_t(nv));
    m.normals.resize(std::size_t(nv));
    m.triangles.resize(std::size_t(nt));
    in.bytes(m.positions.data(), nv * 24);
    in.bytes(m.normals.data(), nv * 24);
    in.bytes(m.triangles.data(), nt * 12);
    why = malformed(m, r);
    if (!why.empty()) why = "the stored mesh is malformed: " + why;
    return why.empty();
}

// Size and modification time of a file: a file whose stamp changed while it was loaded is not stored.
struct FileStamp {
    std::uintmax_t size = 0;
    fs::file_time_type mtime{};
    bool ok = false;
    bool operator==(const FileStamp& o) const { return ok && o.ok && size == o.size && mtime == o.mtime; }
};

FileStamp stamp_of(const std::string& path) {
    std::error_code e1, e2;
    FileStamp s;
    s.size = fs::file_size(path, e1);
    s.mtime = fs::last_write_time(path, e2);
    s.ok = !e1 && !e2;
    return s;
}

// One writer at a time in this process: atomic_file's temporary is named by the process, not the thread.
std::mutex& write_mutex() {
    static std::mutex m;
    return m;
}

}  // namespace

std::string mesh_cache_dir(const std::string& setting) {
    return cache_file::folder(setting, "SHADELAB_MESH_CACHE", "meshes");
}

std::string mesh_cache_key(const std::string& path, const std::string& ext) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("mesh file '" + path + "' cannot be opened: check its read permission");
    Sha256 file;
    std::vector<char> buf(std::size_t(1) << 20);
    while (in) {
        in.read(buf.data(), std::streamsize(buf.size()));
        file.add(buf.data(), std::size_t(in.gcount()));
    }
    if (in.bad()) throw Error("mesh file '" + path + "' could not be read to its end: is it being written?");
    // Newline-separated fields none of which holds a newline, then the fixed-size digest: no two different
    // tuples give the same bytes.
    const std::string m = "shadelab-mesh-cache " + std::to_string(kFormat) + "\nloader " +
                          std::to_string(kMeshLoaderVersion) + " " + SHADELAB_MESH_LOADER_DIGEST + "\nOpenMesh " +
                          std::to_string(OM_VERSION) + "\n" + byte_order() + "\n" + ext + "\n" + file.raw();
    Sha256 key;
    key.add(m.data(), m.size());
    return hex(key.raw());
}

std::string mesh_cache_entry(const std::string& dir, const std::string& key) {
    return (fs::path(dir) / (key + ".slmesh")).string();
}

bool read_mesh_cache_entry(const std::string& dir, const std::string& key, Mesh& mesh, MeshLoadReport& report,
                           std::string& why) {
    why.clear();
    const std::string path = mesh_cache_entry(dir, key);
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return false;
    try {
        const std::uintmax_t size = fs::file_size(path, ec);
        if (ec) return (why = "its size cannot be read: " + ec.message()), false;
        // Read whole, then copied into the mesh: twice its size.
        if (2.0 * double(size) > double(memory_limit())) return (why = "larger than the memory limit allows"), false;
        std::ifstream in(path, std::ios::binary);
        std::string f(std::size_t(size), '\0');
        if (!in.read(f.data(), std::streamsize(size)) || in.peek() != std::char_traits<char>::eof())
            return (why = "it cannot be read whole (changed while read?)"), false;
        why = cache_file::header_problem(f, kMagic, kFormat, key, "mesh-cache", "payload");
        if (!why.empty()) return false;
        Mesh m;
        MeshLoadReport r;
        if (!decode_payload(f, m, r, why)) return false;
        mesh = std::move(m);
        report = std::move(r);
        return true;
    } catch (const std::exception& e) {   // std::bad_alloc, a failing OpenSSL: not fatal, the file is there
        why = std::string("it could not be read: ") + e.what();
        return false;
    }
}

bool write_mesh_cache_entry(const std::string& dir, const std::string& key, const Mesh& mesh,
                            const MeshLoadReport& report) {
    if (key.size() != 2 * kDigest || dir.empty() || !malformed(mesh, report).empty()) return false;
    try {
        const std::string head = encode_head(mesh, report);
        const std::size_t pos = mesh.positions.size() * 24, nrm = mesh.normals.size() * 24, tri = mesh.triangles.size() * 12;
        Sha256 h;
        h.add(head.data(), head.size());
        h.add(mesh.positions.data(), pos);
        h.add(mesh.normals.data(), nrm);
        h.add(mesh.triangles.data(), tri);
        const std::string header = cache_file::header(kMagic, kFormat, key, head.size() + pos + nrm + tri, h.raw());
        std::lock_guard<std::mutex> lock(write_mutex());
        static std::set<std::string> swept;   // the leftovers of a killed process, once per folder and process
        if (swept.insert(dir).second) remove_stale_temporaries(dir);
        write_file_atomically(mesh_cache_entry(dir, key), "mesh cache entry", [&](const std::string& tmp, std::string&) {
            std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
            out.write(header.data(), std::streamsize(header.size()));
            out.write(head.data(), std::streamsize(head.size()));
            out.write(reinterpret_cast<const char*>(mesh.positions.data()), std::streamsize(pos));
            out.write(reinterpret_cast<const char*>(mesh.normals.data()), std::streamsize(nrm));
            out.write(reinterpret_cast<const char*>(mesh.triangles.data()), std::streamsize(tri));
            out.close();
            return bool(out);
        });
    } catch (const std::exception&) {
        return false;   // read-only, full, a file where the folder should be: load without the cache
    }
    return true;
}

Mesh load_mesh(const std::string& path, MeshLoadReport* report, MeshCacheUse* cache) {
    MeshCacheUse local;
    MeshCacheUse& use = cache ? *cache : local;
    use.hit = use.rejected = use.written = false;
    use.why.clear();
    const std::string dir = mesh_cache_dir(use.setting);
    std::error_code ec;
    // A pipe or device cannot be read twice (once for the key, once by the loader): such paths skip the cache.
    if (dir.empty() || !fs::is_regular_file(path, ec)) return load_mesh_uncached(path, report);
    const std::string ext = check_mesh_opens(path);   // the same first errors as the full load
    const FileStamp before = stamp_of(path);
    const std::string key = mesh_cache_key(path, ext);
    Mesh m;
    MeshLoadReport r;
    if (read_mesh_cache_entry(dir, key, m, r, use.why)) {
        use.hit = true;
        m.source = path;
        log_out(LogLevel::Verbose) << "mesh cache: " << path << " from " << mesh_cache_entry(dir, key) << "\n";
        if (report) *report = std::move(r);
        return m;
    }
    use.rejected = !use.why.empty();
    if (use.rejected)
        log_out(LogLevel::Verbose) << "mesh cache: entry " << mesh_cache_entry(dir, key) << " not used (" << use.why
                                   << "): loading " << path << "\n";
    m = load_mesh_uncached(path, &r);
    if (stamp_of(path) == before) use.written = write_mesh_cache_entry(dir, key, m, r);
    if (report) *report = std::move(r);
    return m;
}

}  // namespace shadelab
