// Structural checks of OBJ, PLY, OFF and STL files before OpenMesh reads them (see mesh_check.hpp).
#include "mesh/mesh_check.hpp"

#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "core/format.hpp"
#include "core/limits.hpp"

namespace fs = std::filesystem;

namespace shadelab {

namespace {

// Lines of a byte buffer, one at a time, with their 1-based number; '\r' before '\n' is dropped.
class Lines {
public:
    explicit Lines(std::string_view data, std::size_t from = 0) : d_(data), pos_(from) {}
    bool next(std::string_view& line) {
        if (pos_ >= d_.size()) return false;
        std::size_t end = d_.find('\n', pos_);
        const std::size_t stop = end == std::string_view::npos ? d_.size() : end;
        line = d_.substr(pos_, stop - pos_);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        pos_ = end == std::string_view::npos ? d_.size() : end + 1;
        ++number_;
        return true;
    }
    std::size_t number() const { return number_; }   // of the line last returned
    std::size_t offset() const { return pos_; }       // byte after it

private:
    std::string_view d_;
    std::size_t pos_;
    std::size_t number_ = 0;
};

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

// Whitespace-separated words of a line.
std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> w;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && is_space(line[i])) ++i;
        const std::size_t s = i;
        while (i < line.size() && !is_space(line[i])) ++i;
        if (i > s) w.push_back(line.substr(s, i - s));
    }
    return w;
}

// The whole word as a number (strtod's grammar), or false.
bool number(std::string_view w, double& v) {
    if (w.empty() || w.size() > 64) return false;
    char buf[65];
    std::memcpy(buf, w.data(), w.size());
    buf[w.size()] = '\0';
    char* end = nullptr;
    v = std::strtod(buf, &end);
    return end == buf + w.size();
}

// The whole word as a decimal integer, or false.
bool integer(std::string_view w, long long& v) {
    if (w.empty() || w.size() > 24) return false;
    char buf[25];
    std::memcpy(buf, w.data(), w.size());
    buf[w.size()] = '\0';
    char* end = nullptr;
    errno = 0;
    v = std::strtoll(buf, &end, 10);
    return end == buf + w.size() && errno == 0;
}

std::string quoted(std::string_view w) {
    std::string s(w.substr(0, 40));
    for (char& c : s)
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
    return "'" + s + (w.size() > 40 ? "...'" : "'");
}

class Checker {
public:
    Checker(const std::string& name, const std::string& format) : name_(name), format_(format) {}
    [[noreturn]] void fail_line(std::size_t line, const std::string& what, const std::string& todo = "") const {
        throw Error("mesh '" + name_ + "' line " + std::to_string(line) + ": " + what + ": " +
                    (todo.empty() ? "fix the file or re-export it as " + format_ : todo));
    }
    [[noreturn]] void fail(const std::string& what, const std::string& todo = "") const {
        throw Error("mesh '" + name_ + "': " + what + ": " + (todo.empty() ? "fix the file or re-export it as " + format_ : todo));
    }

private:
    std::string name_, format_;
};

