// Hostile and broken input: every file that once crashed, hung or silently misled shadelab is kept in
// tests/data/hostile and must now end in one clear shadelab::Error (or, through the CLI, exit 1 with one
// line) -- never a signal, a hang, a partial read without a word, or NaN in a figure.
#include <catch2/catch.hpp>

#include <signal.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "color/image_compare.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/limits.hpp"
#include "image/fits.hpp"
#include "image/image.hpp"
#include "mesh/mesh.hpp"
#include "mesh/mesh_check.hpp"
#include "photometry/csv.hpp"
#include "photometry/pvl.hpp"
#include "scene/batch.hpp"
#include "scene/scene.hpp"
#include "support.hpp"

extern char** environ;

using namespace shadelab;
namespace fs = std::filesystem;

namespace {

const std::string kHostile = test::kData + "/hostile";

std::string write(const fs::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The shadelab binary next to the test binary; empty, with a warning, when it was not built.
fs::path cli_exe() {
    const fs::path exe = fs::read_symlink("/proc/self/exe").parent_path() / "shadelab";
    if (fs::exists(exe)) return exe;
    WARN("no shadelab binary next to the test binary: build the 'shadelab' target to run this test");
    return {};
}

// Runs the CLI with `args` (stdout and stderr to files in `dir`); returns the wait status.
int run_cli(const fs::path& exe, const std::vector<std::string>& args, const fs::path& dir, std::string* err = nullptr) {
    std::string cmd = "'" + exe.string() + "'";
    for (const auto& a : args) cmd += " '" + a + "'";
    cmd += " > '" + (dir / "stdout.txt").string() + "' 2> '" + (dir / "stderr.txt").string() + "'";
    const int status = std::system(cmd.c_str());
    if (err) *err = slurp(dir / "stderr.txt");
    return status;
}

Image flat(int w, int h, float v) {
    Image img(w, h, 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = v;
            img.at(x, y, 3) = 1.0f;
        }
    return img;
}

}  // namespace

// ---- meshes -------------------------------------------------------------------------------------------

TEST_CASE("mesh files that crashed or hung OpenMesh are refused with the file, the line and the reason", "[hostile][mesh]") {
    struct Case {
        const char* file;
        std::vector<std::string> says;
    };
    // Each was found by hand or by fuzzing (issue 16); the comment says what OpenMesh did with it.
    const std::vector<Case> cases = {
        // SIGABRT: assertion !vhandles.empty() in OpenMesh's OBJ reader
        {"obj_face_corner_without_vertex.obj", {"line 2", "'/1'", "no vertex index"}},
        // heap use-after-free in OpenMesh's set_normal: a corner with a normal names a vertex that does not
        // exist (found by fuzz/fuzz_mesh in its first 30 s)
        {"obj_fuzz_use_after_free.obj", {"line 5", "'3//1' names vertex 3, but only 1 are defined above it"}},
        // a corner naming texture coordinate 5 of none: read out of bounds by OpenMesh
        {"obj_texcoord_out_of_range.obj", {"line 4", "texture coordinate 5", "only 0"}},
        // endless loop printing "Unsupported keyword : prope"
        {"ply_header_cut_in_keyword.ply", {"line 4", "'prope'", "not a PLY header keyword"}},
        // SIGSEGV in _PLYReader_::can_u_read
        {"ply_misspelt_element.ply", {"line 3", "'elemenX'", "not a PLY header keyword"}},
        // 3 of 4 faces rendered without a word
        {"ply_truncated_body.ply", {"ends after 3 of the 4 'face' items", "truncated"}},
        {"off_truncated.off", {"ends after 2 of its 4 faces", "truncated"}},
        // counts on the keyword's line, where OpenMesh 9 does not read them: with nothing after them it read
        // counts from nowhere and asked for 12 GB (found by fuzz/fuzz_mesh); with vertices after them it took
        // the first vertex for the counts and said "no triangles"
        {"off_counts_on_keyword_line.off", {"line 1", "counts are on the OFF line", "put 'vertices faces edges' on the line after OFF"}},
        {"off_counts_on_keyword_line_misread.off", {"line 1", "counts are on the OFF line"}},
        {"stl_truncated.stl", {"ends inside facet 4", "truncated"}},
        // 1e39 became Inf in OpenMesh's float parse and the load ended in "no triangles"
        {"ply_beyond_float.ply", {"line 13", "'1e39'", "beyond the range of a float"}},
        // the refusal itself was undefined behaviour: it cast the index inf to long long (UBSan, fuzz/fuzz_mesh)
        {"ply_face_index_inf.ply", {"face 0 names vertex inf, but the file has 4 vertices"}},
        {"obj_beyond_float.obj", {"NaN/Inf, beyond-float-range", "line 2"}},
    };
    for (const auto& c : cases) {
        const std::string path = kHostile + "/" + c.file;
        INFO(path);
        std::string what;
        try {
            load_mesh(path);
        } catch (const Error& e) {
            what = e.what();
        }
        INFO(what);
        CHECK(what.find(path) != std::string::npos);
        for (const auto& s : c.says) CHECK(what.find(s) != std::string::npos);
    }
}

TEST_CASE("the bundled meshes and the well-formed test files pass the structural check", "[hostile][mesh]") {
    for (const auto& dir : {test::kMeshes, test::kData})
        for (const auto& e : fs::directory_iterator(dir)) {
            std::string ext = e.path().extension().string();
            for (auto& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
            if (ext != ".obj" && ext != ".ply" && ext != ".off" && ext != ".stl") continue;
            if (e.path().filename() == "garbage.ply" || fs::file_size(e.path()) == 0) continue;
            INFO(e.path().string());
            CHECK_NOTHROW(check_mesh_file(e.path().string(), ext));
        }
}

TEST_CASE("every cut of a PLY, OFF and STL file is refused or read whole: never a hang, a crash or a partial mesh",
          "[hostile][mesh]") {
    // The figures: of 154 cut points of an ASCII PLY header, 131 hung OpenMesh. Here every prefix
    // of each file is loaded; it must either throw shadelab::Error or (a cut in trailing whitespace) give
    // the whole mesh (a cut in trailing whitespace or in the name after endsolid).
    const fs::path dir = test::scratch_dir("hostile/cuts");
    for (const char* name : {"tetra.ply", "tetra.off", "tetra.stl", "nan_binary.ply", "tetra_binary.stl"}) {
        const std::string whole = slurp(test::kData + "/" + name);
        const std::string ext = fs::path(name).extension().string();
        std::size_t refused = 0, read = 0;
        for (std::size_t n = 1; n < whole.size(); ++n) {
            const std::string path = write(dir / ("cut" + ext), whole.substr(0, n));
            try {
                const Mesh m = load_mesh(path);
                CHECK(m.triangles.size() == 4);
                ++read;
            } catch (const Error&) {
                ++refused;
            }
        }
        INFO(name << ": " << refused << " cuts refused, " << read << " read whole");
        std::cout << "cuts of " << name << ": " << whole.size() - 1 << ", refused with one line " << refused
                  << ", read whole (the cut left every face intact) " << read << "\n";
        CHECK(refused + read == whole.size() - 1);
        CHECK(refused > 0);
    }
}

TEST_CASE("a PLY header asking for billions of elements is refused without allocating them", "[hostile][mesh]") {
    const fs::path dir = test::scratch_dir("hostile/ply_counts");
    const std::string path = write(dir / "huge.ply",
                                   "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                                   "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                   "end_header\n0123456789ab");
    CHECK_THROWS_WITH(load_mesh(path), Catch::Contains("ends after 1 of the 4000000000 'vertex' items"));
    const std::string nolist = write(dir / "noprops.ply", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                                                          "property float y\nproperty float z\nelement junk 99999999999\nend_header\n");
    CHECK_THROWS_WITH(load_mesh(nolist), Catch::Contains("element 'junk' has no properties"));
}

// ---- compare ------------------------------------------------------------------------------------------

TEST_CASE("compare refuses NaN/Inf pixels by default, naming the first one and the count", "[hostile][compare]") {
    Image a = flat(8, 6, 0.5f), b = flat(8, 6, 0.5f);
    a.at(3, 2, 1) = std::numeric_limits<float>::infinity();
    a.at(5, 4, 0) = std::numeric_limits<float>::quiet_NaN();
    const NonFinitePixels n = find_non_finite(a);
    CHECK(n.count == 2);
    CHECK(n.x == 3);
    CHECK(n.y == 2);
    CHECK_THROWS_WITH(compare_images(a, b), Catch::Contains("2 pixels") && Catch::Contains("(x, y) = (3, 2)"));
    CHECK_THROWS_WITH(compare_images(b, a), Catch::Contains("the reference has 2 pixels"));
}

TEST_CASE("compare --ignore-nonfinite leaves those pixels out of every figure and counts them", "[hostile][compare]") {
    Image a = flat(8, 6, 0.5f), b = flat(8, 6, 0.5f);
    a.at(0, 0, 0) = 0.25f;   // one real difference elsewhere, so the figures are not all zero
    a.at(3, 2, 1) = std::numeric_limits<float>::infinity();
    b.at(6, 1, 2) = -std::numeric_limits<float>::infinity();
    const ImageDiff d = compare_images(a, b, 1e-3, true);
    CHECK(d.nonfinite_excluded == 2);
    CHECK(d.pixels == 8 * 6 - 2);
    for (double v : {d.de_mean, d.de_p99, d.de_max, d.rel_max, d.rel_p99, d.abs_max}) CHECK(std::isfinite(v));
    CHECK(d.abs_max == Approx(0.25));
    CHECK(d.de_max > 0.0);
    CHECK(d.de_map.at(3, 2, 0) == 0.0f);
    // The map of such a comparison, and even a map holding NaN itself, colour-maps without UB.
    Image m = d.de_map;
    m.at(1, 1, 0) = std::numeric_limits<float>::quiet_NaN();
    const Image c = colourise_delta_e(m, 5.0);
    const Image full = colourise_delta_e(Image(1, 1, 1), 0.0);
    CHECK(c.at(1, 1, 0) == Approx(1.0));   // NaN shown as full scale (the ramp's last stop)
    CHECK(c.at(1, 1, 1) == Approx(1.0));
    CHECK(full.at(0, 0, 2) == Approx(0.05));
}

TEST_CASE("the CLI: compare with an Inf pixel exits 1 naming it, and --ignore-nonfinite reports the count", "[hostile][compare][cli]") {
    const fs::path exe = cli_exe();
    if (exe.empty()) return;
    const fs::path dir = test::scratch_dir("hostile/compare_cli");
    // write_image refuses NaN/Inf, so the Inf image is written as PFM by hand (a 3-line header, then
    // little-endian float RGB rows, bottom row first).
    const int w = 4, h = 3;
    auto pfm = [&](const fs::path& p, bool with_inf) {
        std::ofstream out(p, std::ios::binary);
        out << "PF\n" << w << " " << h << "\n-1.0\n";
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c) {
                    float v = 0.4f;
                    if (with_inf && x == 2 && y == h - 1 - 1) v = std::numeric_limits<float>::infinity();   // image row 1
                    out.write(reinterpret_cast<const char*>(&v), 4);
                }
        return p.string();
    };
    const std::string a = pfm(dir / "a_inf.pfm", true), b = pfm(dir / "b.pfm", false);
    std::string err;
    int status = run_cli(exe, {"compare", a, b, "--map", (dir / "m.png").string()}, dir, &err);
    INFO(err);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 1);
    CHECK(err.find("a_inf.pfm' has 1 pixel holding NaN or Inf, the first at (x, y) = (2, 1):") != std::string::npos);
    status = run_cli(exe, {"compare", a, b, "--map", (dir / "m.png").string(), "--json", (dir / "d.json").string(),
                           "--ignore-nonfinite"},
                     dir, &err);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
    const std::string out = slurp(dir / "stdout.txt");
    INFO(out);
    CHECK(out.find("NaN/Inf excluded    1 pixel (NaN or Inf in either image") != std::string::npos);
    CHECK(out.find("nan") == std::string::npos);
    const auto j = nlohmann::json::parse(slurp(dir / "d.json"));
    CHECK(j["nonfinite_excluded"] == 1);
    CHECK(j["pixels"] == w * h - 1);
    CHECK(j["delta_e2000"]["mean"].is_number());
    CHECK(fs::exists(dir / "m.png"));
}

