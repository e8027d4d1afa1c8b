#include "photometry/csv.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "core/limits.hpp"
#include "core/text.hpp"

namespace shadelab::photometry {

namespace {

// Memory a row of the table costs while it is read, evaluated and written back: the row kept as text, its
// three angles, its value and its share of the output text, with the vectors' growth. Measured: a 41.5 MB
// table of 2,000,000 rows (`photometry eval --csv`) peaked 394 MB above the idle process, 197 bytes a row.
constexpr double kBytesPerRow = 200.0;
// Rows are counted after this many; the table's row count is then estimated from the file's size.
constexpr std::size_t kRowsToEstimate = 4096;

// Refuses a table whose rows, estimated from the first ones' length and the file's size, would not fit.
void check_table_memory(const std::string& path, std::ifstream& in, std::uintmax_t file_bytes, std::streamoff rows_start,
                        std::size_t rows) {
    const std::streamoff at = in.tellg();
    if (rows == 0 || rows_start < 0 || at <= rows_start) return;
    const double estimated_rows =
        double(file_bytes - std::uintmax_t(rows_start)) * double(rows) / double(at - rows_start);
    check_memory("the geometry table '" + path + "' (" + format_bytes(double(file_bytes)) + ", about " +
                     std::to_string(std::llround(estimated_rows)) + " rows)",
                 estimated_rows * kBytesPerRow);
}

std::string trim(std::string s) {
    s.erase(0, s.find_first_not_of(" \t\r"));
    s.erase(s.find_last_not_of(" \t\r") + 1);
    return s;
}

// A header name as written, without surrounding double quotes ("phase" -> phase).
std::string unquote(std::string s) {
    if (s.size() >= 2 && s.front() == '"' && s.back() == '"') return s.substr(1, s.size() - 2);
    return s;
}

}  // namespace

GeometryTable read_geometry_csv(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw Error(path + ": cannot open the geometry table");
    std::error_code size_error;
    const std::uintmax_t file_bytes = std::filesystem::file_size(path, size_error);
    // A line is read whole: a file of one endless line needs its size in memory, twice as the output is made.
    if (!size_error) check_memory("the geometry table '" + path + "'", 2.0 * double(file_bytes));
    GeometryTable t;
    std::string line;
    int lineno = 0;
    while (std::getline(in, line)) {
        ++lineno;
        if (!trim(line).empty()) break;
    }
    if (trim(line).empty()) throw Error(path + ": empty file: expected a header row with phase, incidence, emission");
    if (line.rfind("\xEF\xBB\xBF", 0) == 0) line = line.substr(3);   // UTF-8 byte-order mark
    for (auto& h : split(line, ',')) t.header.push_back(unquote(trim(h)));
    std::size_t col[3];
    const char* names[3] = {"phase", "incidence", "emission"};
    t.value_column = t.header.size();
    for (int c = 0; c < 3; ++c) {
        col[c] = t.header.size();
        for (std::size_t j = 0; j < t.header.size(); ++j)
            if (pvl::iequals(t.header[j], names[c])) col[c] = j;
        if (col[c] == t.header.size())
            throw Error(path + ":" + std::to_string(lineno) + ": the header has no column '" + names[c] +
                        "' (needed: phase, incidence, emission, in degrees)");
    }
    for (std::size_t j = 0; j < t.header.size(); ++j)
        if (pvl::iequals(t.header[j], "value")) t.value_column = j;
    // The fields are found by scanning for commas and the three angle fields parsed in place (millions of rows:
    // no per-field strings).
    const std::size_t need = std::max({col[0], col[1], col[2]});
    const std::streamoff rows_start = in.tellg();
    std::vector<std::pair<std::size_t, std::size_t>> spans;   // [begin, end) of each field
    while (std::getline(in, line)) {
        ++lineno;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.find_first_not_of(" \t") == std::string::npos) continue;
        spans.clear();
        std::size_t b = 0;
        while (true) {
            const std::size_t e = line.find(',', b);
            spans.push_back({b, e == std::string::npos ? line.size() : e});
            if (e == std::string::npos || spans.size() > need) break;
            b = e + 1;
        }
        const std::string where = path + ":" + std::to_string(lineno);
        Geometry g;
        double* dst[3] = {&g.phase, &g.incidence, &g.emission};
        for (int c = 0; c < 3; ++c) {
            if (col[c] >= spans.size())
                throw Error(where + ": the row has " + std::to_string(spans.size()) + " fields, no '" + names[c] + "'");
            const std::string s = trim(line.substr(spans[col[c]].first, spans[col[c]].second - spans[col[c]].first));
            char* end = nullptr;
            const double v = std::strtod(s.c_str(), &end);
            if (s.empty() || *end != '\0' || !std::isfinite(v))
                throw Error(where + ": " + names[c] + " '" + s + "' is not a finite number of degrees");
            *dst[c] = v;
        }
        check_geometry(g, where);
        t.geometry.push_back(g);
        t.rows.push_back(std::move(line));
        if (t.rows.size() == kRowsToEstimate && !size_error)
            check_table_memory(path, in, file_bytes, rows_start, t.rows.size());
    }
    return t;
}

void write_values_csv(const std::string& path, const GeometryTable& t, const std::vector<double>& values) {
    std::string out;
    out.reserve(t.rows.size() * 48 + 64);
    // the header, with `value` appended or in place
    for (std::size_t j = 0; j < std::max(t.header.size(), t.value_column + 1); ++j) {
        if (j) out += ',';
        out += j == t.value_column ? std::string("value") : t.header[j];
    }
    out += '\n';
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
        const std::string buf = num(values[r], 9);
        if (t.value_column >= t.header.size()) {   // appended: the line as it was, then the value
            out += t.rows[r];
            out += ',';
            out += buf;
        } else {   // an existing value column: its field replaced
            const std::vector<std::string> f = split(t.rows[r], ',');
            for (std::size_t j = 0; j < std::max(f.size(), t.value_column + 1); ++j) {
                if (j) out += ',';
                if (j == t.value_column) out += buf;
                else if (j < f.size()) out += f[j];
            }
        }
        out += '\n';
    }
    write_text_atomically(path, "table", out);
}

}  // namespace shadelab::photometry
