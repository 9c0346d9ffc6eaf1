#include "brdf/mirror.h"

#include <gtest/gtest.h>

#include "basis/error.h"
#include "brdf_checks.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

TEST(MirrorTest, SamplesTheMirrorDirectionAsADelta) {
  const MirrorBrdf mirror(Rgb(0.9, 0.8, 0.7));
  EXPECT_TRUE(mirror.IsDelta());
  testing::Rng rng(81);
  for (int n = 0; n < 50; ++n) {
    const Vec3 w_o = testing::RandomUpperDirection(rng);
    const BrdfSample s = mirror.Sample(w_o, rng.Uniform(), rng.Uniform(), rng.Uniform());
    EXPECT_TRUE(s.is_delta);
    EXPECT_EQ(s.pdf, 1.0);
    EXPECT_EQ(s.delta_reflectance, Rgb(0.9, 0.8, 0.7));
    // Angle of incidence equals angle of reflection, in the plane of incidence.
    EXPECT_NEAR(s.w_i.z, w_o.z, 1e-15);
    EXPECT_NEAR(Length(Cross(s.w_i + w_o, Vec3{0, 0, 1})), 0.0, 1e-15);
    EXPECT_EQ(mirror.Eval(s.w_i, w_o), Rgb());
    EXPECT_EQ(mirror.Pdf(w_o, s.w_i), 0.0);
  }
  EXPECT_EQ(mirror.Sample(Vec3{0, 0.6, -0.8}, 0.5, 0.5, 0.5).pdf, 0.0);
}

TEST(MirrorTest, ReflectanceMustBeInTheUnitInterval) {
  EXPECT_THROW(MirrorBrdf(Rgb(1.1)), InputError);
  EXPECT_THROW(MirrorBrdf(Rgb(-0.1)), InputError);
  EXPECT_TRUE(MirrorBrdf(Rgb(1.0)).IsEnergyConserving());
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
