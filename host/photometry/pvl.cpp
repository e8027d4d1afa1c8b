#include "photometry/pvl.hpp"

#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.hpp"

namespace shadelab::pvl {

bool iequals(const std::string& a, const std::string& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i])))
            return false;
    return true;
}

const Keyword* Block::keyword(const std::string& n) const {
    for (const auto& k : keywords)
        if (iequals(k.name, n)) return &k;
    return nullptr;
}

const Block* Block::block(const std::string& k, const std::string& n) const {
    for (const auto& b : blocks)
        if (iequals(b.kind, k) && iequals(b.name, n)) return &b;
    return nullptr;
}

const Block* Block::find(const std::string& k, const std::string& n) const {
    for (const auto& b : blocks) {
        if (iequals(b.kind, k) && iequals(b.name, n)) return &b;
        if (const Block* inner = b.find(k, n)) return inner;
    }
    return nullptr;
}

namespace {

// A cursor over the text with the line number, skipping blanks and comments.
class Lexer {
public:
    Lexer(const std::string& text, const std::string& file) : s_(text), file_(file) {}

    [[noreturn]] void fail(const std::string& what) const { fail_at(line_, what); }
    [[noreturn]] void fail_at(int line, const std::string& what) const {
        throw Error(file_ + ":" + std::to_string(line) + ": " + what);
    }
    int line() const { return line_; }
    bool at_end() {
        skip();
        return i_ >= s_.size();
    }
    char peek() {
        skip();
        return i_ < s_.size() ? s_[i_] : '\0';
    }
    void expect(char c, const std::string& context) {
        if (peek() != c) fail(std::string("expected '") + c + "' " + context);
        ++i_;
    }
    // A bare word: letters, digits and _ . + - : / (PVL identifiers, numbers, dates).
    std::string word() {
        skip();
        const std::size_t start = i_;
        while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || std::string("_.+-:/").find(s_[i_]) != std::string::npos) &&
               !(s_[i_] == '/' && i_ + 1 < s_.size() && s_[i_ + 1] == '*'))
            ++i_;
        return s_.substr(start, i_ - start);
    }
    // A quoted string starting at the current quote; ISIS's line continuation: "-" + newline + indent removed,
    // other newlines with their indent become nothing (ISIS wraps long strings at arbitrary characters).
    std::string quoted() {
        skip();
        const char q = s_[i_++];
        std::string out;
        while (true) {
            if (i_ >= s_.size()) fail(std::string("unterminated quoted string (missing ") + q + ")");
            const char c = s_[i_++];
            if (c == q) break;
            if (c == '\n' || c == '\r') {
                if (c == '\n') ++line_;
                if (c == '\r' && i_ < s_.size() && s_[i_] == '\n') { ++i_; ++line_; }
                if (!out.empty() && out.back() == '-') out.pop_back();
                while (!out.empty() && (out.back() == ' ' || out.back() == '\t')) out.pop_back();
                while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t')) ++i_;
                continue;
            }
            out += c;
        }
        return out;
    }
    // Drops a unit "<...>" if one follows.
    void skip_unit() {
        if (peek() != '<') return;
        while (i_ < s_.size() && s_[i_] != '>') {
            if (s_[i_] == '\n') fail("unterminated unit '<...'");
            ++i_;
        }
        if (i_ >= s_.size()) fail("unterminated unit '<...'");
        ++i_;
    }
    // True if the rest of the current line holds nothing but blanks or a comment.
    bool line_ends() {
        std::size_t j = i_;
        while (j < s_.size() && (s_[j] == ' ' || s_[j] == '\t' || s_[j] == '\r')) ++j;
        return j >= s_.size() || s_[j] == '\n' || (s_[j] == '/' && j + 1 < s_.size() && s_[j + 1] == '*') ||
               s_[j] == '#';
    }

private:
    void skip() {
        while (i_ < s_.size()) {
            const char c = s_[i_];
            if (c == '\n') { ++line_; ++i_; }
            else if (c == ' ' || c == '\t' || c == '\r' || c == '\f') ++i_;
            else if (c == '/' && i_ + 1 < s_.size() && s_[i_ + 1] == '*') {
                const std::size_t end = s_.find("*/", i_ + 2);
                if (end == std::string::npos) fail("unterminated comment '/*'");
                for (std::size_t j = i_; j < end; ++j) line_ += s_[j] == '\n' ? 1 : 0;
                i_ = end + 2;
            } else if (c == '#') {
                while (i_ < s_.size() && s_[i_] != '\n') ++i_;
            } else break;
        }
    }

    const std::string& s_;
    std::string file_;
    std::size_t i_ = 0;
    int line_ = 1;
};

