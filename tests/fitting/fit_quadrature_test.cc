#include "fitting/fit_quadrature.h"

#include <gtest/gtest.h>

#include <span>
#include <vector>

#include "basis/error.h"
#include "basis/projection.h"
#include "brdf/dbrdf.h"
#include "brdf/ggx.h"
#include "brdf/lambertian.h"
#include "fitting/fit_common.h"
#include "tests/fitting/fit_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

const Zone kZone = Zone::FromDegrees(11.3, 54.9);  // the thesis rig at the fast preset

double RelativeError(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).norm() / b.norm(); }

DBrdfParams GgxShapedDBrdf(double alpha_x, double alpha_y, int theta_samples, int phi_samples) {
  return testing::GgxShapedDBrdf(alpha_x, alpha_y, theta_samples, phi_samples, Rgb(0.7, 0.8, 0.9), 0.3, Rgb(0.2, 0.1, 0.05));
}

TEST(PairQuadratureTest, LambertianMatchesTheSeparableProjection) {
  // f^ = rho / pi cos(theta_i) separates: z_kj = (integral Z_k cos / pi) (integral Z_j) rho.
  const int order = 6;
  const PairQuadrature q(kZone, order);
  const LambertianBrdf lambert(Rgb(0.5, 0.25, 0.125));
  const auto iso = q.ProjectIsotropicBrdf(lambert);
  const ZonalBasis zb(kZone, order);
  const Eigen::VectorXd a = ProjectOntoZonalBasis(zb, [](const Vec3& w) { return w.z / M_PI; }, 60, 32);
  const Eigen::VectorXd b = ProjectOntoZonalBasis(zb, [](const Vec3&) { return 1.0; }, 60, 32);
  for (int ch = 0; ch < 3; ++ch) {
    const Eigen::MatrixXd expected = lambert.albedo()[ch] * a * b.transpose();
    // Both are exact rules for these integrands (psi Gauss nodes, exact azimuthal harmonics), so
    // only rounding differs: sums over ~4e5 nodes in which the terms cos(m Delta), m > 0, cancel
    // (measured 4.5e-12).
    EXPECT_LT(RelativeError(IsotropicLayout(order).Expand(iso[ch]), expected), 1e-10);
  }
}

TEST(PairQuadratureTest, IsotropicTableProjectionMatchesBruteForce) {
  const int order = 6;
  const PairQuadrature q(kZone, order);
  const DBrdfParams params = GgxShapedDBrdf(0.4, 0.4, 91, 1);
  const DBrdfProjection projection = ProjectDBrdfTable(q, 91, 1);
  ASSERT_TRUE(projection.isotropic);
  const auto model = DBrdfTensor(projection, params, order);
  // The brute-force product rule converges like O(h^2) on the table's kinks: 1.4e-5 at 32 x 64
  // nodes per direction and 1.7e-5 at 48 x 96 (it is the reference that moves), so 1e-4 bounds
  // the half-vector rule's own error with margin.
  const auto reference = testing::BruteForceTensor(DBrdf(params), kZone, order, 40, 80);
  for (int ch = 0; ch < 3; ++ch) EXPECT_LT(RelativeError(model[ch], reference[ch]), 1e-4) << ch;
  // The same through the BRDF's own Eval at the nodes: the table decomposition is exact.
  const auto through_eval = q.ProjectIsotropicBrdf(DBrdf(params));
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_LT(RelativeError(IsotropicLayout(order).Expand(through_eval[ch]), model[ch]), 1e-11);
  }
}

TEST(PairQuadratureTest, AnisotropicPathWithEqualPhiValuesEqualsTheIsotropicOne) {
  // sum_k phi-hat_k = 1, so a 2-D table constant in phi is the 1-D table: two independent code
  // paths (harmonic coupling vs. the block-diagonal shortcut) must agree to rounding.
  const int order = 5;
  const PairQuadrature q(kZone, order);
  const DBrdfParams iso = GgxShapedDBrdf(0.3, 0.3, 46, 1);
  DBrdfParams aniso = iso;
  aniso.p_h.phi_samples = 6;
  aniso.p_h.p.clear();
  for (double v : iso.p_h.p) aniso.p_h.p.insert(aniso.p_h.p.end(), 6, v);
  const auto a = DBrdfTensor(ProjectDBrdfTable(q, 46, 6), aniso, order);
  const auto b = DBrdfTensor(ProjectDBrdfTable(q, 46, 1), iso, order);
  for (int ch = 0; ch < 3; ++ch) EXPECT_LT(RelativeError(a[ch], b[ch]), 1e-12);
}

