// Tests of fitting/prior_fit.h against independent references: a material inside the prior's
// span recovered from its exact projection, the leave-one-out exclusion, the non-negative
// solver against the textbook Lawson-Hanson solver and against finite-difference optimality
// conditions, and the reported uncertainty's coverage under noise.
#include "fitting/prior_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "brdf/material_spec.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// The fast thesis zone; order 4 and a coarse grid keep each fit well under a second.
const Zone kZone(0.19722220547535926, 0.9581857593448869);
constexpr int kOrder = 4;

std::shared_ptr<const BrdfPrior> SmallPrior() {
  static const std::shared_ptr<const BrdfPrior> prior = [] {
    std::vector<PriorSource> sources;
    for (const std::string spec : {"ggx:alpha=0.08,F0=0.05,kd=0.1", "ggx:alpha=0.3,F0=0.5,kd=0",
                                   "blinn-phong:kd=0.3,ks=0.2,n=40", "ward:rho_d=0.05,rho_s=0.1,alpha=0.2",
                                   "retro:kd=0.2,kr=0.3,n=5"}) {
      std::shared_ptr<const Brdf> b = MakeBrdf(spec);
      sources.push_back({spec.substr(0, spec.find(',')), b, spec});
    }
    // Names (unique in a prior) are the specs up to their first comma.
    return std::make_shared<BrdfPrior>(BuildPrior(sources, HalfDiffGrid(20, 16, 8)));
  }();
  return prior;
}

const PriorFitter& Fitter() {
  static const PriorFitter fitter(kZone, kOrder, SmallPrior());
  return fitter;
}

// A table that is a known non-negative combination of the prior's atoms and the Lambertian.
std::vector<double> Combination(const std::vector<std::pair<int, double>>& atoms, double lambert) {
  const BrdfPrior& prior = *SmallPrior();
  std::vector<double> t(prior.grid.size(), lambert / M_PI);
  for (const auto& [a, w] : atoms) {
    for (int n = 0; n < prior.grid.size(); ++n) t[n] += w * prior.atoms(n, a);
  }
  return t;
}

// Zonal data whose isotropic coefficients are exactly the projection of the tables.
ZonalTensor ExactData(const std::array<std::vector<double>, 3>& tables, double relative_sigma) {
  const PriorFitter& fitter = Fitter();
  const IsotropicLayout layout(kOrder);
  ZonalTensor t;
  t.theta_min_rad = kZone.theta_min_rad();
  t.theta_max_rad = kZone.theta_max_rad();
  t.order = kOrder;
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXf v(tables[c].size());
    for (size_t n = 0; n < tables[c].size(); ++n) v[n] = static_cast<float>(tables[c][n]);
    const Eigen::VectorXd iso = (fitter.TableProjection() * v).cast<double>();
    t.z[c] = layout.Expand(iso);
    const double rms = std::sqrt(iso.squaredNorm() / iso.size());
    t.variance[c] = Eigen::MatrixXd::Constant(t.z[c].rows(), t.z[c].cols(),
                                               std::pow(relative_sigma * rms, 2));
  }
  return t;
}

double RelativeRms(const std::vector<Rgb>& fit, const std::array<std::vector<double>, 3>& truth) {
  double d = 0, n = 0;
  for (size_t k = 0; k < fit.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      d += std::pow(fit[k][c] - truth[c][k], 2);
      n += truth[c][k] * truth[c][k];
    }
  }
  return std::sqrt(d / n);
}

PriorFitOptions Plain() {
  PriorFitOptions o;
  o.pca_components = 0;
  o.replicates = 0;
  o.model_error_floor = 0.01;
  return o;
}

TEST(PriorFit, MaterialInsideThePriorsSpanIsRecoveredFromItsExactProjection) {
  // R: two atoms and a diffuse floor; G: one atom; B: atoms of other channels.
  const std::array<std::vector<double>, 3> truth = {
      Combination({{0, 0.6}, {7, 0.3}}, 0.1), Combination({{4, 1.2}}, 0.0),
      Combination({{2, 0.5}, {9, 0.2}}, 0.05)};
  const PriorFitResult r = Fitter().Fit(ExactData(truth, 1e-6), Plain());
  ASSERT_TRUE(r.fitted);
  // Exact data in the span: the only errors are float storage of the projection (1e-7 relative)
  // and the solver's ridge (1e-12 of the Gram trace), amplified by the conditioning of the atoms'
  // projections (nearby atoms are nearly collinear at order 4): 1e-4 is ample and still far below
  // what a wrong combination gives (the next test's leave-one-out error is > 1e-2).
  EXPECT_LT(RelativeRms(r.brdf->values(), truth), 1e-4);
  EXPECT_LT(r.statistics.relative_residual, 1e-5);
}

