#include "acquisition/ground_truth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "basis/spherical_harmonics.h"
#include "brdf/material_spec.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// The material as it is, except that it does not declare itself isotropic: the ground truth then
// integrates every cell at its own 2 x 2 points, an independent second method for the row
// rotation.
class NotDeclaredIsotropic final : public Brdf {
 public:
  explicit NotDeclaredIsotropic(std::unique_ptr<Brdf> inner) : inner_(std::move(inner)) {}
  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override { return inner_->Eval(w_i, w_o); }
  void EvalBatch(std::span<const Vec3> w_i, std::span<const Vec3> w_o, std::span<Rgb> f) const override {
    inner_->EvalBatch(w_i, w_o, f);
  }
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const override {
    return inner_->Sample(w_o, u_lobe, u0, u1);
  }
  double Pdf(const Vec3& w_o, const Vec3& w_i) const override { return inner_->Pdf(w_o, w_i); }
  double GlossyProbability(const Vec3& w_o) const override { return inner_->GlossyProbability(w_o); }
  bool IsReciprocal() const override { return inner_->IsReciprocal(); }
  bool IsEnergyConserving() const override { return inner_->IsEnergyConserving(); }
  std::string Spec() const override { return inner_->Spec(); }

 private:
  std::unique_ptr<Brdf> inner_;
};

ZonalData Layout(int order) {
  ZonalData layout;
  layout.theta_min_rad = 10 * M_PI / 180;
  layout.theta_max_rad = 56 * M_PI / 180;
  layout.order = order;
  layout.grid = MakeExitantGrid(layout.zone(), 2.0, 4.0);
  return layout;
}

// Relative L2 difference of two truths over the same cells (solid-angle weights cancel within a
// row and differ little between rows; unweighted is enough for a comparison).
double Difference(const GroundTruth& a, const GroundTruth& b) {
  double d = 0, norm = 0;
  for (size_t k = 0; k < a.value.size(); ++k) {
    for (int ch = 0; ch < 3; ++ch) {
      for (size_t i = 0; i < a.cells.size(); ++i) {
        d += std::pow(a.value[k][ch][i] - b.value[k][ch][i], 2);
        norm += std::pow(b.value[k][ch][i], 2);
      }
    }
  }
  return std::sqrt(d / norm);
}

TEST(GroundTruthTest, RowRotationOfAnIsotropicMaterialMatchesPerCellIntegration) {
  // A measured material (a network, importance-sampled by its half-vector proxy: a mixture whose
  // lobe choice once correlated with the sample points, a bias of 3.6% here that no sample count
  // removed) at order 4. Both methods are Monte Carlo estimates with independent samples; their
  // difference shrinks with the sample count like 1/sqrt(N) (below 1% of the coefficients' norm
  // at 16384 samples), which a wrong rotation (sign, index or azimuth average) or a biased
  // sampler could not: they leave a difference that does not shrink. On a grid of 4 x 8 deg cells
  // (12 rows, 15 of every row's 45 columns): the per-cell method's cost is per cell, and a wrong
  // rotation shows in every cell alike. Measured: 0.0087 and 0.00087 on the 2 x 4 deg grid (4x the
  // cells, 23 s of CPU instead of 6), 0.0086 and 0.00087 on this one.
  ZonalData layout = Layout(4);
  layout.grid = MakeExitantGrid(layout.zone(), 4.0, 8.0);
  const std::string spec = "merl:blue-acrylic";
  const auto isotropic = MakeBrdf(spec);
  ASSERT_TRUE(isotropic->IsIsotropic());
  const NotDeclaredIsotropic per_cell(MakeBrdf(spec));
  double previous = 1;
  for (int samples : {1024, 16384}) {
    GroundTruthOptions options;
    options.samples = samples;
    options.phi_stride = 3;
    const GroundTruth rotated = TrueZonalCoefficients(*isotropic, layout, options);
    const GroundTruth direct = TrueZonalCoefficients(per_cell, layout, options);
    ASSERT_EQ(rotated.cells, direct.cells);
    const double difference = Difference(rotated, direct);
    std::printf("%5d samples: rotated vs per-cell %.5f\n", samples, difference);
    EXPECT_LT(difference, previous / 2.5) << samples << " samples";  // 1/sqrt(16) = 1/4
    previous = difference;
  }
  EXPECT_LT(previous, 0.01);
}

TEST(GroundTruthTest, LambertianGivesTheSameTruthEitherWay) {
  // The product rule is deterministic, so the rotated and the per-cell truths of a Lambertian
  // agree to rounding (only its m = 0 functions are non-zero: the rotation must not leak).
  const ZonalData layout = Layout(6);
  const auto isotropic = MakeBrdf("lambert:0.4");
  const NotDeclaredIsotropic per_cell(MakeBrdf("lambert:0.4"));
  const GroundTruth rotated = TrueZonalCoefficients(*isotropic, layout);
  const GroundTruth direct = TrueZonalCoefficients(per_cell, layout);
  EXPECT_LT(Difference(rotated, direct), 1e-9);
}

TEST(GroundTruthTest, CacheReturnsWhatItStoredAndKeysOnTheMaterial) {
  const std::string dir = ::testing::TempDir() + "/zbrdf-truth-cache";
  std::filesystem::remove_all(dir);
  const ZonalData layout = Layout(2);
  GroundTruthOptions options;
  options.samples = 256;
  const auto a = MakeBrdf("ggx:alpha=0.3,F0=0.5,kd=0.1");
  const auto b = MakeBrdf("ggx:alpha=0.31,F0=0.5,kd=0.1");
  const GroundTruth computed = TrueZonalCoefficients(*a, layout, options);
  const GroundTruth first = TrueZonalCoefficientsCached(*a, layout, options, dir);
  const GroundTruth again = TrueZonalCoefficientsCached(*a, layout, options, dir);
  EXPECT_EQ(first.cells, computed.cells);
  EXPECT_EQ(again.value, computed.value);
  size_t entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) entries += e.is_regular_file();
  EXPECT_EQ(entries, 1u);
  const GroundTruth other = TrueZonalCoefficientsCached(*b, layout, options, dir);
  EXPECT_NE(other.value, computed.value);
  entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) entries += e.is_regular_file();
  EXPECT_EQ(entries, 2u);
  // A damaged entry is recomputed, not trusted.
  for (const auto& e : std::filesystem::directory_iterator(dir)) std::filesystem::resize_file(e.path(), 100);
  EXPECT_EQ(TrueZonalCoefficientsCached(*a, layout, options, dir).value, computed.value);
  std::filesystem::remove_all(dir);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