// ---- scenes and batches -------------------------------------------------------------------------------

TEST_CASE("scene files with overflowing numbers, deep nesting or a huge size are one clear error", "[hostile][scene]") {
    const fs::path dir = test::scratch_dir("hostile/scenes");
    const std::string mesh = test::kData + "/scene_quad.obj";
    const std::string overflow = write(dir / "overflow.json", "{ \"meshes\": [ { \"path\": \"" + mesh + "\" } ], \"ambient\": [1e999, 0, 0] }");
    CHECK_THROWS_WITH(load_scene(overflow), Catch::Contains("overflow.json") && Catch::Contains("not valid JSON") &&
                                                Catch::Contains("1e999"));
    const std::string deep = write(dir / "deep.json", "{ \"_x\": " + std::string(100000, '[') + std::string(100000, ']') + " }");
    CHECK_THROWS_WITH(load_scene(deep), Catch::Contains("deep.json") && Catch::Contains("nested deeper than 32 levels"));
    const std::string utf8 = write(dir / "utf8.json", "{ \"name\": \"bad\xff\xfe\", \"meshes\": [ { \"path\": \"" + mesh + "\" } ] }");
    CHECK_THROWS_WITH(load_scene(utf8), Catch::Contains("utf8.json") && Catch::Contains("not valid JSON"));
    {
        std::ofstream big(dir / "big.json");
        big << "{ \"_pad\": \"" << std::string(17u << 20, 'x') << "\" }";
    }
    CHECK_THROWS_WITH(load_scene((dir / "big.json").string()), Catch::Contains("more than the 16777216 a scene file may have"));
}

