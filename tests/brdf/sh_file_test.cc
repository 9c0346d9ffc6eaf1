#include "brdf/sh_file.h"

#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "basis/error.h"
#include "basis/zone.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

std::string TempPath(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "zbrdf-sh-file-test";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

ShBrdfData RandomData(TargetKind target, int order, int rows, int cols) {
  ShBrdfData data;
  data.theta_min_rad = DegToRad(9);
  data.theta_max_rad = DegToRad(57);
  data.target = target;
  data.order = order;
  data.exitant_theta = rows;
  data.exitant_phi = cols;
  const int n = data.size();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int ch = 0; ch < 3; ++ch) {
    data.coefficients[ch].resize(n, n);
    for (int i = 0; i < n * n; ++i) data.coefficients[ch].data()[i] = u(rng);
  }
  data.FillExitantTables();
  data.info = {{"tau", 1e-3}};
  return data;
}

TEST(ShFileTest, RoundTripsEveryTarget) {
  for (TargetKind target : {TargetKind::kSh, TargetKind::kShEven, TargetKind::kShOdd, TargetKind::kHsh}) {
    const ShBrdfData data = RandomData(target, 4, 9, 12);
    const std::string path = TempPath("sh.exr");
    WriteShFile(path, data);
    const ShBrdfData read = ReadShFile(path);
    EXPECT_EQ(read.target, target);
    EXPECT_EQ(read.order, 4);
    EXPECT_EQ(read.exitant_theta, 9);
    EXPECT_EQ(read.exitant_phi, 12);
    EXPECT_DOUBLE_EQ(read.theta_min_rad, data.theta_min_rad);
    EXPECT_DOUBLE_EQ(read.theta_max_rad, data.theta_max_rad);
    EXPECT_EQ(read.info, data.info);
    for (int ch = 0; ch < 3; ++ch) {
      // Stored in float: relative 6e-8 of values of order 1.
      EXPECT_LT((read.coefficients[ch] - data.coefficients[ch]).cwiseAbs().maxCoeff(), 1e-7);
      ASSERT_EQ(read.exitant[ch].size(), data.exitant[ch].size());
      for (size_t i = 0; i < data.exitant[ch].size(); ++i) EXPECT_EQ(read.exitant[ch][i], data.exitant[ch][i]);
    }
  }
}

TEST(ShFileTest, ExitantTablesAreTheTensorAtCellCentres) {
  const ShBrdfData data = RandomData(TargetKind::kSh, 3, 5, 7);
  const TargetBasis basis(TargetKind::kSh, 3);
  const int n = basis.size();
  Eigen::VectorXd t(n);
  const int i = 3, j = 5;
  const Vec3 w = data.ExitantDirection(i, j);
  EXPECT_NEAR(SphericalTheta(w), (i + 0.5) * 0.5 * M_PI / 5, 1e-12);
  EXPECT_NEAR(SphericalPhi(w), (j + 0.5) * 2 * M_PI / 7, 1e-12);
  basis.Eval(w, t.data());
  const Eigen::VectorXd y = data.coefficients[1] * t;
  for (int a = 0; a < n; ++a) EXPECT_NEAR(data.exitant[1][(i * 7 + j) * n + a], y[a], 1e-6 * (1 + std::abs(y[a])));
}

TEST(ShFileTest, LayerNamesFollowTheDocumentedScheme) {
  EXPECT_EQ(ShLayerName(TargetKind::kSh, 2, -1), "Y2_-1");
  EXPECT_EQ(ShLayerName(TargetKind::kShOdd, 3, 0), "Y3_0");
  EXPECT_EQ(ShLayerName(TargetKind::kHsh, 4, 4), "H4_4");
}

TEST(ShFileTest, RejectsBadInput) {
  ShBrdfData data = RandomData(TargetKind::kSh, 2, 4, 4);
  data.exitant[0].pop_back();
  EXPECT_THROW(WriteShFile(TempPath("bad.exr"), data), InputError);
  EXPECT_THROW(ReadShFile(TempPath("does-not-exist.exr")), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
