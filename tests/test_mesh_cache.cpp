// The mesh cache (host/mesh/mesh_cache.hpp): a hit returns the fresh load's mesh bit for bit and its report, an
// edited file is a miss whatever its time stamp, a damaged entry is rejected, loaded from the file and rewritten,
// "off" writes nothing, and a cache that cannot be written does not stop a load. Every case uses its own scratch
// folder; the test runner turns the user's cache off for every other test (tests/main.cpp).
#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <set>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cl/program_cache.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "mesh/mesh.hpp"
#include "mesh/mesh_cache.hpp"
#include "support.hpp"

using namespace shadelab;
namespace fs = std::filesystem;

namespace {

using test::ScopedEnv;

struct Loaded {
    Mesh mesh;
    MeshLoadReport report;
    MeshCacheUse use;
};

Loaded load(const std::string& path, const fs::path& cache) {
    Loaded l;
    l.use.setting = cache.string();
    l.mesh = load_mesh(path, &l.report, &l.use);
    return l;
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Bit for bit: the arrays' bytes (so -0.0 against 0.0 or another NaN payload would show), the source, every
// field of the report and every note.
void check_same(const Loaded& got, const Mesh& want, const MeshLoadReport& wr) {
    CHECK(same_bytes(got.mesh.positions, want.positions));
    CHECK(same_bytes(got.mesh.normals, want.normals));
    CHECK(same_bytes(got.mesh.triangles, want.triangles));
    CHECK(got.mesh.source == want.source);
    const MeshLoadReport& r = got.report;
    CHECK(r.vertices_in == wr.vertices_in);
    CHECK(r.faces_in == wr.faces_in);
    CHECK(r.triangles_out == wr.triangles_out);
    CHECK(r.degenerate_dropped == wr.degenerate_dropped);
    CHECK(r.unused_vertices == wr.unused_vertices);
    CHECK(r.normals_from_file == wr.normals_from_file);
    CHECK(r.normals_repaired == wr.normals_repaired);
    CHECK(r.notes == wr.notes);
}

std::vector<fs::path> entries(const fs::path& cache) {
    std::vector<fs::path> v;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(cache, ec))
        if (e.path().extension() == ".slmesh") v.push_back(e.path());
    return v;
}

std::size_t files_under(const fs::path& dir) {
    std::size_t n = 0;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec))
        n += it->is_regular_file(ec) ? 1 : 0;
    return n;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

void spit(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

// The raw SHA-256 of `bytes` (the test's own, from the program cache's helper: not the code under test).
std::string sha256_raw(const std::string& bytes) {
    const std::string h = sha256_hex(bytes);
    std::string raw;
    for (std::size_t i = 0; i < h.size(); i += 2) raw += char(std::stoi(h.substr(i, 2), nullptr, 16));
    return raw;
}

// The files with repairs in their reports, and the formats' own test files.
const std::vector<std::string> kRepaired = {"cube_no_normals.obj", "partial_normals.obj", "zero_normal.obj",
                                            "cancel.obj", "degenerate.obj", "repeated.obj", "repeated.off",
                                            "tetra.off", "tetra.ply", "tetra.stl", "tetra_binary.stl",
                                            "upper_case.OFF", "scene_quad.obj"};

}  // namespace

TEST_CASE("mesh cache: a hit gives the fresh load's mesh and report, bit for bit, for every bundled mesh and repaired file",
          "[mesh][cache]") {
    const fs::path cache = test::scratch_dir("mesh-cache-hit");
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(test::kMeshes)) {
        const std::string ext = e.path().extension().string();
        if (ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl") files.push_back(e.path().string());
    }
    std::sort(files.begin(), files.end());
    REQUIRE(files.size() >= 5);   // suzanne, spot, teapot, the bunny, the dragon
    for (const std::string& f : kRepaired) files.push_back(test::kData + "/" + f);
    // What the reports hold across these files, so that the comparison covers every kind of repair.
    std::size_t degenerate = 0, repaired_normals = 0, computed = 0, unused = 0, notes = 0;
    std::set<std::string> keys;   // upper_case.OFF holds tetra.off's bytes: one key, so its first load is a hit
    for (const std::string& path : files) {
        INFO(path);
        MeshLoadReport want_report;
        const Mesh want = load_mesh_uncached(path, &want_report);
        const bool seen = !keys.insert(mesh_cache_key(path, lower_ext(path))).second;
        const Loaded first = load(path, cache);
        CHECK(first.use.hit == seen);
        CHECK_FALSE(first.use.rejected);
        CHECK(first.use.written == !seen);
        check_same(first, want, want_report);
        const Loaded second = load(path, cache);
        CHECK(second.use.hit);
        CHECK_FALSE(second.use.written);
        check_same(second, want, want_report);
        degenerate += want_report.degenerate_dropped ? 1 : 0;
        repaired_normals += want_report.normals_repaired ? 1 : 0;
        computed += want_report.normals_from_file ? 0 : 1;
        unused += want_report.unused_vertices ? 1 : 0;
        notes += want_report.notes.size();
    }
    CHECK(keys.size() == files.size() - 1);
    CHECK(entries(cache).size() == keys.size());
    CHECK(degenerate >= 2);
    CHECK(repaired_normals >= 1);
    CHECK(computed >= 3);
    CHECK(unused >= 2);
    CHECK(notes >= 5);
}

