#include "basis/gram.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "basis/legendre.h"
#include "basis/quadrature.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using LD = long double;

LD FactorialL(int n) {
  LD f = 1;
  for (int k = 2; k <= n; ++k) f *= k;
  return f;
}

// Wigner 3j symbol by the Racah formula, in long double. Independent of everything in basis/.
LD Wigner3j(int j1, int j2, int j3, int m1, int m2, int m3) {
  if (m1 + m2 + m3 != 0) return 0;
  if (j3 < std::abs(j1 - j2) || j3 > j1 + j2) return 0;
  if (std::abs(m1) > j1 || std::abs(m2) > j2 || std::abs(m3) > j3) return 0;
  const LD delta = FactorialL(j1 + j2 - j3) * FactorialL(j1 - j2 + j3) *
                   FactorialL(-j1 + j2 + j3) / FactorialL(j1 + j2 + j3 + 1);
  const LD front = std::sqrt(delta * FactorialL(j1 + m1) * FactorialL(j1 - m1) *
                             FactorialL(j2 + m2) * FactorialL(j2 - m2) * FactorialL(j3 + m3) *
                             FactorialL(j3 - m3));
  LD sum = 0;
  for (int k = 0; k <= j1 + j2 + j3; ++k) {
    const int args[6] = {k, j3 - j2 + k + m1, j3 - j1 + k - m2, j1 + j2 - j3 - k, j1 - k - m1,
                         j2 - k + m2};
    bool valid = true;
    for (int a : args) valid = valid && a >= 0;
    if (!valid) continue;
    LD denom = 1;
    for (int a : args) denom *= FactorialL(a);
    sum += (k % 2 == 0 ? 1 : -1) / denom;
  }
  const int phase_exp = j1 - j2 - m3;
  return ((phase_exp % 2 == 0) ? 1 : -1) * front * sum;
}

// Polar-cap kernel D_ll'(m; x0) = integral over {cos theta >= x0} of Y_lm Y_l'm, from the
// Gaunt expansion Y_lm Y*_l'm = sum_n c_n Y_n0 and integral_{x0}^1 P_n = (P_{n-1} - P_{n+1})/(2n+1)
// (Simons, Dahlen & Wieczorek 2006, section 4).
LD CapKernel(int l, int l2, int m, LD x0) {
  const int n_max = l + l2;
  std::vector<LD> p(n_max + 2);
  p[0] = 1;
  p[1] = x0;
  for (int n = 1; n <= n_max; ++n) p[n + 1] = ((2 * n + 1) * x0 * p[n] - n * p[n - 1]) / (n + 1);
  LD sum = 0;
  for (int n = std::abs(l - l2); n <= n_max; ++n) {
    const LD integral = n == 0 ? 1 - x0 : (p[n - 1] - p[n + 1]) / (2 * n + 1);
    sum += (2 * n + 1) / 2.0L * Wigner3j(l, l2, n, 0, 0, 0) * Wigner3j(l, l2, n, m, -m, 0) *
           integral;
  }
  return ((m % 2 == 0) ? 1 : -1) * std::sqrt(static_cast<LD>((2 * l + 1) * (2 * l2 + 1))) * sum;
}

TEST(Gram, ShGramOnAZoneIsTheDifferenceOfTwoPolarCapKernels) {
  for (auto [min_deg, max_deg] : {std::pair{9.0, 57.0}, {9.0, 90.0}, {40.0, 45.0}, {0.0, 30.0}}) {
    const Zone zone = Zone::FromDegrees(min_deg, max_deg);
    constexpr int kL = 10;
    const TargetBasis sh(TargetKind::kSh, kL);
    double worst = 0;
    for (int m = 0; m <= kL; ++m) {
      const Eigen::MatrixXd g = TargetGramBlock(sh, zone, m);
      for (int i = 0; i < g.rows(); ++i) {
        for (int j = 0; j < g.cols(); ++j) {
          const LD reference = CapKernel(m + i, m + j, m, std::cos((LD)zone.theta_max_rad())) -
                               CapKernel(m + i, m + j, m, std::cos((LD)zone.theta_min_rad()));
          worst = std::max(worst, std::abs(g(i, j) - static_cast<double>(reference)));
        }
      }
    }
    EXPECT_LE(worst, 1e-14) << zone.ToString();
  }
}

TEST(Gram, CapKernelReferenceIsTheIdentityOnTheSphere) {
  // Guards the reference itself: the cap of the whole sphere gives orthonormality.
  for (int m = 0; m <= 4; ++m) {
    for (int l = m; l <= 8; ++l) {
      for (int l2 = m; l2 <= 8; ++l2) {
        EXPECT_NEAR(static_cast<double>(CapKernel(l, l2, m, -1.0L)), l == l2 ? 1.0 : 0.0, 1e-15);
      }
    }
  }
}