// ---- OBJ ---------------------------------------------------------------------------------------------
// OpenMesh reads 'v', 'vt', 'vn' and 'f' (and follows 'mtllib'); it asserts on a face corner without a
// vertex index and uses the corner's vertex, texture-coordinate and normal numbers unchecked, so every
// index must name an element defined above it.
void check_obj(std::string_view d, const Checker& c) {
    Lines lines(d);
    std::string_view line;
    std::size_t v = 0, vt = 0, vn = 0;
    // A 1-based or negative (relative) index: true when it names one of the `count` seen so far.
    auto resolves = [](long long i, std::size_t count) {
        return (i > 0 && std::uint64_t(i) <= count) || (i < 0 && std::uint64_t(-(i + 1)) < count);
    };
    while (lines.next(line)) {
        const auto w = words(line);
        if (w.empty() || w[0][0] == '#') continue;
        const std::string_view kw = w[0];
        if (kw == "v" || kw == "vn" || kw == "vt") {
            const std::size_t need = kw == "vt" ? 1 : 3;
            if (w.size() < need + 1)
                c.fail_line(lines.number(), "'" + std::string(kw) + "' needs " + std::to_string(need) + " numbers, has " +
                                                std::to_string(w.size() - 1));
            // Coordinates are validated (NaN, range) by load_mesh's own scan; here only their grammar.
            for (std::size_t k = 1; k <= need; ++k) {
                double x;
                if (!number(w[k], x)) c.fail_line(lines.number(), quoted(w[k]) + " is not a number");
            }
            (kw == "v" ? v : kw == "vn" ? vn : vt) += 1;
        } else if (kw == "f") {
            if (w.size() > 1 + 100000) c.fail_line(lines.number(), "a face with more than 100000 corners");
            for (std::size_t k = 1; k < w.size(); ++k) {
                const std::string_view corner = w[k];
                std::string_view part[3];
                std::size_t parts = 0, s = 0;
                for (std::size_t i = 0; i <= corner.size(); ++i)
                    if (i == corner.size() || corner[i] == '/') {
                        if (parts == 3) c.fail_line(lines.number(), "face corner " + quoted(corner) + " has more than two '/'");
                        part[parts++] = corner.substr(s, i - s);
                        s = i + 1;
                    }
                long long idx = 0;
                if (part[0].empty() || !integer(part[0], idx) || idx == 0)
                    c.fail_line(lines.number(), "face corner " + quoted(corner) + " has no vertex index (a corner is v, v/t, v//n or v/t/n)");
                const char* names[3] = {"vertex", "texture coordinate", "normal"};
                const std::size_t counts[3] = {v, vt, vn};
                // Vertex indices too: OpenMesh sets a corner's normal on the vertex it names before it
                // checks that the vertex exists (a heap use-after-free found by fuzz/fuzz_mesh).
                for (std::size_t p = 0; p < parts; ++p) {
                    if (part[p].empty()) continue;
                    if (!integer(part[p], idx) || !resolves(idx, counts[p]))
                        c.fail_line(lines.number(), "face corner " + quoted(corner) + " names " + names[p] + " " +
                                                        std::string(part[p]) + ", but only " + std::to_string(counts[p]) +
                                                        " are defined above it");
                }
            }
        }
    }
}

// ---- PLY ---------------------------------------------------------------------------------------------
struct PlyProperty {
    std::string name;
    bool list = false;
    int count_type = 0;   // list: index into kPlyTypes of the count
    int type = 0;         // index into kPlyTypes of the value (or the list's items)
};
struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::size_t line = 0;
    std::vector<PlyProperty> properties;
};

struct PlyType {
    const char* name;
    int bytes;
    bool integral;
    double lo, hi;
};
const PlyType kPlyTypes[] = {
    {"char", 1, true, -128, 127},           {"int8", 1, true, -128, 127},
    {"uchar", 1, true, 0, 255},             {"uint8", 1, true, 0, 255},
    {"short", 2, true, -32768, 32767},      {"int16", 2, true, -32768, 32767},
    {"ushort", 2, true, 0, 65535},          {"uint16", 2, true, 0, 65535},
    {"int", 4, true, -2147483648.0, 2147483647.0}, {"int32", 4, true, -2147483648.0, 2147483647.0},
    {"uint", 4, true, 0, 4294967295.0},     {"uint32", 4, true, 0, 4294967295.0},
    {"float", 4, false, -FLT_MAX, FLT_MAX}, {"float32", 4, false, -FLT_MAX, FLT_MAX},
    {"double", 8, false, -DBL_MAX, DBL_MAX}, {"float64", 8, false, -DBL_MAX, DBL_MAX},
};

int ply_type(std::string_view w) {
    for (int i = 0; i < int(std::size(kPlyTypes)); ++i)
        if (w == kPlyTypes[i].name) return i;
    return -1;
}

