// Small string utilities: names close to a mistyped one, for "did you mean" messages (unknown
// commands and flags of the CLI, unknown bundled materials and rigs), and ASCII lower case.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace zbrdf {

// The Damerau-Levenshtein distance between a and b: the fewest insertions, deletions,
// substitutions and swaps of two adjacent characters that turn a into b (Lowrance and Wagner
// 1975, with unit costs). Unlike the "optimal string alignment" variant, it is a metric: a
// substring may be edited again after a swap ("ca" -> "abc" is 2). Bytes are compared, so a
// multi-byte UTF-8 character counts as several.
size_t EditDistance(const std::string& a, const std::string& b);

// The candidates within EditDistance max(2, name.size() / 3) of name, closest first (ties in
// the order of `candidates`), at most max_count of them; empty if none is that close. The
// threshold lets a two-letter slip through in a short name and proportionally more in a long
// one, while "plot" is not offered for "eval".
std::vector<std::string> ClosestNames(const std::string& name,
                                      const std::vector<std::string>& candidates,
                                      size_t max_count = 3);

// `text` with ASCII letters in lower case (file extensions, model and parameter names).
std::string AsciiLower(std::string text);

}  // namespace zbrdf
