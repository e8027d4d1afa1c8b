#include "core/csv.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/format.hpp"

namespace shadelab {

namespace {
void check_finite(double v, const std::vector<std::string>& columns, const std::vector<std::string>& row) {
    if (!std::isfinite(v))
        throw Error("internal: a non-finite number reached the CSV column '" +
                    (row.size() < columns.size() ? columns[row.size()] : std::string("?")) + "'");
}
}  // namespace

CsvTable& CsvTable::row() {
    rows_.emplace_back();
    return *this;
}

CsvTable& CsvTable::add(double v, int digits) {
    check_finite(v, columns_, rows_.back());
    rows_.back().push_back(num(v, digits));
    return *this;
}

CsvTable& CsvTable::add(const std::string& word) {
    std::string w = word;
    for (char& c : w)
        if (c == ',' || c == '\n' || c == '"') c = ';';
    rows_.back().push_back(w);
    return *this;
}

CsvTable& CsvTable::blank() {
    rows_.back().push_back("");
    return *this;
}

std::string CsvTable::text() const {
    std::ostringstream out;
    for (std::size_t c = 0; c < columns_.size(); ++c) out << (c ? "," : "") << columns_[c];
    out << "\n";
    for (const auto& r : rows_) {
        for (std::size_t c = 0; c < r.size(); ++c) out << (c ? "," : "") << r[c];
        out << "\n";
    }
    return out.str();
}

void CsvTable::write(const std::string& path) const {
    for (const auto& r : rows_)
        if (r.size() != columns_.size())
            throw Error("internal: CSV row with " + std::to_string(r.size()) + " fields for " +
                        std::to_string(columns_.size()) + " columns in '" + path + "'");
    write_text_atomically(path, "table", text());
}

CsvTable& CsvTable::add_fixed(double v, int decimals) {
    check_finite(v, columns_, rows_.back());
    rows_.back().push_back(fixed(v, decimals));
    return *this;
}

CsvTable& CsvTable::add_count(std::size_t v) {
    rows_.back().push_back(std::to_string(v));
    return *this;
}

CsvTable& CsvTable::add_quoted(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) {
        rows_.back().push_back(text);
        return *this;
    }
    std::string q = "\"";
    for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    rows_.back().push_back(q + "\"");
    return *this;
}

}  // namespace shadelab