TEST_CASE("a batch with a 1e999 scene, a non-UTF-8 scene and a non-UTF-8 file name renders the good ones and writes the report",
          "[hostile][batch]") {
    const fs::path dir = test::scratch_dir("hostile/batch");
    const std::string mesh = test::kData + "/scene_quad.obj";
    const std::string good_scene =
        "{ \"camera\": { \"position\": [0, 0, 3], \"target\": [0, 0, 0], \"fov\": 20 }, \"resolution\": [24, 16], "
        "\"meshes\": [ { \"path\": \"" + mesh + "\" } ], \"outputs\": { \"exr\": \"{name}.exr\" } }";
    BatchOptions o;
    o.scenes = {write(dir / "bad.json", "{ \"meshes\": [ { \"path\": \"" + mesh + "\" } ], \"ambient\": [1e999, 0, 0] }"),
                write(dir / "good.json", good_scene),
                // a file name that is not UTF-8: it names the job, its output and the report entry
                write(dir / "latin1_caf\xe9.json", good_scene),
                // a name that is not UTF-8 inside the file: refused, and the message quotes the bytes
                write(dir / "utf8.json", "{ \"name\": \"caf\xe9\", \"meshes\": [ { \"path\": \"" + mesh + "\" } ] }")};
    o.out_dir = (dir / "out").string();
    o.progress = ProgressStyle::Lines;
    std::ostringstream log;
    o.log = &log;
    BatchSummary s;
    REQUIRE_NOTHROW(s = run_batch(o, test::runtime()));
    INFO(log.str());
    CHECK(s.failed == 2);
    CHECK(s.ok == 2);
    CHECK(s.exit_code() == 1);
    CHECK(fs::exists(dir / "out" / "good.exr"));
    CHECK(fs::exists(dir / "out" / "latin1_caf\xe9.exr"));
    const auto report = nlohmann::json::parse(slurp(s.report_json));
    CHECK(report["failed"] == 2);
    CHECK(report["jobs"].size() == 4);
    std::set<std::string> failed;
    for (const auto& j : report["jobs"])
        if (j["status"] == "failed") failed.insert(fs::path(j["scene"].get<std::string>()).filename().string());
    CHECK(failed == std::set<std::string>{"bad.json", "utf8.json"});
    for (const auto& j : report["jobs"])
        if (j["scene"].get<std::string>().find("bad.json") != std::string::npos)
            CHECK(j["error"].get<std::string>().find("1e999") != std::string::npos);
    CHECK(fs::exists(s.report_csv));
}

