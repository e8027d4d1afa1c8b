// A small reader for PVL (Parameter Value Language, PDS/ISIS3 label syntax) as ISIS3's photometric parameter
// files use it. What it accepts:
//  - `Object = NAME` ... `End_Object` and `Group = NAME` ... `End_Group` blocks, nested; `End` stops the file;
//    `Begin_Object`/`Begin_Group` as synonyms; the name after End_Object/End_Group (`End_Group = Algorithm`) is
//    accepted and checked.
//  - `Keyword = value` with value a number or bare word, a quoted string ("..." or '...', may span lines; a
//    line that ends in '-' inside the quotes continues without the '-', as ISIS writes long strings), or a list
//    `(a, b, c)` / `{a, b, c}` that may span lines; a unit in angle brackets after a value (`30 <deg>`) is dropped.
//  - comments `/* ... */` and lines starting with '#'.
//  - names and keywords case-insensitive (PVL is), values kept as written.
// What it does not: nested lists, multi-line unquoted values, `Keyword` without a value, the PDS pointer syntax.
// Every error names the file and line.
#pragma once
#include <string>
#include <vector>

namespace shadelab::pvl {

struct Keyword {
    std::string name;                 // as written
    std::vector<std::string> values;  // one for a scalar, the elements for a list
    bool list = false;                // written as (a, b, ...)
    bool quoted = false;              // scalar written in quotes
    int line = 0;
};

struct Block {
    std::string kind;                 // "Object", "Group", or "" for the file itself
    std::string name;
    int line = 0;
    std::vector<Keyword> keywords;
    std::vector<Block> blocks;

    // Case-insensitive lookups; nullptr when absent.
    const Keyword* keyword(const std::string& name) const;
    const Block* block(const std::string& kind, const std::string& name) const;   // direct child
    const Block* find(const std::string& kind, const std::string& name) const;    // depth-first, any level
};

// Throws shadelab::Error "FILE:LINE: what is wrong" on malformed input.
Block parse(const std::string& text, const std::string& file);
Block parse_file(const std::string& path);

bool iequals(const std::string& a, const std::string& b);

}  // namespace shadelab::pvl
