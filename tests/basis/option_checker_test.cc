#include "basis/option_checker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

struct Inner {
  int n = 1;
  void Validate() const { OptionChecker("Inner").AtLeast("n", n, 1).ThrowIfInvalid(); }
};

std::vector<std::string> ProblemsOf(const OptionChecker& check) {
  try {
    check.ThrowIfInvalid();
  } catch (const InvalidOptions& e) {
    return e.problems();
  }
  return {};
}

TEST(OptionChecker, EveryProblemIsReportedWithTheFieldTheRangeAndTheValue) {
  Inner bad;
  bad.n = 0;
  OptionChecker check("Outer");
  check.InRange("a", 5, 0, 4)
      .InRangeAbove("b", 0, 0, 1)
      .InRangeBelow("c", 1, 0, 1)
      .AtLeast("d", std::nan(""), 0)
      .Above("e", 0, 0)
      .Positive("f", INFINITY)
      .ValidZone("g, h", 0.5, 0.25)
      .Require(false, "i", "must be even (got 3)")
      .Nested("inner", bad);
  const std::vector<std::string> expected = {
      "a must be in [0, 4] (got 5)",
      "b must be in (0, 1] (got 0)",
      "c must be in [0, 1) (got 1)",
      "d must be >= 0 (got nan)",
      "e must be > 0 (got 0)",
      "f must be > 0 and finite (got inf)",
      "g, h must satisfy 0 <= theta_min < theta_max <= 90 deg (got 28.6479, 14.3239 deg)",
      "i must be even (got 3)",
      "inner.n must be >= 1 (got 0)"};
  EXPECT_EQ(ProblemsOf(check), expected);
  try {
    check.ThrowIfInvalid();
    FAIL() << "expected InvalidOptions";
  } catch (const InputError& e) {  // the CLI catches InputError and prints what()
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("Outer: a must be in [0, 4] (got 5); b must be", 0), 0u) << message;
    EXPECT_NE(message.find("; inner.n must be >= 1 (got 0)"), std::string::npos) << message;
  }
}

TEST(OptionChecker, ValuesInRangeAndTheirEdgesPass) {
  OptionChecker check("Fine");
  check.InRange("a", 0, 0, 4)
      .InRange("a", 4, 0, 4)
      .InRangeAbove("b", 1, 0, 1)
      .InRangeBelow("c", 0, 0, 1)
      .AtLeast("d", 0, 0)
      .Above("e", 1e-300, 0)
      .Positive("f", 1e300)
      .ValidZone("g", 0, M_PI / 2)
      .Require(true, "h", "is never reported")
      .Nested("inner", Inner());
  EXPECT_TRUE(ProblemsOf(check).empty());
  EXPECT_NO_THROW(check.ThrowIfInvalid());
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
