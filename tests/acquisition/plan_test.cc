#include "acquisition/plan.h"

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/spherical_harmonics.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

PlanOptions Options(int order) {
  PlanOptions o;
  o.theta_min_rad = DegToRad(10);
  o.theta_max_rad = DegToRad(56);
  o.order = order;
  o.shortest_exposure_us = 1000;
  return o;
}

TEST(Plan, Order4HasFiftyPatternsAndHundredFiftyFrames) {
  const CapturePlan plan = MakePlan(Options(4));
  // dark + Z00+ + (25 - 1) functions with two lobes each.
  EXPECT_EQ(plan.lobes.size(), 1u + 1u + 2u * 24u);
  EXPECT_EQ(plan.frame_count(), 150);
  EXPECT_EQ(plan.lobes[0].Name(), "dark");
  EXPECT_EQ(plan.lobes[1].Name(), "Z0,0+");
  std::set<std::string> names;
  for (const PlannedLobe& lobe : plan.lobes) names.insert(lobe.Name());
  EXPECT_EQ(names.size(), plan.lobes.size());
  EXPECT_EQ(names.count("Z0,0-"), 0u) << "Z00 is positive everywhere: no negative lobe";
  for (int l = 1; l <= 4; ++l) {
    for (int m = -l; m <= l; ++m) {
      const std::string base = "Z" + std::to_string(l) + "," + std::to_string(m);
      EXPECT_EQ(names.count(base + "+"), 1u) << base;
      EXPECT_EQ(names.count(base + "-"), 1u) << base;
    }
  }
}

TEST(Plan, BracketIsThreeExposuresTwoStopsApartByDefault) {
  const CapturePlan plan = MakePlan(Options(2));
  ASSERT_EQ(plan.exposures_us.size(), 3u);
  EXPECT_DOUBLE_EQ(plan.exposures_us[0], 1000);
  EXPECT_DOUBLE_EQ(plan.exposures_us[1], 4000);
  EXPECT_DOUBLE_EQ(plan.exposures_us[2], 16000);
}

TEST(Plan, FrameIndexRoundTripsInCaptureOrder) {
  PlanOptions o = Options(3);
  o.repeats = 2;
  const CapturePlan plan = MakePlan(o);
  for (int i = 0; i < plan.frame_count(); ++i) {
    const PlannedFrame f = plan.Frame(i);
    EXPECT_EQ(plan.FrameIndex(f.lobe, f.exposure, f.repeat), i);
    if (i > 0) {
      const PlannedFrame prev = plan.Frame(i - 1);
      EXPECT_GE(f.lobe, prev.lobe) << "lobe by lobe";
      if (f.lobe == prev.lobe && f.repeat == prev.repeat) {
        EXPECT_EQ(f.exposure, prev.exposure + 1) << "shortest exposure first";
      }
    }
  }
}

TEST(Plan, JsonRoundTrip) {
  const CapturePlan plan = MakePlan(Options(5));
  const CapturePlan back = CapturePlan::FromJson(plan.ToJson());
  EXPECT_DOUBLE_EQ(back.theta_min_rad, plan.theta_min_rad);
  EXPECT_DOUBLE_EQ(back.theta_max_rad, plan.theta_max_rad);
  EXPECT_EQ(back.order, plan.order);
  EXPECT_EQ(back.exposures_us, plan.exposures_us);
  ASSERT_EQ(back.lobes.size(), plan.lobes.size());
  for (size_t i = 0; i < plan.lobes.size(); ++i) EXPECT_EQ(back.lobes[i].Name(), plan.lobes[i].Name());
}

TEST(Plan, DamagedJsonIsAnInputError) {
  nlohmann::json j = MakePlan(Options(2)).ToJson();
  j["lobes"][3] = "Z9,12+";  // |m| > l
  EXPECT_THROW(CapturePlan::FromJson(j), InputError);
  j = MakePlan(Options(2)).ToJson();
  j.erase("exposures_us");
  EXPECT_THROW(CapturePlan::FromJson(j), InputError);
  j = MakePlan(Options(2)).ToJson();
  j["exposures_us"][0] = -5.0;
  EXPECT_THROW(CapturePlan::FromJson(j), InputError);
  // A float where an integer belongs: nlohmann's get<int>() would convert 1e102 with undefined
  // behaviour (fuzz corpus regression-order-1e102); integral floats are read as integers.
  j = MakePlan(Options(2)).ToJson();
  j["order"] = 1e102;
  EXPECT_THROW(CapturePlan::FromJson(j), InputError);
  j["order"] = 2.5;
  EXPECT_THROW(CapturePlan::FromJson(j), InputError);
  j["order"] = 2.0;
  EXPECT_EQ(CapturePlan::FromJson(j).order, 2);
}

TEST(Plan, AbsurdOptionsAreRejected) {
  PlanOptions o = Options(31);
  EXPECT_THROW(MakePlan(o), InputError);
  o = Options(4);
  o.exposures = 0;
  EXPECT_THROW(MakePlan(o), InputError);
  o = Options(4);
  o.stops_apart = 0;
  EXPECT_THROW(MakePlan(o), InputError);
  o = Options(4);
  o.shortest_exposure_us = std::nan("");
  EXPECT_THROW(MakePlan(o), InputError);
  o = Options(4);
  o.repeats = 0;
  EXPECT_THROW(MakePlan(o), InputError);
}

TEST(Plan, OptionsReportEveryBadFieldAtOnce) {
  PlanOptions o = Options(31);
  o.exposures = 0;
  o.repeats = 101;
  try {
    o.Validate();
    FAIL() << "expected InvalidOptions";
  } catch (const InvalidOptions& e) {
    const std::vector<std::string> expected = {"order must be in [0, 30] (got 31)",
                                               "exposures must be in [1, 10] (got 0)",
                                               "repeats must be in [1, 100] (got 101)"};
    EXPECT_EQ(e.problems(), expected);
    EXPECT_EQ(std::string(e.what()).rfind("PlanOptions: order must be", 0), 0u) << e.what();
  }
  EXPECT_NO_THROW(Options(4).Validate());
}

TEST(Plan, PredictedTimeFollowsTheTimingModel) {
  // Per pattern: settle; per frame: max(frame period, exposure + readout).
  PlanOptions o = Options(2);
  o.shortest_exposure_us = 50000;  // 50, 200, 800 ms: period-limited, then exposure-limited
  const CapturePlan plan = MakePlan(o);
  TimingParams t;
  t.frame_rate_hz = 10;  // 100 ms period
  t.readout_ms = 30;
  t.projector_settle_ms = 50;
  const double patterns = static_cast<double>(plan.lobes.size());
  const double per_bracket = 0.1 + (0.2 + 0.03) + (0.8 + 0.03);
  EXPECT_NEAR(PredictCaptureTimeS(plan, t), patterns * (0.05 + per_bracket), 1e-9);
}

TEST(Plan, DefaultZoneShrinksAndRoundsInward) {
  double lo, hi;
  DefaultZone(DegToRad(9.06), DegToRad(57.0), 0.5, &lo, &hi);
  EXPECT_NEAR(RadToDeg(lo), 9.6, 1e-9);
  EXPECT_NEAR(RadToDeg(hi), 56.5, 1e-9);
  EXPECT_THROW(DefaultZone(DegToRad(10), DegToRad(10.5), 0.5, &lo, &hi), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