// ---- images and limits --------------------------------------------------------------------------------

TEST_CASE("image headers asking for gigabytes are refused up front with the figure", "[hostile][image]") {
    CHECK_THROWS_WITH(read_image(kHostile + "/fits_header_asks_for_6GB.fits"),
                      Catch::Contains("40000x40000") && Catch::Contains("6.4 GB") && Catch::Contains("truncated"));
    CHECK_THROWS_WITH(read_image(kHostile + "/png_ihdr_says_20000x20000.png"),
                      Catch::Contains("20000x20000") && Catch::Contains("1.2 GB") && Catch::Contains("cannot hold"));
    // EXR: a header whose chunks the file could not even index is refused before OpenImageIO opens it; a
    // file cut in its pixel data is caught by reading its last row before the image is allocated.
    CHECK_THROWS_WITH(read_image(kHostile + "/exr_header_says_20000x20000.exr"),
                      Catch::Contains("its header says 20000x20000 in 1250 chunks") && Catch::Contains("457 bytes"));
    CHECK_THROWS_WITH(read_image(kHostile + "/exr_truncated_256x256.exr"),
                      Catch::Contains("truncated or corrupt: its header says 256x256 but its last row cannot be read"));
}

// The fuzz finding of fuzz_image: an 877-byte EXR whose data window is 2097160x6 (its display window 8x6).
// OpenEXR's C++ reader allocates its decode buffers at open from that width (four ZIP line buffers of
// 16 rows x 12.6 MB here, each with two decompressor buffers: 1.6 GB), and OpenImageIO 2.4's converting
// read_scanlines then asked for 256 rows x 12.6 MB = 3.2 GB whatever the image's 6 rows. The header is now
// read first (OpenEXR's core library) and its cost checked; the read is native, converted by us.
TEST_CASE("an EXR whose data window is 2097160 pixels wide is refused before its decode buffers are allocated",
          "[hostile][image]") {
    const std::string wide = kHostile + "/exr_wide_data_window_3GB.exr";
    set_memory_limit(1000000000);
    CHECK_THROWS_WITH(read_image(wide), Catch::Contains("(2097160x6, decoded in chunks of 201.3 MB) would need") &&
                                            Catch::Contains("more than the limit of 1.0 GB"));
    set_memory_limit(0);
}