// A binary value of type t at p, as a double (the PLY types are at most 8 bytes).
double ply_binary_value(const unsigned char* p, int t, bool big_endian) {
    unsigned char b[8];
    const int n = kPlyTypes[t].bytes;
    for (int i = 0; i < n; ++i) b[i] = big_endian ? p[n - 1 - i] : p[i];
    const std::string name = kPlyTypes[t].name;
    auto as = [&b](auto x) {
        std::memcpy(&x, b, sizeof x);
        return double(x);
    };
    if (name == "char" || name == "int8") return as(std::int8_t());
    if (name == "uchar" || name == "uint8") return as(std::uint8_t());
    if (name == "short" || name == "int16") return as(std::int16_t());
    if (name == "ushort" || name == "uint16") return as(std::uint16_t());
    if (name == "int" || name == "int32") return as(std::int32_t());
    if (name == "uint" || name == "uint32") return as(std::uint32_t());
    if (name == "float" || name == "float32") return as(float());
    return as(double());
}

// The header, line by line up to 'end_header': the format and every element with its properties.
struct PlyHeader {
    std::string format;
    std::vector<PlyElement> elements;
};

// One 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME' line (words w) of line n.
PlyProperty ply_property(const std::vector<std::string_view>& w, std::string_view line, std::size_t n, const Checker& c) {
    PlyProperty p;
    if (w.size() == 5 && w[1] == "list") {
        p.list = true;
        p.count_type = ply_type(w[2]);
        p.type = ply_type(w[3]);
        p.name = std::string(w[4]);
        if (p.count_type < 0 || p.type < 0) c.fail_line(n, "unknown type in " + quoted(line));
        if (!kPlyTypes[p.count_type].integral) c.fail_line(n, "a list's count must have an integer type");
    } else if (w.size() == 3) {
        p.type = ply_type(w[1]);
        p.name = std::string(w[2]);
        if (p.type < 0) c.fail_line(n, "unknown property type " + quoted(w[1]) + " (char, uchar, short, ushort, int, uint, float, double)");
    } else {
        c.fail_line(n, "expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME'");
    }
    return p;
}