TEST(PriorFit, LeaveOneOutNeverUsesTheExcludedMaterial) {
  const BrdfPrior& prior = *SmallPrior();
  const std::string left_out = prior.materials[1];
  // The truth is exactly that material.
  const std::array<std::vector<double>, 3> truth = {Combination({{3, 1.0}}, 0),
                                                    Combination({{4, 1.0}}, 0),
                                                    Combination({{5, 1.0}}, 0)};
  const ZonalTensor data = ExactData(truth, 1e-6);
  const PriorFitResult with = Fitter().Fit(data, Plain());
  EXPECT_LT(RelativeRms(with.brdf->values(), truth), 1e-4);
  PriorFitOptions loo = Plain();
  loo.exclude = {left_out, "not-a-material"};
  const PriorFitResult without = Fitter().Fit(data, loo);
  EXPECT_EQ(without.excluded, std::vector<std::string>{left_out});  // unknown names ignored
  EXPECT_EQ(without.atoms_available, 3 * (prior.material_count() - 1) + 1);
  for (int c = 0; c < 3; ++c) {
    for (const auto& contribution : without.contributions[c]) {
      EXPECT_NE(contribution.material, left_out);
    }
  }
  // It really had to do without: the fit can no longer reproduce the material.
  EXPECT_GT(RelativeRms(without.brdf->values(), truth), 1e-2);
}

TEST(PriorFit, GramSolverMatchesLawsonHansonOnRandomProblems) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const int rows = 40, cols = 15;
    Eigen::MatrixXd a(rows, cols);
    Eigen::VectorXd b(rows);
    for (int i = 0; i < rows; ++i) {
      b[i] = normal(rng);
      for (int j = 0; j < cols; ++j) a(i, j) = normal(rng);
    }
    const Eigen::VectorXd reference = NonNegativeLeastSquares(a, b);
    const Eigen::VectorXd x = NonNegativeLeastSquaresGram(a.transpose() * a, a.transpose() * b);
    // Well-conditioned random problems: both solvers reach the unique minimizer; the normal
    // equations lose about cond(A)^2 * eps ~ 1e-13 relative.
    EXPECT_LT((x - reference).norm(), 1e-8 * std::max(1.0, reference.norm())) << trial;
  }
}

TEST(PriorFit, GramSolverSatisfiesTheOptimalityConditionsByFiniteDifferences) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  const int rows = 30, cols = 12;
  Eigen::MatrixXd a(rows, cols);
  Eigen::VectorXd b(rows);
  for (int i = 0; i < rows; ++i) {
    b[i] = normal(rng);
    for (int j = 0; j < cols; ++j) a(i, j) = normal(rng);
  }
  const Eigen::VectorXd x = NonNegativeLeastSquaresGram(a.transpose() * a, a.transpose() * b);
  auto objective = [&](const Eigen::VectorXd& v) { return 0.5 * (a * v - b).squaredNorm(); };
  int active = 0;
  for (int j = 0; j < cols; ++j) {
    EXPECT_GE(x[j], 0.0);
    const double h = 1e-6;
    Eigen::VectorXd up = x, down = x;
    up[j] += h;
    down[j] -= h;
    // Central difference of a quadratic: exact up to rounding, ~1e-9 here.
    const double gradient = (objective(up) - objective(down)) / (2 * h);
    if (x[j] > 0) {
      ++active;
      EXPECT_NEAR(gradient, 0.0, 1e-6) << j;  // stationary along free coordinates
    } else {
      EXPECT_GT(gradient, -1e-6) << j;        // no descent into the feasible set
    }
  }
  EXPECT_GT(active, 0);
  EXPECT_LT(active, cols);  // the test exercises both conditions
}