double TraceOfGram(const TargetBasis& target, const Zone& zone) {
  double trace = 0;
  for (int m = 0; m <= target.order(); ++m) {
    trace += (m == 0 ? 1 : 2) * TargetGramBlock(target, zone, m).trace();
  }
  return trace;
}

TEST(Gram, TraceIsTheShannonNumber) {
  for (int order : {2, 6, 10, 20}) {
    for (auto [min_deg, max_deg] : {std::pair{9.0, 57.0}, {9.0, 90.0}}) {
      const Zone zone = Zone::FromDegrees(min_deg, max_deg);
      const double shannon =
          (order + 1.0) * (order + 1.0) * (zone.cos_upper() - zone.cos_lower()) / 2;
      EXPECT_NEAR(TraceOfGram(TargetBasis(TargetKind::kSh, order), zone), shannon, 1e-12 * shannon);
    }
  }
}

double Condition(const TargetBasis& target, const Zone& zone) {
  double lo = INFINITY, hi = 0;
  for (int m = 0; m <= target.order(); ++m) {
    const Eigen::MatrixXd g = TargetGramBlock(target, zone, m);
    if (g.size() == 0) continue;
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(g);
    lo = std::min(lo, eig.eigenvalues().minCoeff());
    hi = std::max(hi, eig.eigenvalues().maxCoeff());
  }
  return hi / lo;
}

TEST(Gram, ConditionNumbersMatchDesignNotes) {
  // docs/design.md section 3, items 1 and 4 (two significant digits given there).
  const Zone built = Zone::FromDegrees(9, 57), designed = Zone::FromDegrees(9, 90);
  EXPECT_NEAR(Condition(TargetBasis(TargetKind::kSh, 2), built) / 3e4, 1.0, 0.2);
  EXPECT_NEAR(Condition(TargetBasis(TargetKind::kSh, 4), built) / 1e9, 1.0, 0.5);
  const double designed_expected[] = {254, 1.6e5, 1.3e8, 1.2e11, 1.2e14};
  for (int i = 0; i < 5; ++i) {
    const int order = 2 * (i + 1);
    EXPECT_NEAR(Condition(TargetBasis(TargetKind::kSh, order), designed) / designed_expected[i],
                1.0, 0.1)
        << "order " << order;
  }
  EXPECT_NEAR(Condition(TargetBasis(TargetKind::kShEven, 10), designed), 2.3, 0.1);
  EXPECT_NEAR(Condition(TargetBasis(TargetKind::kShEven, 14), designed), 4.3, 0.1);
}

TEST(Gram, MixedBlockConvergesInPsiAndMatchesGaussInCosThetaForEvenM) {
  const Zone zone = Zone::FromDegrees(9, 57);
  for (int order : {4, 10, 14}) {
    const ZonalBasis zb(zone, order);
    const TargetBasis sh(TargetKind::kSh, order);
    const int nodes = DefaultPsiNodes(order, order);
    for (int m = 0; m <= order; ++m) {
      const Eigen::MatrixXd b = MixedBlock(sh, zb, m, nodes);
      const Eigen::MatrixXd b2 = MixedBlock(sh, zb, m, 2 * nodes);
      EXPECT_LE((b - b2).cwiseAbs().maxCoeff(), 1e-15) << "order " << order << " m " << m;
      if (m % 2 == 0) {
        // Even m: Y x Z is a polynomial of degree <= 2L in cos(theta); Gauss in x is exact.
        const CosThetaRule rule = CosThetaGaussRule(zone, order + 2);
        Eigen::MatrixXd exact = Eigen::MatrixXd::Zero(b.rows(), b.cols());
        std::vector<double> f(b.rows()), z(LegendreCount(order));
        for (size_t q = 0; q < rule.x.size(); ++q) {
          sh.EvalThetaFactor(m, rule.x[q], rule.s_x[q], f.data());
          zb.EvalThetaPart(rule.x[q], z.data());
          for (int i = 0; i < b.rows(); ++i) {
            for (int j = 0; j < b.cols(); ++j) {
              exact(i, j) += 2 * M_PI * rule.weight[q] * f[i] * z[LegendreIndex(m + j, m)];
            }
          }
        }
        EXPECT_LE((b - exact).cwiseAbs().maxCoeff(), 1e-14) << "order " << order << " m " << m;
      }
    }
  }
}

TEST(Gram, ZonalBasisGramIsIdentityBlockwise) {
  // The ZB is its own target on the zone [0, 90] (HSH): Gram blocks are identities.
  const Zone hemisphere = Zone::FromDegrees(0, 90);
  const TargetBasis hsh(TargetKind::kHsh, 12);
  for (int m = 0; m <= 12; ++m) {
    const Eigen::MatrixXd g = TargetGramBlock(hsh, hemisphere, m);
    EXPECT_LE((g - Eigen::MatrixXd::Identity(g.rows(), g.cols())).cwiseAbs().maxCoeff(), 1e-14);
  }
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
