#include "acquisition/patterns.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "basis/error.h"
#include "basis/spherical_harmonics.h"
#include "tests/rig/rig_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

namespace fs = std::filesystem;

struct Fixture {
  const testing::FastThesisRig& rig = testing::SharedFastThesisRig();
  RigCalibration calibration = NominalCalibration(rig.rig, rig.maps);
  CapturePlan plan;
  std::string cache;
  Fixture() {
    PlanOptions o;
    o.theta_min_rad = DegToRad(10);
    o.theta_max_rad = DegToRad(56);
    o.order = 2;
    plan = MakePlan(o);
    std::string leaf = "zbrdf-pattern-test-";
    leaf += std::to_string(::getpid());
    cache = (fs::temp_directory_path() / leaf).string();
    fs::remove_all(cache);
  }
  ~Fixture() { fs::remove_all(cache); }
  // Sum over projector pixels of (sample radiance / s) x solid angle: the integral of Z^+ (or
  // Z^-) over the zone that the pattern realizes.
  double RealizedIntegral(const PatternSet& set, int lobe) const {
    const Pattern p = set.Load(lobe);
    const RigCalibration& c = calibration;
    double sum = 0;
    for (size_t i = 0; i < p.levels.size(); ++i) {
      if (!c.ProjectorValid(static_cast<int>(i))) continue;
      const double radiance = c.projector_peak_radiance * c.projector_response[p.levels[i]] *
                              c.projector_flat_field[i];
      sum += radiance * c.projector_solid_angle_sr[i];
    }
    return sum / set.lobes()[lobe].radiance_per_unit_z;
  }
};

TEST(Patterns, DarkIsBlackAndZ00RealizesItsClosedFormIntegral) {
  Fixture f;
  const PatternSet set(f.plan, f.calibration, f.cache);
  ASSERT_EQ(set.lobes().size(), f.plan.lobes.size());
  const Pattern dark = set.Load(0);
  for (uint16_t level : dark.levels) ASSERT_EQ(level, 0);
  EXPECT_EQ(set.lobes()[0].radiance_per_unit_z, 0.0);
  // Z_00 is the constant 1 / sqrt(|zone|): its integral over the zone is sqrt(|zone|). The
  // projector pixels tile the zone up to the partial pixels at its edges (footprint-averaged),
  // so the realized integral agrees to the rounding of 8-bit levels and the pixel solid angles.
  const double expected = std::sqrt(f.plan.zone().solid_angle_sr());
  EXPECT_NEAR(f.RealizedIntegral(set, 1), expected, 0.01 * expected);
  // Inside the zone Z_00's pattern is full-scale (flat field 1 on this rig).
  const Pattern z00 = set.Load(1);
  int full = 0, lit = 0;
  for (uint16_t level : z00.levels) {
    lit += level > 0;
    full += level == 255;
  }
  EXPECT_GT(full, 0.9 * lit);
  EXPECT_LT(set.lobes()[1].quantization_error, 1e-3);
}

TEST(Patterns, PositiveAndNegativeLobesCancelOverTheZone) {
  // Every Z_lm with l > 0 is orthogonal to Z_00, so integral Z^+ = integral Z^-.
  Fixture f;
  const PatternSet set(f.plan, f.calibration, f.cache);
  for (size_t lobe = 2; lobe + 1 < f.plan.lobes.size(); lobe += 2) {
    ASSERT_EQ(f.plan.lobes[lobe].kind, PlannedLobe::Kind::kPositive);
    ASSERT_EQ(f.plan.lobes[lobe + 1].kind, PlannedLobe::Kind::kNegative);
    const double pos = f.RealizedIntegral(set, static_cast<int>(lobe));
    const double neg = f.RealizedIntegral(set, static_cast<int>(lobe + 1));
    EXPECT_NEAR(pos, neg, 0.01 * (pos + neg)) << f.plan.lobes[lobe].Name();
    // 8-bit quantization: RMS 1/255/sqrt(12) of full scale, relative to the lobe's own RMS.
    EXPECT_GT(set.lobes()[lobe].quantization_error, 0.0);
    // (0.11% of full scale; measured 0.20-0.24% for these lobes.)
    EXPECT_LT(set.lobes()[lobe].quantization_error, 0.004) << f.plan.lobes[lobe].Name();
  }
}

TEST(Patterns, AreCachedAndDamageIsNamed) {
  Fixture f;
  const PatternSet first(f.plan, f.calibration, f.cache);
  EXPECT_GT(first.compute_seconds(), 0.0);
  const PatternSet second(f.plan, f.calibration, f.cache);
  EXPECT_EQ(second.compute_seconds(), 0.0) << "loaded from the cache";
  EXPECT_EQ(second.folder(), first.folder());
  for (size_t i = 0; i < f.plan.lobes.size(); ++i) {
    EXPECT_EQ(second.Load(static_cast<int>(i)).levels, first.Load(static_cast<int>(i)).levels);
  }
  // Another zone is another pattern set.
  CapturePlan other = f.plan;
  other.theta_max_rad = DegToRad(50);
  EXPECT_NE(PatternKey(other, f.calibration), PatternKey(f.plan, f.calibration));
  // A damaged index is recomputed; a pattern file lost after loading is a named error.
  std::ofstream(first.folder() + "/index.json") << "{ damaged";
  const PatternSet third(f.plan, f.calibration, f.cache);
  EXPECT_GT(third.compute_seconds(), 0.0);
  fs::remove(third.folder() + "/" + third.lobes()[3].file);
  try {
    third.Load(3);
    FAIL() << "a missing pattern loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(third.lobes()[3].file), std::string::npos) << e.what();
  }
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