// Deep EXR (several samples per pixel, OpenEXR 2's deep scanline and deep tiled parts), written by
// `oiiotool --pattern constant:color=0.5,0.4,0.3,1,2 4x3 5 --chnames R,G,B,A,Z --deepen [--tile 2 2]`: shadelab
// reads flat images only, and says so instead of handing OpenImageIO's deep read to code that expects a flat one.
TEST_CASE("a deep EXR, scanline or tiled, is refused with a line that says how to flatten it", "[hostile][image]") {
    for (const char* layout : {"scanline", "tiled"}) {
        INFO(layout);
        const std::string path = kHostile + "/exr_deep_" + layout + "_4x3.exr";
        CHECK_THROWS_WITH(read_image(path), Catch::Contains("holds deep data (several samples per pixel)") &&
                                                Catch::Contains("--flatten") && Catch::Contains(path));
    }
}

// A geometry table is read into memory whole (each row kept to be written back with its value): its size is
// checked against the memory limit before reading (twice the file: a single endless line is read whole) and
// again after the first 4096 rows, from the rows' length (200 bytes a row, measured).
TEST_CASE("a geometry table too big for the memory limit is refused with its size and estimated rows",
          "[hostile][photometry]") {
    const fs::path dir = test::scratch_dir("hostile_csv_memory");
    const fs::path csv = dir / "geometry.csv";
    {
        std::ofstream out(csv);
        out << "phase,incidence,emission\n";
        for (int r = 0; r < 10000; ++r) out << "10.000,20.000,30.000\n";   // 21 bytes a row
    }
    const double bytes = double(fs::file_size(csv));
    set_memory_limit(std::uint64_t(5 * bytes));   // the file fits twice, its 10000 rows (2 MB) do not
    CHECK_THROWS_WITH(photometry::read_geometry_csv(csv.string()),
                      Catch::Contains("geometry table '" + csv.string() + "'") && Catch::Contains("about 10000 rows") &&
                          Catch::Contains("more than the limit") && Catch::Contains("SHADELAB_MAX_MEMORY"));
    set_memory_limit(std::uint64_t(1.5 * bytes));   // not even the file twice: refused before a row is read
    CHECK_THROWS_WITH(photometry::read_geometry_csv(csv.string()),
                      Catch::Contains("geometry table '" + csv.string() + "' would need") &&
                          !Catch::Contains("rows)"));
    set_memory_limit(std::uint64_t(15 * bytes));   // room for the rows: read
    CHECK(photometry::read_geometry_csv(csv.string()).geometry.size() == 10000);
    set_memory_limit(0);
}

