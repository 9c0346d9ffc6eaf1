#include "basis/strings.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <utility>

namespace zbrdf {

std::string AsciiLower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

size_t EditDistance(const std::string& a, const std::string& b) {
  // Lowrance and Wagner's algorithm: d[i+1][j+1] is the distance between a[0, i) and b[0, j),
  // with a sentinel row and column of `infinity`; last_row_of[c] is the last row (1-based) whose
  // character of a is c, so a swap of the characters a[k-1] == b[j-1] and b[l-1] == a[i-1]
  // with the substring between them deleted or inserted costs 1 + (i-k-1) + (j-l-1).
  const size_t rows = a.size() + 2, cols = b.size() + 2, infinity = a.size() + b.size();
  std::vector<size_t> d(rows * cols);
  auto at = [&](size_t i, size_t j) -> size_t& { return d[i * cols + j]; };
  at(0, 0) = infinity;
  for (size_t i = 0; i <= a.size(); ++i) {
    at(i + 1, 0) = infinity;
    at(i + 1, 1) = i;
  }
  for (size_t j = 0; j <= b.size(); ++j) {
    at(0, j + 1) = infinity;
    at(1, j + 1) = j;
  }
  std::array<size_t, 256> last_row_of{};  // 0: not seen yet
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t last_match_col = 0;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t k = last_row_of[static_cast<unsigned char>(b[j - 1])];
      const size_t l = last_match_col;
      size_t cost = 1;
      if (a[i - 1] == b[j - 1]) {
        cost = 0;
        last_match_col = j;
      }
      at(i + 1, j + 1) = std::min({at(i, j) + cost, at(i + 1, j) + 1, at(i, j + 1) + 1,
                                   at(k, l) + (i - k - 1) + 1 + (j - l - 1)});
    }
    last_row_of[static_cast<unsigned char>(a[i - 1])] = i;
  }
  return at(a.size() + 1, b.size() + 1);
}

std::vector<std::string> ClosestNames(const std::string& name,
                                      const std::vector<std::string>& candidates,
                                      size_t max_count) {
  const size_t threshold = std::max<size_t>(2, name.size() / 3);
  std::vector<std::pair<size_t, size_t>> close;  // distance, index in candidates
  for (size_t k = 0; k < candidates.size(); ++k) {
    // Every edit changes the length by at most one: a length difference beyond the threshold
    // rules a candidate out without the O(n m) distance (a long mistyped name against a list).
    const size_t length_difference = name.size() > candidates[k].size()
                                         ? name.size() - candidates[k].size()
                                         : candidates[k].size() - name.size();
    if (length_difference > threshold) continue;
    const size_t distance = EditDistance(name, candidates[k]);
    if (distance <= threshold) close.emplace_back(distance, k);
  }
  std::stable_sort(close.begin(), close.end());
  std::vector<std::string> out;
  for (size_t k = 0; k < std::min(close.size(), max_count); ++k) {
    out.push_back(candidates[close[k].second]);
  }
  return out;
}

}  // namespace zbrdf
