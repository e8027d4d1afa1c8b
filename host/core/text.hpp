// Small text helpers shared by the command line and the tests.
#pragma once
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

namespace shadelab {

// Splits at every `sep`, keeping empty fields ("a,,b" -> a, "", b; "a," -> a, "").
inline std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::string cur;
    std::istringstream in(s);
    while (std::getline(in, cur, sep)) out.push_back(cur);
    if (!s.empty() && s.back() == sep) out.push_back("");
    return out;
}

// Levenshtein distance: insertions, deletions and substitutions of one character each cost 1.
inline std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diag = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diag = up;
        }
    }
    return row[b.size()];
}

// The candidate closest to `word` for a "did you mean" hint: the fewest edits to the candidate or to a prefix
// of it ("minaert" -> "minnaert_1941"), within a third of the word's length (at least 2); "" when none is close.
inline std::string closest_match(const std::string& word, const std::vector<std::string>& candidates) {
    std::string best;
    if (word.size() <= 2) return best;   // "-q" is one edit from every short flag: no hint is better than a wrong one
    std::size_t best_d = std::max<std::size_t>(2, word.size() / 3) + 1;
    for (const auto& c : candidates) {
        std::size_t d = edit_distance(word, c);
        for (std::size_t len = word.size() > 0 ? word.size() - 1 : 0; len <= word.size() + 1 && len < c.size(); ++len)
            d = std::min(d, edit_distance(word, c.substr(0, len)) + 1);   // a prefix match costs one more
        if (d < best_d) { best_d = d; best = c; }
    }
    return best;
}

// " (did you mean 'x'?)" or "".
inline std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
    const std::string m = closest_match(word, candidates);
    return m.empty() ? std::string() : " (did you mean '" + m + "'?)";
}

}  // namespace shadelab
