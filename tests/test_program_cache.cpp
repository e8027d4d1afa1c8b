// The program-binary cache (host/cl/program_cache.hpp): a warm entry is used, and a stale, truncated, corrupt,
// misnamed or driver-refused entry is detected, rebuilt from source and never used. Each case runs the kernel
// and checks what it computes, so "used the wrong binary" would show as a wrong number, not only a counter.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cl/program_cache.hpp"
#include "cl/runtime.hpp"
#include "support.hpp"

using namespace shadelab;
namespace fs = std::filesystem;

namespace {

// A kernel folder holding shade.cl (what Runtime looks for) and an include that sets the value it writes.
void write_kernels(const fs::path& dir, int value) {
    fs::create_directories(dir);
    std::ofstream(dir / "value.h") << "#define SL_CACHE_VALUE " << value << "\n";
    std::ofstream(dir / "shade.cl") << "#include \"value.h\"\n"
                                       "__kernel void fill(__global int* out) { out[get_global_id(0)] = SL_CACHE_VALUE * SL_SCALE; }\n";
}

struct Built {
    int value;
    std::size_t from_cache, rejected;
};

// Builds shade.cl with -DSL_SCALE=scale in a fresh runtime (as a new process would) and runs it once.
Built build_and_run(const fs::path& kernels, const fs::path& cache, int scale) {
    Runtime rt(RuntimeOptions{"", -1, kernels.string(), cache.string()});
    cl::Program p = rt.build("shade.cl", {"SL_SCALE=" + std::to_string(scale)});
    cl::Kernel k(p, "fill");
    cl::Buffer out(rt.context(), CL_MEM_WRITE_ONLY, sizeof(int) * 4);
    k.setArg(0, out);
    rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(4));
    std::vector<int> host(4, -1);
    rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, sizeof(int) * 4, host.data());
    REQUIRE(rt.programs_built() == 1);
    return Built{host[3], rt.programs_from_cache(), rt.cache_entries_rejected()};
}

std::vector<fs::path> entries(const fs::path& cache) {
    std::vector<fs::path> v;
    for (const auto& e : fs::directory_iterator(cache))
        if (e.path().extension() == ".clbin") v.push_back(e.path());
    return v;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

void spit(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

// After damage to the entry: this run rebuilds from source (the right value, nothing from the cache, one entry
// rejected), and the entry it writes back serves the next run (loaded, and the right value again).
void check_rebuilt_then_cached(const fs::path& root, int scale, int want) {
    const Built b = build_and_run(root / "k", root / "c", scale);
    CHECK(b.value == want);
    CHECK(b.from_cache == 0);
    CHECK(b.rejected == 1);
    const Built again = build_and_run(root / "k", root / "c", scale);
    CHECK(again.from_cache == 1);
    CHECK(again.value == want);
}

}  // namespace

TEST_CASE("program cache: a cold build writes an entry that the next runtime loads and runs", "[runtime][cache]") {
    const fs::path root = test::scratch_dir("program-cache-warm");
    write_kernels(root / "k", 7);
    const Built cold = build_and_run(root / "k", root / "c", 3);
    CHECK(cold.value == 21);
    CHECK(cold.from_cache == 0);
    REQUIRE(entries(root / "c").size() == 1);
    const Built warm = build_and_run(root / "k", root / "c", 3);
    CHECK(warm.value == 21);
    CHECK(warm.from_cache == 1);
    CHECK(warm.rejected == 0);
    // Other options are another key, another entry.
    const Built other = build_and_run(root / "k", root / "c", 5);
    CHECK(other.value == 35);
    CHECK(other.from_cache == 0);
    CHECK(entries(root / "c").size() == 2);
}

TEST_CASE("program cache: an edited include is a new key, so the stale binary is never used", "[runtime][cache]") {
    const fs::path root = test::scratch_dir("program-cache-stale");
    write_kernels(root / "k", 7);
    REQUIRE(build_and_run(root / "k", root / "c", 2).value == 14);
    write_kernels(root / "k", 9);   // shade.cl unchanged; only the header it includes
    const Built b = build_and_run(root / "k", root / "c", 2);
    CHECK(b.value == 18);
    CHECK(b.from_cache == 0);
}

TEST_CASE("program cache: truncated, corrupt, misnamed and driver-refused entries are rejected and rebuilt", "[runtime][cache]") {
    const fs::path root = test::scratch_dir("program-cache-corrupt");
    write_kernels(root / "k", 4);
    REQUIRE(build_and_run(root / "k", root / "c", 1).value == 4);
    REQUIRE(entries(root / "c").size() == 1);
    const fs::path entry = entries(root / "c")[0];
    const std::string good = slurp(entry);
    REQUIRE(good.size() > 200);

    struct Damage {
        const char* name;
        std::string bytes;
    };
    std::string flipped = good;
    flipped[good.size() - 100] = char(flipped[good.size() - 100] ^ 0x5a);   // a byte of the binary
    std::string wrong_key = good;
    wrong_key[10] = char(wrong_key[10] ^ 1);                                   // a byte of the stored key
    std::string bad_magic = good;
    bad_magic[0] = 'X';
    const std::vector<Damage> damages = {{"truncated to half", good.substr(0, good.size() / 2)},
                                         {"truncated header", good.substr(0, 20)},
                                         {"one binary byte flipped", flipped},
                                         {"another key inside", wrong_key},
                                         {"bad magic", bad_magic},
                                         {"empty file", std::string()}};
    for (const Damage& d : damages) {
        INFO(d.name);
        spit(entry, d.bytes);
        check_rebuilt_then_cached(root, 1, 4);
    }
    SECTION("a well-formed entry whose binary the driver refuses") {
        const std::string key = entry.stem().string();
        REQUIRE(write_program_cache_entry((root / "c").string(), key, std::vector<unsigned char>(4096, 0xab)));
        check_rebuilt_then_cached(root, 1, 4);
    }
}

TEST_CASE("program cache: off writes nothing and loads nothing, and the folder follows the settings", "[runtime][cache]") {
    const fs::path root = test::scratch_dir("program-cache-off");
    write_kernels(root / "k", 3);
    Runtime rt(RuntimeOptions{"", -1, (root / "k").string(), "off"});
    CHECK(rt.program_cache_dir().empty());
    rt.build("shade.cl", {"SL_SCALE=1"});
    CHECK(rt.programs_from_cache() == 0);
    CHECK(!fs::exists(root / "c"));
    CHECK(program_cache_dir("0").empty());
    CHECK(program_cache_dir("/some/folder") == "/some/folder");
    CHECK(sha256_hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");   // FIPS 180-2 B.1
}