TEST(PairQuadratureTest, AnisotropicTableProjectionMatchesBruteForce) {
  const int order = 5;
  const PairQuadrature q(kZone, order);
  const DBrdfParams params = GgxShapedDBrdf(0.25, 0.5, 46, 8);
  const auto model = DBrdfTensor(ProjectDBrdfTable(q, 46, 8), params, order);
  const auto reference = testing::BruteForceTensor(DBrdf(params), kZone, order, 40, 80);
  // The data are anisotropic: entries off the isotropic blocks carry energy.
  IsotropyReport report = AnalyzeIsotropy(testing::SyntheticData(reference, kZone, order));
  EXPECT_GT(report.anisotropic_energy_fraction, kAnisotropyThreshold);
  // Measured 7e-5 at 32 x 64 and 3e-5 at 48 x 96 reference nodes (the reference converging).
  for (int ch = 0; ch < 3; ++ch) EXPECT_LT(RelativeError(model[ch], reference[ch]), 1.5e-4) << ch;
}

TEST(PairQuadratureTest, GgxProjectionMatchesBruteForce) {
  const int order = 6;
  const GgxBrdf ggx(0.2, 0.2, Rgb(0.9, 0.5, 0.1), Rgb(0.1));
  const auto reference = testing::BruteForceTensor(ggx, kZone, order, 48, 96);
  for (int cells : {90, 30}) {  // the D-BRDF's and the analytic fits' rules
    const PairQuadrature q(kZone, order, {0, cells, 4});
    const auto iso = q.ProjectIsotropicBrdf(ggx);
    for (int ch = 0; ch < 3; ++ch) {
      // GGX is smooth: the reference converges fast; both rules agree with it to 1e-5.
      EXPECT_LT(RelativeError(IsotropicLayout(order).Expand(iso[ch]), reference[ch]), 1e-5)
          << "cells " << cells << " channel " << ch;
    }
  }
}

TEST(PairQuadratureTest, ProjectingSeveralFunctionsAtOnceGivesEachWhatItGetsAlone) {
  // One pass over the nodes for several functions (the channels of a BRDF, the analytic fits'
  // F0 = 0 and F0 = 1 models) sums each as ProjectIsotropic does: equal bit for bit.
  const int order = 5;
  const PairQuadrature q(kZone, order);
  const GgxBrdf ggx(0.3, 0.3, Rgb(0.0, 1.0, 0.5), Rgb(0.1, 0.0, 0.2));
  std::vector<std::vector<double>> g(3, std::vector<double>(q.size()));
  for (int p = 0; p < q.theta_nodes() * q.theta_nodes(); ++p) {
    for (int s = q.PairSegmentBegin(p); s < q.PairSegmentBegin(p + 1); ++s) {
      for (int64_t i = q.segments()[s].begin; i < q.segments()[s].end; ++i) {
        Vec3 w_i, w_r;
        q.Directions(p, q.nodes()[i], &w_i, &w_r);
        const Rgb f = ggx.Eval(w_i, w_r);
        for (int ch = 0; ch < 3; ++ch) g[ch][i] = f[ch] * w_i.z;
      }
    }
  }
  const std::vector<std::span<const double>> spans(g.begin(), g.end());
  const std::vector<Eigen::VectorXd> together = q.ProjectIsotropicAll(spans);
  const auto brdf = q.ProjectIsotropicBrdf(ggx);
  ASSERT_EQ(together.size(), 3u);
  for (int ch = 0; ch < 3; ++ch) {
    const Eigen::VectorXd alone = q.ProjectIsotropic(g[ch]);
    EXPECT_EQ(together[ch], alone) << "channel " << ch;
    EXPECT_EQ(brdf[ch], alone) << "channel " << ch;
    EXPECT_GT(alone.norm(), 0) << "channel " << ch;
  }
}

TEST(PairQuadratureTest, RejectsBadOptions) {
  EXPECT_THROW(PairQuadrature(kZone, 31), InputError);
  EXPECT_THROW(PairQuadrature(kZone, 4, {0, 0, 4}), InputError);
  const PairQuadrature q(kZone, 2, {0, 90, 2});
  EXPECT_THROW(ProjectDBrdfTable(q, 8, 1), InputError);  // 7 does not divide 90
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