// A 28 KB sparse GeoTIFF (written by GDAL with SPARSE_OK: no tile stored) whose one band is 30000x30000:
// read through GDAL as a band, its image (value and alpha, 7.2 GB) is checked against the limit first.
TEST_CASE("a GeoTIFF band of 30000x30000 in a 28 KB file is refused against the memory limit", "[hostile][image]") {
    set_memory_limit(1000000000);
    CHECK_THROWS_WITH(read_image(kHostile + "/gtiff_sparse_30000x30000.tif[1]"),
                      Catch::Contains("(30000x30000) would need 7.2 GB of memory, more than the limit of 1.0 GB"));
    set_memory_limit(0);
}

TEST_CASE("a PDS3 SCALING_FACTOR that takes stored floats beyond float range masks those pixels, not Inf", "[hostile][image]") {
    // Found by fuzz_raster: PC_REAL samples of 1e38 times SCALING_FACTOR 8.5 were handed on as Inf. The file (4x3,
    // written byte by byte, OFFSET 1.0) holds 1, 2, 1e38, -1e38 / 3e38, 0.5, 4e37, 0 / 1, 1, 1, 1: four
    // stored values would leave float range once scaled, 4e37 * 8.5 + 1 = 3.4e38 just stays in it.
    const Image img = read_image(kHostile + "/pds3_scaling_beyond_float.lbl");
    REQUIRE(img.width == 4);
    REQUIRE(img.height == 3);
    REQUIRE(img.channels == 2);
    for (const float v : img.pixels) REQUIRE(std::isfinite(v));
    const std::set<std::pair<int, int>> masked = {{2, 0}, {3, 0}, {0, 1}};
    const float stored[3][4] = {{1.0f, 2.0f, 1e38f, -1e38f}, {3e38f, 0.5f, 4e37f, 0.0f}, {1.0f, 1.0f, 1.0f, 1.0f}};
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x) {
            INFO("pixel (" << x << ", " << y << ")");
            const bool m = masked.count({x, y}) > 0;
            CHECK(img.at(x, y, 1) == (m ? 0.0f : 1.0f));
            if (!m) CHECK(img.at(x, y, 0) == float(double(stored[y][x]) * 8.5 + 1.0));
        }
}

TEST_CASE("EXR channels of mixed stored types (half and float) read exactly, channel by channel", "[image]") {
    // Written by OpenImageIO with channelformats half, float, half, float: R = 0.25 + x/8, G = y/4 + 1e-4
    // (1e-4 is not a half: a float channel read as half would lose it), B = 0.75, A = 1.
    const Image img = read_image(test::kData + "/exr_mixed_half_float_channels.exr");
    REQUIRE(img.width == 5);
    REQUIRE(img.height == 4);
    REQUIRE(img.channels == 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 5; ++x) {
            INFO("pixel (" << x << ", " << y << ")");
            CHECK(img.at(x, y, 0) == 0.25f + float(x) / 8.0f);
            CHECK(img.at(x, y, 1) == float(y) / 4.0f + 1e-4f);
            CHECK(img.at(x, y, 2) == 0.75f);
            CHECK(img.at(x, y, 3) == 1.0f);
        }
}

// fuzz_pvl: 100000 nested 'Group=a' lines recursed once per level until the stack overflowed (SIGSEGV).
TEST_CASE("a PVL file nesting blocks deeper than 32 levels is refused with the line, not a stack overflow",
          "[hostile][pvl]") {
    CHECK_THROWS_WITH(pvl::parse_file(kHostile + "/pvl_nested_100000_groups.pvl"),
                      Catch::Contains("pvl_nested_100000_groups.pvl:33: Group 'a' is nested 33 levels deep, more than the 32"));
    // 32 levels still read (ISIS files use two or three).
    std::string ok;
    for (int i = 0; i < 32; ++i) ok += "Group = g" + std::to_string(i) + "\n";
    for (int i = 31; i >= 0; --i) ok += "End_Group = g" + std::to_string(i) + "\n";
    const pvl::Block root = pvl::parse(ok + "End\n", "ok.pvl");
    CHECK(root.find("Group", "g31") != nullptr);
}

