// Geometry tables in CSV for `shadelab photometry eval --csv`: a header row naming the columns (phase, incidence,
// emission in degrees, case-insensitive, in any order, among any others), one row per geometry. The output is the
// input with a `value` column appended (or overwritten where the input has one), every other column as it was.
#pragma once
#include <string>
#include <vector>

#include "photometry/isis.hpp"

namespace shadelab::photometry {

struct GeometryTable {
    std::vector<std::string> header;             // column names as written
    std::vector<std::string> rows;               // each data line as written (without its line end)
    std::vector<Geometry> geometry;              // per row
    std::size_t value_column = 0;                // where the value goes (header.size() when appended)
};

// Throws shadelab::Error naming the file, line and column: no header, a missing column, a field that is not a
// number, an angle outside [0, 180] degrees, a row with too few fields.
GeometryTable read_geometry_csv(const std::string& path);

// Writes the table with `values` in its value column (atomically). Values with 9 significant digits.
void write_values_csv(const std::string& path, const GeometryTable& t, const std::vector<double>& values);

}  // namespace shadelab::photometry