TEST_CASE("mesh cache: a hit is the entry's content (a well-formed entry is used as it is)", "[mesh][cache]") {
    const fs::path cache = test::scratch_dir("mesh-cache-entry-used");
    const std::string path = test::kData + "/tetra.off";
    MeshLoadReport forged;
    forged.triangles_out = 2;
    forged.notes = {"a note only the entry holds"};
    Mesh quad = make_quad(3.0);
    REQUIRE(write_mesh_cache_entry(cache.string(), mesh_cache_key(path, ".off"), quad, forged));
    const Loaded l = load(path, cache);
    CHECK(l.use.hit);
    CHECK(l.mesh.positions == quad.positions);
    CHECK(l.mesh.triangles == quad.triangles);
    CHECK(l.mesh.source == path);
    CHECK(l.report.notes == forged.notes);
    // Another extension is another key: the same bytes read as another format are not that entry.
    CHECK(mesh_cache_key(path, ".off") != mesh_cache_key(path, ".ply"));
}

TEST_CASE("mesh cache: an edited file is a miss even with the same size and time stamp", "[mesh][cache]") {
    const fs::path dir = test::scratch_dir("mesh-cache-edited");
    const fs::path cache = dir / "cache", mesh = dir / "m.off";
    fs::copy_file(test::kData + "/tetra.off", mesh);
    const Loaded a = load(mesh.string(), cache);
    REQUIRE(a.use.written);
    REQUIRE(load(mesh.string(), cache).use.hit);
    const auto stamp = fs::last_write_time(mesh);
    std::string text = slurp(mesh);
    const std::size_t at = text.find("0 0 1\n");
    REQUIRE(at != std::string::npos);
    text[at + 4] = '2';   // vertex 3 from (0, 0, 1) to (0, 0, 2): same size
    spit(mesh, text);
    fs::last_write_time(mesh, stamp);
    const Loaded b = load(mesh.string(), cache);
    CHECK_FALSE(b.use.hit);
    CHECK_FALSE(b.use.rejected);
    CHECK(b.use.written);
    MeshLoadReport want_report;
    const Mesh want = load_mesh_uncached(mesh.string(), &want_report);
    check_same(b, want, want_report);
    CHECK(std::count(b.mesh.positions.begin(), b.mesh.positions.end(), glm::dvec3(0, 0, 2)) == 1);
    CHECK(load(mesh.string(), cache).use.hit);
    CHECK(entries(cache).size() == 2);
}

TEST_CASE("mesh cache: truncated, corrupt, misnamed and malformed entries are rejected, loaded from the file and rewritten",
          "[mesh][cache]") {
    const fs::path cache = test::scratch_dir("mesh-cache-damaged");
    const std::string path = test::kMeshes + "/suzanne.obj";   // notes, duplicated vertices, 968 triangles
    MeshLoadReport want_report;
    const Mesh want = load_mesh_uncached(path, &want_report);
    REQUIRE_FALSE(want_report.notes.empty());   // the note's byte flipped below is a note's
    REQUIRE(load(path, cache).use.written);
    REQUIRE(entries(cache).size() == 1);
    const fs::path entry = entries(cache)[0];
    const std::string good = slurp(entry);
    REQUIRE(good.size() > 1000);
    constexpr std::size_t kHeader = 4 + 4 + 32 + 8 + 32;

    auto flipped = [&](std::size_t at) {
        std::string s = good;
        s[at] = char(s[at] ^ 0x5a);
        return s;
    };
    // A well-formed entry (its payload's SHA-256 right) whose last triangle names a vertex that does not exist.
    std::string bad_index = good;
    const std::uint32_t huge = 0xfffffff0u;
    std::memcpy(&bad_index[good.size() - 4], &huge, 4);
    bad_index.replace(48, 32, sha256_raw(bad_index.substr(kHeader)));
    struct Damage {
        const char* name;
        std::string bytes;
    };
    const std::vector<Damage> damages = {{"truncated to half", good.substr(0, good.size() / 2)},
                                         {"truncated by one byte", good.substr(0, good.size() - 1)},
                                         {"one byte appended", good + "x"},
                                         {"truncated header", good.substr(0, 20)},
                                         {"a byte of the report's counts flipped", flipped(kHeader + 20)},
                                         {"a byte of a note flipped", flipped(kHeader + 90)},
                                         {"a byte of the positions flipped", flipped(good.size() / 2)},
                                         {"a byte of the triangles flipped", flipped(good.size() - 3)},
                                         {"a byte of the stored SHA-256 flipped", flipped(60)},
                                         {"the size field changed", flipped(40)},
                                         {"another key inside", flipped(10)},
                                         {"another format version", flipped(4)},
                                         {"bad magic", flipped(0)},
                                         {"empty file", std::string()},
                                         {"well formed, a triangle index out of range", bad_index}};
    for (const Damage& d : damages) {
        INFO(d.name);
        spit(entry, d.bytes);
        const Loaded l = load(path, cache);
        CHECK_FALSE(l.use.hit);
        CHECK(l.use.rejected);
        CHECK_FALSE(l.use.why.empty());
        CHECK(l.use.written);
        check_same(l, want, want_report);
        CHECK(slurp(entry) == good);   // rewritten as it was
        const Loaded again = load(path, cache);
        CHECK(again.use.hit);
        check_same(again, want, want_report);
    }
    // A folder where the entry should be: not an entry (missing), and it cannot be replaced; the load goes on.
    fs::remove(entry);
    fs::create_directories(entry / "x");
    const Loaded l = load(path, cache);
    CHECK_FALSE(l.use.hit);
    CHECK_FALSE(l.use.written);
    check_same(l, want, want_report);
}

