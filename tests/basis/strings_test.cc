#include "basis/strings.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// All strings over `alphabet` of length <= max_length.
std::vector<std::string> AllStrings(const std::string& alphabet, size_t max_length) {
  std::vector<std::string> out = {""};
  for (size_t begin = 0; begin < out.size(); ++begin) {
    if (out[begin].size() == max_length) continue;
    for (char c : alphabet) out.push_back(out[begin] + c);
  }
  return out;
}

// The independent reference: breadth-first search over strings, one edit (insert, delete,
// substitute, swap two adjacent characters) per step, which is the definition of the distance.
// Strings are kept to `max_length` characters: between strings of length <= m, a path through
// length m + 3 takes 3 insertions and 3 deletions, longer than the direct m substitutions and
// insertions, so for m = 4 a cap of 6 loses no shortest path.
std::map<std::string, size_t> DistancesFrom(const std::string& start, const std::string& alphabet,
                                            size_t max_length) {
  std::map<std::string, size_t> distance = {{start, 0}};
  std::deque<std::string> queue = {start};
  while (!queue.empty()) {
    const std::string s = queue.front();
    queue.pop_front();
    std::vector<std::string> next;
    for (size_t i = 0; i <= s.size(); ++i) {
      if (s.size() < max_length) {
        for (char c : alphabet) next.push_back(s.substr(0, i) + c + s.substr(i));
      }
      if (i == s.size()) continue;
      next.push_back(s.substr(0, i) + s.substr(i + 1));
      for (char c : alphabet) {
        std::string t = s;
        t[i] = c;
        next.push_back(t);
      }
      if (i + 1 < s.size()) {
        std::string t = s;
        std::swap(t[i], t[i + 1]);
        next.push_back(t);
      }
    }
    for (const std::string& t : next) {
      if (distance.emplace(t, distance[s] + 1).second) queue.push_back(t);
    }
  }
  return distance;
}

TEST(EditDistance, EqualsTheFewestSingleEditsForEveryPairOfShortStrings) {
  const std::string alphabet = "abc";
  const std::vector<std::string> strings = AllStrings(alphabet, 4);  // 121 strings
  for (const std::string& a : strings) {
    const std::map<std::string, size_t> reference = DistancesFrom(a, alphabet, 6);
    for (const std::string& b : strings) {
      ASSERT_EQ(EditDistance(a, b), reference.at(b)) << "'" << a << "' -> '" << b << "'";
    }
  }
}

TEST(EditDistance, KnownPairs) {
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3u);  // Levenshtein's classic example
  EXPECT_EQ(EditDistance("ca", "abc"), 2u);          // 3 in the optimal-string-alignment variant
  EXPECT_EQ(EditDistance("simualte", "simulate"), 1u);
  EXPECT_EQ(EditDistance("", "order"), 5u);
  EXPECT_EQ(EditDistance("order", ""), 5u);
  EXPECT_EQ(EditDistance("", ""), 0u);
}

TEST(ClosestNames, ClosestFirstWithinAThirdOfTheLengthOrTwo) {
  const std::vector<std::string> commands = {"eval", "fit", "fit-all", "plot", "simulate"};
  EXPECT_EQ(ClosestNames("simulat", commands), std::vector<std::string>({"simulate"}));
  EXPECT_EQ(ClosestNames("fitall", commands), std::vector<std::string>({"fit-all"}));
  // "fi" is 1 from fit and 5 from fit-all; "eval" is 4 from "plot": not offered.
  EXPECT_EQ(ClosestNames("fi", commands), std::vector<std::string>({"fit"}));
  EXPECT_TRUE(ClosestNames("eval", {"plot"}).empty());
  // Ties keep the candidates' order; max_count bounds the list.
  EXPECT_EQ(ClosestNames("fat", {"fat-x", "fit", "cat"}),
            std::vector<std::string>({"fit", "cat", "fat-x"}));
  EXPECT_EQ(ClosestNames("fat", {"fit", "cat", "fat-x"}, 1), std::vector<std::string>({"fit"}));
}

TEST(ClosestNames, SkippingCandidatesByLengthChangesNothing) {
  // A candidate whose length differs from the name's by more than the threshold is skipped
  // without computing its distance (an edit changes the length by at most one): the list must be
  // what filtering every candidate by its EditDistance gives, for names of every length 0-7.
  const std::vector<std::string> strings = AllStrings("ab", 7);  // 255 strings
  for (const std::string& name : strings) {
    const size_t threshold = std::max<size_t>(2, name.size() / 3);
    std::vector<std::pair<size_t, size_t>> close;
    for (size_t k = 0; k < strings.size(); ++k) {
      const size_t distance = EditDistance(name, strings[k]);
      if (distance <= threshold) close.emplace_back(distance, k);
    }
    std::stable_sort(close.begin(), close.end());
    std::vector<std::string> expected;
    for (const auto& [distance, k] : close) expected.push_back(strings[k]);
    ASSERT_EQ(ClosestNames(name, strings, strings.size()), expected) << "'" << name << "'";
  }
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
