// The numerical stability suite (tools/stress.h): every case, one test per group, and the
// runner's own classification of outcomes. Tolerances are the cases' own (stated in their
// `tolerance` and justified next to the checks in tools/stress.cc and in docs/stress.md); what
// these tests add is that each case ends as declared: pass, or the declared error kind with a
// clear message, never FAIL. Seeds are fixed (StressOptions::seed = 1).
#include "tools/stress.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <limits>
#include <set>

#include "basis/error.h"
#include "pictures/image.h"
#include "simulated_sessions.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

StressOptions TestOptions() {
  // The tools tests' direction-map cache (simulated_sessions.h), so maps are traced once.
  ::setenv("ZBRDF_CACHE_DIR", testing::TestBuildDir("test-cache").c_str(), 0);
  StressOptions o;
  o.work_dir = testing::TestBuildDir("stress-work");
  o.rig_path = testing::ThesisRigPath();
  o.seed = 1;
  return o;
}

// What the case declares, as the outcome it must have.
void ExpectAsDeclared(const StressCase& c, const StressResult& r) {
  SCOPED_TRACE(c.name + ": " + r.detail);
  ASSERT_NE(r.outcome, StressOutcome::kFail);
  switch (c.expect) {
    case StressExpect::kSuccess:
      EXPECT_EQ(r.outcome, StressOutcome::kPass);
      break;
    case StressExpect::kInputError:
      EXPECT_EQ(r.error_kind, "input");
      break;
    case StressExpect::kDeviceError:
      EXPECT_EQ(r.error_kind, "device");
      break;
    case StressExpect::kNumericalError:
      EXPECT_EQ(r.error_kind, "numerical");
      break;
    case StressExpect::kSuccessOrError:
      break;
  }
  if (r.outcome == StressOutcome::kExpectedError) {
    // Clear: the message names what and says what to do, in more than a few words.
    EXPECT_GE(r.detail.size(), 40u);
  }
  EXPECT_EQ(CountNonFiniteJson(r.ToJson()), 0);
}

void RunGroup(const std::string& group, size_t expected_cases) {
  const StressOptions options = TestOptions();
  size_t n = 0;
  for (const StressCase& c : StressCases()) {
    if (c.group != group) continue;
    ++n;
    ExpectAsDeclared(c, RunStressCase(c, options));
  }
  EXPECT_EQ(n, expected_cases);
}

TEST(StressTest, TableIsWellFormed) {
  std::set<std::string> names;
  for (const StressCase& c : StressCases()) {
    EXPECT_TRUE(names.insert(c.name).second) << "duplicate " << c.name;
    EXPECT_FALSE(c.what.empty()) << c.name;
    EXPECT_FALSE(c.tolerance.empty()) << c.name;
    EXPECT_TRUE(c.group == "basis" || c.group == "hdr" || c.group == "zonal" || c.group == "capture")
        << c.name;
    EXPECT_EQ(&FindStressCase(c.name), &c);
  }
  try {
    FindStressCase("no-such-case");
    ADD_FAILURE() << "no error for an unknown case";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("basis-order30-narrow"), std::string::npos) << e.what();
  }
}

// The runner must call FAIL whatever is not as declared: success where an error was expected, a
// check missed, an internal error, an error of the wrong kind or without a message.
TEST(StressTest, RunnerClassifiesOutcomes) {
  const StressOptions options = TestOptions();
  const auto run = [&](StressExpect expect, std::function<std::string()> body) {
    StressCase c{"runner-selftest", "basis", "self test", "none", expect,
                 [body](const StressOptions&, const std::string&) { return body(); }};
    return RunStressCase(c, options);
  };
  const std::string clear = "thing.exr: value 3 is NaN; re-process the session";
  EXPECT_EQ(run(StressExpect::kSuccess, [] { return std::string("ok"); }).outcome, StressOutcome::kPass);
  EXPECT_EQ(run(StressExpect::kInputError, [] { return std::string("ok"); }).outcome, StressOutcome::kFail);
  EXPECT_EQ(run(StressExpect::kSuccess, []() -> std::string { throw StressCheckFailed("x > 1"); }).outcome,
            StressOutcome::kFail);
  const StressResult input = run(StressExpect::kInputError, [&]() -> std::string { throw InputError(clear); });
  EXPECT_EQ(input.outcome, StressOutcome::kExpectedError);
  EXPECT_EQ(input.detail, clear);
  EXPECT_EQ(run(StressExpect::kSuccessOrError, [&]() -> std::string { throw NumericalError(clear); }).outcome,
            StressOutcome::kExpectedError);
  EXPECT_EQ(run(StressExpect::kInputError, [&]() -> std::string { throw NumericalError(clear); }).outcome,
            StressOutcome::kFail);
  EXPECT_EQ(run(StressExpect::kSuccessOrError, [&]() -> std::string { throw InternalError(clear); }).outcome,
            StressOutcome::kFail);
  EXPECT_EQ(run(StressExpect::kSuccessOrError, []() -> std::string { throw InputError("bad"); }).outcome,
            StressOutcome::kFail);  // unclear
  EXPECT_EQ(run(StressExpect::kSuccessOrError, []() -> std::string { throw std::bad_alloc(); }).outcome,
            StressOutcome::kFail);
}

TEST(StressTest, NonFiniteCheckersFindNaNAndInf) {
  const StressOptions options = TestOptions();
  RgbImage image;
  image.width = 3;
  image.height = 2;
  image.pixels.assign(6, Rgb(0.5));
  image.pixels[4].g = std::numeric_limits<double>::quiet_NaN();
  image.pixels[1].b = std::numeric_limits<double>::infinity();
  const std::string path = options.work_dir + "/nonfinite.exr";
  WriteExrImage(path, image);
  EXPECT_EQ(CountNonFiniteExr(path), 2);
  nlohmann::json j = {{"a", 1.0}, {"b", {1.0, std::numeric_limits<double>::quiet_NaN()}}};
  EXPECT_EQ(CountNonFiniteJson(j), 1);
  j["c"] = {{"d", -std::numeric_limits<double>::infinity()}};
  EXPECT_EQ(CountNonFiniteJson(j), 2);
  EXPECT_THROW(CountNonFiniteExr(options.work_dir + "/missing.exr"), InputError);
}

// Orders up to 30 on narrow zones and zones touching the pole or the horizon (about 3 s each).
TEST(StressTest, Basis) { RunGroup("basis", 10); }

TEST(StressTest, Hdr) { RunGroup("hdr", 5); }

TEST(StressTest, Zonal) { RunGroup("zonal", 7); }

// Simulated captures of extreme materials, then convert and fits (about 25 s on 2 cores).
TEST(StressTest, Capture) { RunGroup("capture", 7); }

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
