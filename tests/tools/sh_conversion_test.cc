#include "tools/sh_conversion.h"

#include <gtest/gtest.h>

#include "acquisition/zonal.h"
#include "basis/error.h"
#include "basis/target_basis.h"
#include "brdf/lambertian.h"
#include "brdf/sh_brdf.h"
#include "fitting/fit_error.h"
#include "tests/tools/simulated_sessions.h"
#include "tools/fit_session.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

TEST(ShConversionTest, ConvertsASessionAndRoundTripsThroughTheFile) {
  const std::string session = testing::SimulatedSession("lambert:0.5,0.4,0.3", 8);
  const ZonalTensor data = ToZonalTensor(ReadZonalExr(session + "/zonal.exr"));
  const ShConversionResult result = ConvertToSh(data, {});
  EXPECT_TRUE(result.tau_automatic);
  EXPECT_GT(result.kept_directions, 0);
  EXPECT_LE(result.kept_directions, result.singular_directions);
  EXPECT_GE(result.diagnostics.noise_gain, 1.0);
  // The thesis zone cannot constrain SH outside it: the conversion says so.
  ASSERT_FALSE(result.warnings.empty());
  EXPECT_NE(result.warnings[0].find("Shannon number"), std::string::npos);
  // A Lambertian's f^ = rho cos(theta_i) / pi is band-limited (degree 1 in w_i, 0 in w_r): the
  // zone is reproduced to the capture's accuracy (its coefficient error is ~2%).
  const ShBrdf sh(result.data);
  const CosineWeightedFn f = [&sh](const Vec3& w_o, std::span<const Vec3> w_i, std::span<Rgb> out) {
    sh.CosineWeightedBatch(w_o, w_i, out);
  };
  const BrdfComparison c = CompareBrdfs(f, CosineWeightedOf(LambertianBrdf(Rgb(0.5, 0.4, 0.3))), data.zone());
  EXPECT_LT(c.in_zone, 0.05);
  const std::string path = testing::TestBuildDir("test-sh") + "/lambert.exr";
  WriteShFile(path, result.data);
  const ShBrdf read(ReadShFile(path), path);
  const Vec3 wi = Normalize(Vec3{0.2, 0.3, 0.9}), wo = Normalize(Vec3{-0.4, 0.1, 0.8});
  // The file stores y_ab in float: the rounding bound is 6e-8 sum_ab |y_ab T_a(w_i) T_b(w_o)|.
  const TargetBasis basis(result.data.target, result.data.order);
  Eigen::VectorXd ti(basis.size()), to(basis.size());
  basis.Eval(wi, ti.data());
  basis.Eval(wo, to.data());
  const double bound = 6e-8 * ti.cwiseAbs().dot(result.data.coefficients[0].cwiseAbs() * to.cwiseAbs()) / wi.z;
  EXPECT_NEAR(read.Eval(wi, wo).r, sh.Eval(wi, wo).r, bound);
  EXPECT_EQ(read.Spec(), "file:" + path);
}

TEST(ShConversionTest, GivenTauTruncatesAndOtherTargetsWork) {
  const std::string session = testing::SimulatedSession("lambert:0.5,0.4,0.3", 8);
  const ZonalTensor data = ToZonalTensor(ReadZonalExr(session + "/zonal.exr"));
  ShConversionOptions options;
  options.tau = 0.3;  // sh-odd order 6 on this zone: singular values 0.12 to 0.70
  options.target = TargetKind::kShOdd;
  options.order = 6;
  const ShConversionResult r = ConvertToSh(data, options);
  EXPECT_FALSE(r.tau_automatic);
  EXPECT_EQ(r.data.order, 6);
  EXPECT_EQ(r.data.target, TargetKind::kShOdd);
  EXPECT_GT(r.diagnostics.truncated_components, 0);
  // Noise gain is 1 / (smallest kept singular value) <= 1 / (tau * largest).
  EXPECT_LE(r.diagnostics.noise_gain, 1.0 / (0.3 * r.diagnostics.largest_singular_value) * (1 + 1e-12));
  options.tau = 1.5;
  EXPECT_THROW(ConvertToSh(data, options), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