TEST(PriorFit, UncertaintyCoversTheTruthAtAboutItsStatedRate) {
  const std::array<std::vector<double>, 3> truth = {Combination({{0, 0.6}, {6, 0.4}}, 0.1),
                                                    Combination({{4, 0.8}, {10, 0.5}}, 0.05),
                                                    Combination({{8, 0.7}}, 0.2)};
  const ZonalTensor exact = ExactData(truth, 0.0);
  PriorFitOptions o = Plain();
  o.model_error_floor = 0.0;  // the variances are the whole error model here
  o.replicates = 24;
  o.replicate_atom_fraction = 1.0;  // noise only: the spread is the estimator's
  long covered = 0, total = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    ZonalTensor noisy = exact;
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> normal(0.0, 1.0);
    for (int c = 0; c < 3; ++c) {
      const double rms = std::sqrt(exact.z[c].squaredNorm() / exact.z[c].size());
      const double sigma = 0.003 * rms;
      noisy.variance[c].setConstant(sigma * sigma);
      for (int i = 0; i < noisy.z[c].rows(); ++i) {
        for (int j = 0; j < noisy.z[c].cols(); ++j) {
          if (exact.z[c](i, j) != 0) noisy.z[c](i, j) += sigma * normal(rng);
        }
      }
    }
    // Entries an isotropic BRDF leaves zero carry no noise: pooling +m and -m copies halves the
    // variance of the others, which the fit knows from IsotropicCoefficients.
    const PriorFitResult r = Fitter().Fit(noisy, o);
    const HalfDiffGrid& grid = r.brdf->grid();
    for (int n = 0; n < grid.size(); ++n) {
      if (!grid.NodeAboveHorizon(n)) continue;
      for (int c = 0; c < 3; ++c) {
        const double s = r.brdf->sigma()[n][c];
        if (!(s > 0)) continue;
        covered += std::abs(r.brdf->values()[n][c] - truth[c][n]) <= s;
        ++total;
      }
    }
  }
  const double rate = static_cast<double>(covered) / total;
  // Nominal 68.3% for a Gaussian error. The spread comes from 24 replicates (a 15% relative
  // standard error on sigma), the non-negativity bound makes the estimator slightly non-linear,
  // and nodes of one fit are correlated (few effective samples): [0.5, 0.85] rejects a spread
  // that is off by a factor of 1.5 either way.
  EXPECT_GT(rate, 0.5) << covered << " of " << total;
  EXPECT_LT(rate, 0.85) << covered << " of " << total;
}

TEST(PriorFit, SecondStageWithZeroWeightLeavesTheCombination) {
  const std::array<std::vector<double>, 3> truth = {Combination({{0, 0.6}}, 0.1),
                                                    Combination({{4, 1.2}}, 0.0),
                                                    Combination({{2, 0.5}}, 0.05)};
  const ZonalTensor data = ExactData(truth, 1e-4);
  PriorFitOptions zero_weight = Plain();
  zero_weight.pca_components = 5;
  zero_weight.pca_weight = 0.0;
  const PriorFitResult a = Fitter().Fit(data, Plain());
  const PriorFitResult b = Fitter().Fit(data, zero_weight);
  ASSERT_EQ(a.brdf->values().size(), b.brdf->values().size());
  for (size_t n = 0; n < a.brdf->values().size(); ++n) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(a.brdf->values()[n][c], b.brdf->values()[n][c],
                  1e-12 * (1 + a.brdf->values()[n][c]));
    }
  }
  // With weight 1 the table changes (the second stage does something) but stays non-negative.
  PriorFitOptions full = zero_weight;
  full.pca_weight = 1.0;
  const PriorFitResult c = Fitter().Fit(data, full);
  double change = 0;
  for (size_t n = 0; n < c.brdf->values().size(); ++n) {
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_GE(c.brdf->values()[n][ch], 0.0);
      change += std::abs(c.brdf->values()[n][ch] - a.brdf->values()[n][ch]);
    }
  }
  EXPECT_GT(change, 0.0);
}

TEST(PriorFit, DegenerateAndMalformedData) {
  const std::array<std::vector<double>, 3> zero = {Combination({}, 0), Combination({}, 0),
                                                   Combination({}, 0)};
  const PriorFitResult r = Fitter().Fit(ExactData(zero, 0.0), Plain());
  EXPECT_FALSE(r.fitted);
  EXPECT_FALSE(r.conditions.empty());
  ZonalTensor bad = ExactData({Combination({{0, 1}}, 0), Combination({{1, 1}}, 0),
                               Combination({{2, 1}}, 0)},
                              1e-3);
  bad.z[1](0, 0) = NAN;
  EXPECT_THROW(Fitter().Fit(bad, Plain()), InputError);
  ZonalTensor other_order = bad;
  other_order.order = kOrder + 1;
  EXPECT_THROW(Fitter().Fit(other_order, Plain()), InputError);
  PriorFitOptions o;
  o.pca_weight = 1.5;
  o.replicates = -1;
  try {
    o.Validate();
    FAIL() << "expected InvalidOptions";
  } catch (const InvalidOptions& e) {
    EXPECT_EQ(e.problems().size(), 2u) << e.what();
  }
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