TEST_CASE("memory limit: sizes and the SHADELAB_MAX_MEMORY / --max-memory override", "[hostile][limits]") {
    CHECK(parse_bytes("16G", "x") == 16000000000ull);
    CHECK(parse_bytes("512M", "x") == 512000000ull);
    CHECK(parse_bytes("4096", "x") == 4096ull);
    CHECK_THROWS_WITH(parse_bytes("lots", "--max-memory"), Catch::Contains("--max-memory: 'lots' is not a memory size"));
    CHECK_THROWS_AS(parse_bytes("-3G", "x"), Error);
    CHECK_THROWS_AS(parse_bytes("nanG", "x"), Error);
    CHECK(format_bytes(6.4e9) == "6.4 GB");
    set_memory_limit(1000000);
    CHECK_THROWS_WITH(check_memory("--size 100000x100000", 1.6e12),
                      Catch::Contains("--size 100000x100000 would need 1.6 TB") && Catch::Contains("limit of 1.0 MB") &&
                          Catch::Contains("--max-memory"));
    CHECK_NOTHROW(check_memory("a small thing", 1e5));
    set_memory_limit(0);
    CHECK(memory_limit() > 1000000);
}

// ---- faults -------------------------------------------------------------------------------------------

TEST_CASE("unfinished temporaries of a dead process are removed, but a live process's are kept", "[hostile][faults]") {
    const fs::path dir = test::scratch_dir("hostile/stale");
    // A pid that certainly existed and is now gone: a child that exited and was reaped.
    const pid_t child = ::fork();
    if (child == 0) ::_exit(0);
    REQUIRE(child > 0);
    ::waitpid(child, nullptr, 0);
    const std::string dead = std::to_string(child), live = std::to_string(::getppid());
    write(dir / (".a.png.tmp" + dead + ".png"), "half an image");
    write(dir / (".report.json.tmp" + dead), "{ \"half");
    write(dir / (".b.exr.tmp" + live + ".exr"), "another run's image, being written");
    write(dir / "a.png", "a finished image");
    write(dir / ".tmp123", "not ours: no name before .tmp");
    CHECK(remove_stale_temporaries(dir.string()) == 2);
    std::set<std::string> left;
    for (const auto& e : fs::directory_iterator(dir)) left.insert(e.path().filename().string());
    CHECK(left == std::set<std::string>{".b.exr.tmp" + live + ".exr", "a.png", ".tmp123"});
    CHECK(remove_stale_temporaries((dir / "no-such-folder").string()) == 0);
}

TEST_CASE("kill -9 mid-batch: every image on disk is whole and identical to a clean run, and a rerun completes the rest",
          "[hostile][faults][cli]") {
    const fs::path exe = cli_exe();
    if (exe.empty()) return;
    const fs::path dir = test::scratch_dir("hostile/kill9");
    std::vector<std::string> scenes;
    for (int i = 0; i < 6; ++i)
        scenes.push_back(write(dir / ("k" + std::to_string(i) + ".json"),
                               "{ \"resolution\": [640, 640], \"meshes\": [ { \"path\": \"" + test::kMeshes +
                                   "/teapot.obj\", \"material\": { \"albedo\": [0." + std::to_string(i + 2) +
                                   ", 0.5, 0.5] } } ], \"outputs\": { \"png\": \"{name}.png\", \"exr\": \"{name}.exr\" } }"));
    auto batch_args = [&](const fs::path& out) {
        std::vector<std::string> a = {exe.string(), "batch"};
        a.insert(a.end(), scenes.begin(), scenes.end());
        a.insert(a.end(), {"--out", out.string()});
        return a;
    };
    // The clean run, for the reference images.
    {
        std::string cmd;
        for (const auto& a : batch_args(dir / "clean")) cmd += "'" + a + "' ";
        REQUIRE(std::system((cmd + "> /dev/null 2>&1").c_str()) == 0);
    }
    // The killed run: SIGKILL as soon as the first image is in place (so mid-batch, whatever the speed).
    const fs::path out = dir / "killed";
    std::vector<std::string> args = batch_args(out);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
    pid_t pid = 0;
    REQUIRE(posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ) == 0);
    posix_spawn_file_actions_destroy(&fa);
    bool exited = false;
    while (!exited) {
        int st = 0;
        if (::waitpid(pid, &st, WNOHANG) == pid) exited = true;
        else if (fs::exists(out / "k0.png") || fs::exists(out / "k0.exr")) break;
        else std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (!exited) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, nullptr, 0);
    }
    std::size_t whole = 0;
    for (const auto& e : fs::directory_iterator(out)) {
        const std::string name = e.path().filename().string();
        if (name[0] == '.') continue;   // an unfinished temporary: never mistaken for an image
        INFO(name);
        Image got, want;
        REQUIRE_NOTHROW(got = read_image(e.path().string()));
        REQUIRE_NOTHROW(want = read_image((dir / "clean" / name).string()));
        CHECK(got.pixels == want.pixels);
        ++whole;
    }
    std::cout << "kill -9 mid-batch: " << whole << " of 12 images in place at the kill"
              << (exited ? " (the batch had finished: nothing was interrupted)" : "") << "\n";
    // The rerun: finishes the rest, leaves no temporary, and every image equals the clean run's.
    std::string cmd;
    for (const auto& a : batch_args(out)) cmd += "'" + a + "' ";
    REQUIRE(std::system((cmd + "> /dev/null 2>&1").c_str()) == 0);
    std::size_t images = 0;
    for (const auto& e : fs::directory_iterator(out)) {
        const std::string name = e.path().filename().string();
        INFO(name);
        CHECK(name[0] != '.');
        if (e.path().extension() != ".png" && e.path().extension() != ".exr") continue;
        CHECK(read_image(e.path().string()).pixels == read_image((dir / "clean" / name).string()).pixels);
        ++images;
    }
    CHECK(images == 12);
}