PlyHeader read_ply_header(Lines& lines, const Checker& c) {
    std::string_view line;
    if (!lines.next(line) || line != "ply") c.fail_line(1, "a PLY file starts with the line 'ply'", "is it really a PLY file?");
    PlyHeader h;
    std::vector<PlyElement>& elements = h.elements;
    bool ended = false;
    while (!ended && lines.next(line)) {
        const std::size_t n = lines.number();
        const auto w = words(line);
        if (w.empty()) continue;
        const std::string_view kw = w[0];
        if (kw == "comment" || kw == "obj_info") continue;
        if (kw == "format") {
            if (!h.format.empty()) c.fail_line(n, "a second 'format' line");
            if (w.size() != 3 || (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian"))
                c.fail_line(n, "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
            if (w[2] != "1.0" && w[2] != "1") c.fail_line(n, "PLY version " + quoted(w[2]) + ": only 1.0 exists");
            h.format = std::string(w[1]);
        } else if (kw == "element") {
            long long count = -1;
            if (w.size() != 3 || !integer(w[2], count) || count < 0)
                c.fail_line(n, "expected 'element NAME COUNT' with a count >= 0");
            for (const auto& e : elements)
                if (e.name == w[1]) c.fail_line(n, "element '" + e.name + "' is declared twice");
            elements.push_back({std::string(w[1]), std::uint64_t(count), n, {}});
        } else if (kw == "property") {
            if (elements.empty()) c.fail_line(n, "'property' before any 'element'");
            const PlyProperty p = ply_property(w, line, n, c);
            for (const auto& q : elements.back().properties)
                if (q.name == p.name) c.fail_line(n, "property '" + p.name + "' is declared twice in element '" + elements.back().name + "'");
            elements.back().properties.push_back(p);
        } else if (kw == "end_header") {
            if (w.size() != 1) c.fail_line(n, "'end_header' must be alone on its line");
            ended = true;
        } else {
            c.fail_line(n, quoted(kw) + " is not a PLY header keyword (format, element, property, comment, obj_info, end_header)");
        }
    }
    if (!ended) c.fail("the PLY header has no 'end_header' line: the file is truncated or not PLY", "re-export it");
    if (h.format.empty()) c.fail("the PLY header has no 'format' line");
    return h;
}

// What OpenMesh reads: a vertex element with scalar x, y, z; a face element with a list of integer
// vertex indices. Other elements and properties are skipped by it (and walked here). Returns the vertex element.
const PlyElement& ply_vertex_element(const std::vector<PlyElement>& elements, const Checker& c) {
    const PlyElement* vertex = nullptr;
    for (const auto& e : elements) {
        if (e.count > 0 && e.properties.empty()) c.fail_line(e.line, "element '" + e.name + "' has no properties");
        if (e.name == "vertex") {
            vertex = &e;
            for (const char* axis : {"x", "y", "z"}) {
                bool found = false;
                for (const auto& p : e.properties) found = found || (p.name == axis && !p.list);
                if (!found) c.fail_line(e.line, "the vertex element has no scalar property '" + std::string(axis) + "'");
            }
            for (const auto& p : e.properties)
                if (p.list) c.fail_line(e.line, "the vertex element has a list property ('" + p.name + "'): not read");
        }
        if (e.name == "face") {
            if (!vertex) c.fail_line(e.line, "the face element comes before the vertex element");
            for (const auto& p : e.properties)
                if ((p.name == "vertex_indices" || p.name == "vertex_index") && (!p.list || !kPlyTypes[p.type].integral))
                    c.fail_line(e.line, "face property '" + p.name + "' must be a list of integers");
        }
    }
    if (!vertex) c.fail("the PLY header declares no 'element vertex'");
    return *vertex;
}

// The body: every element's items in order, each bounded by the bytes left.
class PlyBody {
public:
    PlyBody(std::string_view d, const Checker& c, const std::string& format, std::size_t body, std::size_t line_no,
            const PlyElement& vertex)
        : d_(d), c_(c), ascii_(format == "ascii"), big_(format == "binary_big_endian"), pos_(body), line_no_(line_no),
          vertex_(vertex), nvertices_(double(vertex.count)) {}

    void walk(const PlyElement& e) {
        const bool faces = e.name == "face";
        for (std::uint64_t i = 0; i < e.count; ++i) {
            for (const auto& p : e.properties) {
                const bool indices = faces && p.list && (p.name == "vertex_indices" || p.name == "vertex_index");
                double count = 1;
                if (p.list) {
                    count = list_length(e, p, i);
                    if (indices && count < 3)
                        c_.fail("face " + std::to_string(i) + " has " + std::to_string(long(count)) + " vertices: a face needs at least 3");
                }
                for (double k = 0; k < count; ++k) {
                    const double v = ascii_ ? ascii_value(e, p, i) : binary_value(e, p, i, indices);
                    if (indices && !(v >= 0 && v < nvertices_))
                        c_.fail("face " + std::to_string(i) + " names vertex " + num(v, 17) + ", but the file has " +
                                std::to_string(vertex_.count) + " vertices");
                }
            }
        }
    }

private:
    // ASCII: the next whitespace-separated word, counting the lines it passes (for messages).
    bool next_word(std::string_view& w) {
        while (pos_ < d_.size() && is_space(d_[pos_])) {
            if (d_[pos_] == '\n') ++line_no_;
            ++pos_;
        }
        const std::size_t s = pos_;
        while (pos_ < d_.size() && !is_space(d_[pos_])) ++pos_;
        w = d_.substr(s, pos_ - s);
        return pos_ > s;
    }

    [[noreturn]] void truncated(const PlyElement& e, std::uint64_t item) const {
        c_.fail("the file ends after " + std::to_string(item) + " of the " + std::to_string(e.count) + " '" + e.name +
                    "' items its header declares: it is truncated",
                "re-export it");
    }

    double list_length(const PlyElement& e, const PlyProperty& p, std::uint64_t i) {
        if (ascii_) {
            std::string_view w;
            long long k;
            if (!next_word(w)) truncated(e, i);
            if (!integer(w, k) || k < 0 || double(k) > kPlyTypes[p.count_type].hi)
                c_.fail_line(line_no_, "'" + e.name + "' item " + std::to_string(i) + ": list length " + quoted(w) +
                                           " is not a count of type " + kPlyTypes[p.count_type].name);
            return double(k);
        }
        if (d_.size() - pos_ < std::size_t(kPlyTypes[p.count_type].bytes)) truncated(e, i);
        const double count = ply_binary_value(reinterpret_cast<const unsigned char*>(d_.data()) + pos_, p.count_type, big_);
        pos_ += std::size_t(kPlyTypes[p.count_type].bytes);
        if (count < 0) c_.fail("'" + e.name + "' item " + std::to_string(i) + " has a negative list length");
        return count;
    }

    double ascii_value(const PlyElement& e, const PlyProperty& p, std::uint64_t i) {
        double v = 0;
        std::string_view w;
        if (!next_word(w)) truncated(e, i);
        bool ok = number(w, v);
        if (ok && kPlyTypes[p.type].integral) {
            long long iv;
            ok = integer(w, iv) && double(iv) >= kPlyTypes[p.type].lo && double(iv) <= kPlyTypes[p.type].hi;
        }
        // NaN/Inf are load_mesh's to name (with their line); a finite value beyond the
        // type's range would become Inf (float) or wrap (integers) inside OpenMesh.
        if (!ok && !(number(w, v) && !std::isfinite(v)))
            c_.fail_line(line_no_, "'" + e.name + "' item " + std::to_string(i) + ", property '" + p.name +
                                       "': " + quoted(w) + " is not a " + kPlyTypes[p.type].name +
                                       (kPlyTypes[p.type].integral ? "" : " (or is beyond its range)"));
        if (ok && std::isfinite(v) && (v < kPlyTypes[p.type].lo || v > kPlyTypes[p.type].hi))
            c_.fail_line(line_no_, "'" + e.name + "' item " + std::to_string(i) + ", property '" + p.name +
                                       "': " + quoted(w) + " is beyond the range of a " + kPlyTypes[p.type].name);
        return v;
    }

    // Binary: skips the value; reads it only for face indices (0 otherwise).
    double binary_value(const PlyElement& e, const PlyProperty& p, std::uint64_t i, bool indices) {
        double v = 0;
        const std::size_t b = std::size_t(kPlyTypes[p.type].bytes);
        if (d_.size() - pos_ < b) truncated(e, i);
        if (indices) v = ply_binary_value(reinterpret_cast<const unsigned char*>(d_.data()) + pos_, p.type, big_);
        pos_ += b;
        return v;
    }

    std::string_view d_;
    const Checker& c_;
    bool ascii_, big_;
    std::size_t pos_;
    std::size_t line_no_;   // ASCII: line of the next word (for messages)
    const PlyElement& vertex_;
    double nvertices_;
};

void check_ply(std::string_view d, const Checker& c) {
    Lines lines(d);
    const PlyHeader header = read_ply_header(lines, c);
    const PlyElement& vertex = ply_vertex_element(header.elements, c);
    PlyBody body(d, c, header.format, lines.offset(), lines.number() + 1, vertex);
    for (const auto& e : header.elements) body.walk(e);
}

// ---- OFF ---------------------------------------------------------------------------------------------
// [ST][C][N]OFF, counts (nv nf ne) on the next line, nv vertex lines, nf face lines "n i1 .. in [colour]".
// 4OFF/nOFF (other dimensions) and binary OFF are refused: OpenMesh's readers of those are not worth the risk
// for formats no exporter writes. Counts on the keyword's line are refused too: OpenMesh 9 skips that line
// whole and reads its counts from the next one, so such a file came back as another mesh, as "no triangles"
// or, with nothing after it, as counts read from nowhere (a 12 GB allocation; found by fuzz_mesh).
void check_off(std::string_view d, const Checker& c) {
    Lines lines(d);
    std::string_view line;
    std::vector<std::string_view> w;
    // The next line that is not blank and not a comment, split into words.
    auto next_data = [&]() {
        while (lines.next(line)) {
            w = words(line);
            if (!w.empty() && w[0][0] != '#') return true;
        }
        return false;
    };
    if (!next_data()) c.fail("the file holds only comments");
    const std::string_view kw = w[0];
    if (kw.size() >= 3 && kw.substr(kw.size() - 3) == "OFF") {
        std::string_view prefix = kw.substr(0, kw.size() - 3);
        if (prefix.substr(0, 2) == "ST") prefix.remove_prefix(2);
        if (!prefix.empty() && prefix[0] == 'C') prefix.remove_prefix(1);
        if (!prefix.empty() && prefix[0] == 'N') prefix.remove_prefix(1);
        if (!prefix.empty())
            c.fail_line(lines.number(), "OFF variant " + quoted(kw) + " is not read (OFF, COFF, NOFF, CNOFF, STOFF...)");
        if (w.size() > 1 && w[1] == "BINARY")
            c.fail_line(lines.number(), "binary OFF is not read", "convert it to ASCII OFF, PLY or OBJ");
        if (w.size() > 1 && w[1][0] != '#')
            c.fail_line(lines.number(), "the counts are on the " + std::string(kw) + " line, where OpenMesh does not read them",
                        "put 'vertices faces edges' on the line after " + std::string(kw));
    } else {
        c.fail_line(lines.number(), "an OFF file starts with the keyword OFF (or COFF, NOFF, ...), not " + quoted(kw));
    }
    // the counts are on a line of their own
    if (!next_data()) c.fail("the file ends before its vertex and face counts");
    long long nv = -1, nf = -1;
    if (w.size() < 2 || !integer(w[0], nv) || !integer(w[1], nf) || nv < 0 || nf < 0)
        c.fail_line(lines.number(), "expected the counts 'vertices faces edges', got " + quoted(line));
    for (long long i = 0; i < nv; ++i) {
        if (!next_data())
            c.fail("the file ends after " + std::to_string(i) + " of its " + std::to_string(nv) + " vertices: it is truncated", "re-export it");
        if (w.size() < 3) c.fail_line(lines.number(), "vertex " + std::to_string(i) + " has fewer than 3 coordinates");
        for (const auto& x : w) {
            double v;
            if (!number(x, v)) c.fail_line(lines.number(), "vertex " + std::to_string(i) + ": " + quoted(x) + " is not a number");
        }
    }
    for (long long i = 0; i < nf; ++i) {
        if (!next_data())
            c.fail("the file ends after " + std::to_string(i) + " of its " + std::to_string(nf) + " faces: it is truncated", "re-export it");
        long long n = 0;
        if (!integer(w[0], n) || n < 3)
            c.fail_line(lines.number(), "face " + std::to_string(i) + ": " + quoted(w[0]) + " is not a vertex count >= 3");
        if (std::uint64_t(n) > w.size() - 1)
            c.fail_line(lines.number(), "face " + std::to_string(i) + " says " + std::to_string(n) + " vertices but lists " +
                                            std::to_string(w.size() - 1) + " numbers");
        for (long long k = 1; k <= n; ++k) {
            long long idx = -1;
            if (!integer(w[std::size_t(k)], idx) || idx < 0 || idx >= nv)
                c.fail_line(lines.number(), "face " + std::to_string(i) + " names vertex " + quoted(w[std::size_t(k)]) +
                                                ", but the file has " + std::to_string(nv) + " vertices (0-based)");
        }
        for (std::size_t k = std::size_t(n) + 1; k < w.size(); ++k) {
            double v;
            if (!number(w[k], v)) c.fail_line(lines.number(), "face " + std::to_string(i) + ": " + quoted(w[k]) + " is not a number");
        }
    }
}

// ---- STL ---------------------------------------------------------------------------------------------
// Binary: 80-byte header, facet count n, n 50-byte facets -- the size must say so exactly. Otherwise
// ASCII: solid / facet normal / outer loop / 3 x vertex / endloop / endfacet ... endsolid.
void check_stl(std::string_view d, const Checker& c) {
    if (d.size() >= 84) {
        const auto* b = reinterpret_cast<const unsigned char*>(d.data()) + 80;
        const std::uint64_t n = std::uint64_t(b[0]) | std::uint64_t(b[1]) << 8 | std::uint64_t(b[2]) << 16 | std::uint64_t(b[3]) << 24;
        if (d.size() == 84 + 50 * n) return;   // binary, complete
    }
    Lines lines(d);
    std::string_view line;
    std::vector<std::string_view> w;
    auto next_data = [&]() {
        while (lines.next(line)) {
            w = words(line);
            if (!w.empty()) return true;
        }
        return false;
    };
    if (!next_data() || w[0] != "solid") {
        std::string why = "not an ASCII STL (which starts with 'solid')";
        if (d.size() >= 84) {
            const auto* b = reinterpret_cast<const unsigned char*>(d.data()) + 80;
            const std::uint64_t n = std::uint64_t(b[0]) | std::uint64_t(b[1]) << 8 | std::uint64_t(b[2]) << 16 | std::uint64_t(b[3]) << 24;
            why += " and not a complete binary STL (its header says " + std::to_string(n) + " facets, which take " +
                   std::to_string(84 + 50 * n) + " bytes; the file has " + std::to_string(d.size()) + ")";
        }
        c.fail(why, "re-export it");
    }
    std::size_t facets = 0;
    auto expect = [&](const char* a, const char* b, std::size_t numbers) {
        if (!next_data())
            c.fail("the file ends inside facet " + std::to_string(facets + 1) + " (no '" + a + (b ? std::string(" ") + b : "") +
                       "'): it is truncated",
                   "re-export it");
        const std::size_t head = b ? 2 : 1;
        if (w[0] != a || (b && (w.size() < 2 || w[1] != b)) || w.size() != head + numbers)
            c.fail_line(lines.number(), "expected '" + std::string(a) + (b ? std::string(" ") + b : "") +
                                            (numbers ? " x y z" : "") + "' in facet " + std::to_string(facets + 1) +
                                            ", got " + quoted(line));
        for (std::size_t k = head; k < w.size(); ++k) {
            double v;
            if (!number(w[k], v)) c.fail_line(lines.number(), quoted(w[k]) + " is not a number");
        }
    };
    while (true) {
        if (!next_data())
            c.fail("the file ends after " + std::to_string(facets) + " facets without 'endsolid': it is truncated", "re-export it");
        if (w[0] == "endsolid") break;
        if (w[0] != "facet" || w.size() != 5 || w[1] != "normal")
            c.fail_line(lines.number(), "expected 'facet normal x y z' or 'endsolid', got " + quoted(line));
        for (std::size_t k = 2; k < 5; ++k) {
            double v;
            if (!number(w[k], v)) c.fail_line(lines.number(), quoted(w[k]) + " is not a number");
        }
        expect("outer", "loop", 0);
        for (int k = 0; k < 3; ++k) expect("vertex", nullptr, 3);
        expect("endloop", nullptr, 0);
        expect("endfacet", nullptr, 0);
        ++facets;
    }
}

}  // namespace

void check_mesh_bytes(const std::string& bytes, const std::string& ext, const std::string& name) {
    const std::string_view d(bytes);
    if (ext == ".obj") check_obj(d, Checker(name, "OBJ"));
    else if (ext == ".ply") check_ply(d, Checker(name, "PLY"));
    else if (ext == ".off") check_off(d, Checker(name, "OFF"));
    else if (ext == ".stl") check_stl(d, Checker(name, "STL"));
    else throw Error("mesh '" + name + "' has an unsupported format '" + ext + "': use .obj, .off, .ply or .stl");
}

std::string check_mesh_opens(const std::string& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw Error("mesh file '" + path + "' not found: check the path");
    if (fs::is_directory(path, ec)) throw Error("mesh path '" + path + "' is a folder: give a mesh file");
    const std::string ext = lower_ext(path);
    if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl")
        throw Error("mesh '" + path + "' has an unsupported format '" + ext + "': use .obj, .off, .ply or .stl");
    if (fs::file_size(path, ec) == 0) throw Error("mesh file '" + path + "' is empty: nothing to shade");
    if (!std::ifstream(path)) throw Error("mesh file '" + path + "' cannot be opened: check its read permission");
    return ext;
}

void check_mesh_file(const std::string& path, const std::string& ext) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw Error("mesh file '" + path + "' cannot be opened: check its read permission");
    const std::streamoff size = in.tellg();
    // The file is read whole for the check; OpenMesh then builds a mesh several times its size.
    check_memory("mesh '" + path + "' (" + format_bytes(double(size)) + ")", 4.0 * double(size));
    std::string bytes(std::size_t(size), '\0');
    in.seekg(0);
    if (!in.read(bytes.data(), size)) throw Error("mesh file '" + path + "' could not be read to its end: is it being written?");
    check_mesh_bytes(bytes, ext, path);
}

}  // namespace shadelab