std::string scalar(Lexer& lx, bool& quoted) {
    const char c = lx.peek();
    quoted = c == '"' || c == '\'';
    std::string v = quoted ? lx.quoted() : lx.word();
    if (!quoted && v.empty()) lx.fail(std::string("expected a value, found '") + (c ? std::string(1, c) : "end of file") + "'");
    lx.skip_unit();
    return v;
}

void parse_value(Lexer& lx, Keyword& k) {
    const char c = lx.peek();
    if (c == '(' || c == '{') {
        const char close = c == '(' ? ')' : '}';
        lx.expect(c, "");
        k.list = true;
        if (lx.peek() == close) { lx.expect(close, ""); return; }
        while (true) {
            bool q = false;
            if (lx.peek() == '(' || lx.peek() == '{') lx.fail("nested lists are not supported (keyword '" + k.name + "')");
            k.values.push_back(scalar(lx, q));
            if (lx.peek() == ',') { lx.expect(',', ""); continue; }
            if (lx.peek() == close) { lx.expect(close, ""); break; }
            lx.fail(std::string("expected ',' or '") + close + "' in the list of keyword '" + k.name + "'");
        }
        lx.skip_unit();
        return;
    }
    bool q = false;
    k.values.push_back(scalar(lx, q));
    k.quoted = q;
}

// ISIS parameter files nest two or three levels (Object PhotometricModel > Group Algorithm); the limit keeps a
// hostile file from recursing until the stack overflows (a fuzz finding: 200000 nested 'Object = a').
constexpr int kMaxDepth = 32;
// A parameter file is a few hundred bytes; the cap keeps a wrong path (an image, a cube) from being read whole.
constexpr std::uintmax_t kMaxFileBytes = 16u << 20;

// Parses statements into `b` until the block's end statement (or the file's end for the root).
void parse_block(Lexer& lx, Block& b, bool root, int depth) {
    if (depth > kMaxDepth)
        lx.fail_at(b.line, b.kind + " '" + b.name + "' is nested " + std::to_string(depth) + " levels deep, more than the " +
                std::to_string(kMaxDepth) + " a parameter file may use: check the End_Object/End_Group lines");
    while (true) {
        if (lx.at_end()) {
            if (root) return;
            lx.fail(b.kind + " '" + b.name + "' (line " + std::to_string(b.line) + ") has no End_" + b.kind);
        }
        const int line = lx.line();
        const std::string w = lx.word();
        if (w.empty()) lx.fail(std::string("expected a keyword, found '") + lx.peek() + "'");
        if (iequals(w, "End")) {
            if (!root) lx.fail("'End' inside " + b.kind + " '" + b.name + "' (line " + std::to_string(b.line) + "): missing End_" + b.kind);
            return;
        }
        if (iequals(w, "End_Object") || iequals(w, "End_Group")) {
            const std::string kind = iequals(w, "End_Object") ? "Object" : "Group";
            if (root || !iequals(kind, b.kind))
                lx.fail("'" + w + "' does not close anything open here" +
                        (root ? std::string() : " (open: " + b.kind + " '" + b.name + "')"));
            if (!lx.line_ends() && lx.peek() == '=') {   // End_Group = Algorithm
                lx.expect('=', "");
                const std::string n = lx.word();
                if (!iequals(n, b.name)) lx.fail("'" + w + " = " + n + "' closes " + b.kind + " '" + b.name + "'");
            }
            return;
        }
        lx.expect('=', "after '" + w + "'");
        const bool object = iequals(w, "Object") || iequals(w, "Begin_Object");
        const bool group = iequals(w, "Group") || iequals(w, "Begin_Group");
        if (object || group) {
            Block child;
            child.kind = object ? "Object" : "Group";
            bool q = false;
            child.name = scalar(lx, q);
            child.line = line;
            parse_block(lx, child, false, depth + 1);
            b.blocks.push_back(std::move(child));
            continue;
        }
        Keyword k;
        k.name = w;
        k.line = line;
        parse_value(lx, k);
        b.keywords.push_back(std::move(k));
    }
}

}  // namespace

Block parse(const std::string& text0, const std::string& file) {
    // A UTF-8 byte-order mark some editors write is not part of the PVL text.
    const std::string text = text0.rfind("\xEF\xBB\xBF", 0) == 0 ? text0.substr(3) : text0;
    Lexer lx(text, file);
    Block root;
    root.name = file;
    parse_block(lx, root, true, 0);
    return root;
}

Block parse_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open the PVL file");
    std::error_code ec;
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (!ec && bytes > kMaxFileBytes)
        throw Error(path + ": " + std::to_string(bytes) + " bytes is too large for a PVL parameter file (at most " +
                    std::to_string(kMaxFileBytes >> 20) + " MB): check the path");
    std::ostringstream ss;
    ss << in.rdbuf();
    return parse(ss.str(), path);
}

}  // namespace shadelab::pvl