TEST_CASE("every advertised linear output format writes (.hdr without alpha), and .pfm is not advertised", "[hostile][image]") {
    const fs::path dir = test::scratch_dir("hostile/formats");
    Image img(5, 4, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 5; ++x) {
            img.at(x, y, 0) = 0.25f * float(x);
            img.at(x, y, 1) = 0.5f;
            img.at(x, y, 2) = 2.0f * float(y);
            img.at(x, y, 3) = 1.0f;
        }
    for (const char* ext : {".exr", ".hdr", ".tif", ".fits"}) {
        INFO(ext);
        const std::string path = (dir / (std::string("i") + ext)).string();
        REQUIRE_NOTHROW(write_image(path, img));
        const Image back = read_image(path);
        CHECK(back.width == 5);
        CHECK(back.height == 4);
        // Radiance RGBE keeps 8 bits of mantissa per pixel: within 1%. FITS holds one grey plane.
        if (std::string(ext) != ".fits") CHECK(back.at(4, 3, 2) == Approx(6.0).epsilon(0.01));
    }
    CHECK(read_image((dir / "i.hdr").string()).channels == 3);
    CHECK_THROWS_WITH(encoding_for("x.pfm"), Catch::Contains("unsupported extension") && !Catch::Contains(".pfm)"));
}

TEST_CASE("a batch job whose resolution needs more memory than the limit fails with the figure, and the others run",
          "[hostile][batch][limits]") {
    const fs::path dir = test::scratch_dir("hostile/batch_memory");
    const std::string mesh = test::kData + "/scene_quad.obj";
    BatchOptions o;
    o.scenes = {write(dir / "huge.json", "{ \"resolution\": [16384, 16384], \"meshes\": [ { \"path\": \"" + mesh + "\" } ] }"),
                write(dir / "small.json", "{ \"resolution\": [16, 16], \"meshes\": [ { \"path\": \"" + mesh + "\" } ] }")};
    o.out_dir = (dir / "out").string();
    o.progress = ProgressStyle::Lines;
    std::ostringstream log;
    o.log = &log;
    set_memory_limit(2000000000);   // 2 GB: 16384^2 at 90 bytes/pixel needs 24.2 GB
    const BatchSummary s = run_batch(o, test::runtime());
    set_memory_limit(0);
    INFO(log.str());
    CHECK(s.failed == 1);
    CHECK(s.ok == 1);
    CHECK(log.str().find("huge.json': resolution 16384x16384 would need 24.2 GB of memory, more than the limit of 2.0 GB") !=
          std::string::npos);
    CHECK(fs::exists(dir / "out" / "small.png"));
}