TEST_CASE("mesh cache: off writes nothing, and the folder follows SHADELAB_MESH_CACHE, XDG_CACHE_HOME and HOME",
          "[mesh][cache]") {
    const fs::path dir = test::scratch_dir("mesh-cache-off");
    const std::string path = test::kData + "/cube_no_normals.obj";
    const std::string xdg = (dir / "xdg").string(), home = (dir / "home").string();
    ScopedEnv x("XDG_CACHE_HOME", xdg.c_str()), h("HOME", home.c_str());
    {
        ScopedEnv off("SHADELAB_MESH_CACHE", "off");
        MeshCacheUse use;   // setting "": the environment's
        const Mesh m = load_mesh(path, nullptr, &use);
        CHECK(m.triangles.size() == 12);
        CHECK_FALSE(use.written);
        CHECK(mesh_cache_dir("").empty());
        CHECK(files_under(dir) == 0);
        MeshCacheUse zero;
        zero.setting = "0";
        load_mesh(path, nullptr, &zero);
        CHECK_FALSE(zero.written);
        CHECK(files_under(dir) == 0);
    }
    {
        ScopedEnv unset("SHADELAB_MESH_CACHE", nullptr);
        CHECK(mesh_cache_dir("") == (fs::path(xdg) / "shadelab" / "meshes").string());
        MeshCacheUse use;
        load_mesh(path, nullptr, &use);
        CHECK(use.written);
        CHECK(entries(fs::path(xdg) / "shadelab" / "meshes").size() == 1);
        ScopedEnv no_xdg("XDG_CACHE_HOME", nullptr);
        CHECK(mesh_cache_dir("") == (fs::path(home) / ".cache" / "shadelab" / "meshes").string());
    }
    {
        ScopedEnv there("SHADELAB_MESH_CACHE", (dir / "named").string().c_str());
        CHECK(mesh_cache_dir("") == (dir / "named").string());
        CHECK(mesh_cache_dir("off").empty());   // the setting wins over the variable
        MeshCacheUse use;
        load_mesh(path, nullptr, &use);
        CHECK(use.written);
        CHECK(entries(dir / "named").size() == 1);
    }
}

TEST_CASE("mesh cache: a cache folder that cannot be written does not stop the load", "[mesh][cache]") {
    const fs::path dir = test::scratch_dir("mesh-cache-unwritable");
    spit(dir / "a-file", "not a folder");
    const std::string path = test::kData + "/degenerate.obj";
    MeshLoadReport want_report;
    const Mesh want = load_mesh_uncached(path, &want_report);
    const Loaded l = load(path, dir / "a-file" / "cache");   // its parent is a file: cannot be created
    CHECK_FALSE(l.use.hit);
    CHECK_FALSE(l.use.written);
    check_same(l, want, want_report);
    if (::geteuid() != 0) {   // root may write anywhere: the permission case means something only for others
        fs::create_directories(dir / "ro");
        fs::permissions(dir / "ro", fs::perms::owner_read | fs::perms::owner_exec);
        const Loaded r = load(path, dir / "ro");
        CHECK_FALSE(r.use.written);
        check_same(r, want, want_report);
        fs::permissions(dir / "ro", fs::perms::owner_all);
    }
}

TEST_CASE("mesh cache: a file the loader refuses is refused the same way with the cache, and nothing is stored",
          "[mesh][cache]") {
    const fs::path cache = test::scratch_dir("mesh-cache-refused");
    for (const char* f : {"nan.obj", "points_only.obj", "garbage.ply", "empty.obj", "does-not-exist.obj", "unknown.xyz"}) {
        INFO(f);
        const std::string path = test::kData + "/" + f;
        std::string plain;
        try {
            load_mesh_uncached(path);
        } catch (const Error& e) {
            plain = e.what();
        }
        REQUIRE_FALSE(plain.empty());
        MeshCacheUse use;
        use.setting = cache.string();
        CHECK_THROWS_WITH(load_mesh(path, nullptr, &use), plain);
        CHECK_FALSE(use.written);
    }
    CHECK(entries(cache).empty());
}
