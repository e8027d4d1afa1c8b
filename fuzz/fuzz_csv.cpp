// libFuzzer target: geometry tables for `photometry eval --csv` (header row, any column order, quoted names, a
// byte-order mark, CRLF, blank lines), and the values table written back from them. Every row accepted must
// hold three finite angles in [0, 180] degrees, and the table written back must have one line per row plus
// the header.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <iterator>

#include "core/error.hpp"
#include "fuzz_common.hpp"
#include "photometry/csv.hpp"

namespace {
bool angle_ok(double a) { return std::isfinite(a) && a >= 0.0 && a <= 180.0; }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace shadelab::photometry;
    const auto table = shadelab::fuzz::load_input(data, size, "geometry.csv", read_geometry_csv);
    if (!table) return 0;
    const GeometryTable& t = *table;
    if (t.rows.size() != t.geometry.size() || t.value_column > t.header.size()) __builtin_trap();
    for (const Geometry& g : t.geometry)
        if (!angle_ok(g.phase) || !angle_ok(g.incidence) || !angle_ok(g.emission)) __builtin_trap();
    const std::string out = shadelab::fuzz::scratch_path("values.csv");
    try {
        write_values_csv(out, t, std::vector<double>(t.rows.size(), 0.25));
    } catch (const shadelab::Error&) {
        return 0;   // a write failure is reported, not a crash
    }
    std::ifstream in(out, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::size_t lines = 0;
    for (char ch : text) lines += ch == '\n';
    if (lines != t.rows.size() + 1) __builtin_trap();
    return 0;
}
