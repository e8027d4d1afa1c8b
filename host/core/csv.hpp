// CSV tables: the one CSV writer (moon, photometry tables, speed charts, fit atlas, view, batch reports).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace shadelab {

// A header line, then rows of numbers (or short words). Never writes NaN/Inf: a non-finite number
// is an internal error (callers write an empty field for "no value" with CsvRow::blank()).
class CsvTable {
public:
    explicit CsvTable(std::vector<std::string> columns) : columns_(std::move(columns)) {}
    CsvTable& row();                          // starts a new row
    CsvTable& add(double v, int digits = 9);  // throws on NaN/Inf
    CsvTable& add(const std::string& word);
    CsvTable& blank();
    CsvTable& add_fixed(double v, int decimals);     // exactly `decimals` after the point; throws on NaN/Inf
    CsvTable& add_count(std::size_t v);
    CsvTable& add_quoted(const std::string& text);    // any text, quoted as RFC 4180 says when it needs to be
    void write(const std::string& path) const;   // atomic; creates the folder
    std::string text() const;                     // what write() writes
    std::size_t rows() const { return rows_.size(); }

private:
    std::vector<std::string> columns_;
    std::vector<std::vector<std::string>> rows_;
};

}  // namespace shadelab
