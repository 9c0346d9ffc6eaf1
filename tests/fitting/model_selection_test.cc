#include "fitting/model_selection.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "basis/error.h"
#include "basis/spherical_harmonics.h"
#include "brdf/ggx.h"
#include "fitting/fit_data.h"
#include "fitting/fit_quadrature.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

const Zone kZone(0.19722220547535926, 0.9581857593448869);  // the fast thesis zone
constexpr int kOrder = 3;

using Coefficients = std::array<Eigen::VectorXd, 3>;

// The exact isotropic projection of a GGX material (fit_quadrature.h), computed once.
const Coefficients& Truth() {
  static const Coefficients truth =
      PairQuadrature(kZone, kOrder)
          .ProjectIsotropicBrdf(GgxBrdf(0.3, 0.3, Rgb(0.9, 0.5, 0.1), Rgb(0.1, 0.2, 0.3)));
  return truth;
}

// Noise-free data: the truth expanded to the full tensor, with a small variance everywhere
// (a per-channel sigma of 1e-3 of the largest coefficient).
ZonalTensor Data(const Coefficients& isotropic = Truth()) {
  ZonalTensor data;
  data.theta_min_rad = kZone.theta_min_rad();
  data.theta_max_rad = kZone.theta_max_rad();
  data.order = kOrder;
  const IsotropicLayout layout(kOrder);
  for (int c = 0; c < 3; ++c) {
    data.z[c] = layout.Expand(isotropic[c]);
    const double sigma = 1e-3 * data.z[c].cwiseAbs().maxCoeff();
    data.variance[c] = Eigen::MatrixXd::Constant(data.z[c].rows(), data.z[c].cols(), sigma * sigma);
  }
  return data;
}

ModelCandidate Returning(const std::string& name, const Coefficients& coefficients) {
  return {name, [coefficients](const ZonalTensor&) { return coefficients; }};
}

Coefficients Scaled(double factor) {
  Coefficients out = Truth();
  for (auto& v : out) v *= factor;
  return out;
}

// The truth with the entries of block k (of 4) scaled by factors[k]: each block's held-out error
// is |factors[k] - 1| exactly.
Coefficients BlockScaled(const std::array<double, 4>& factors) {
  Coefficients out = Truth();
  const IsotropicLayout layout(kOrder);
  for (int m = 0; m <= kOrder; ++m) {
    for (int l = m; l <= kOrder; ++l) {
      for (int lp = m; lp <= kOrder; ++lp) {
        for (auto& v : out) v[layout.Index(m, l, lp)] *= factors[CrossValidationBlock(l, lp, 4)];
      }
    }
  }
  return out;
}

// Degree and signed order of each tensor index.
void DegreeAndOrder(int index, int* l, int* m) {
  *l = static_cast<int>(std::sqrt(static_cast<double>(index)));
  *m = index - *l * *l - *l;
  ASSERT_EQ(ShIndex(*l, *m), index);
}

TEST(ModelSelectionTest, ExactCoefficientsWinOverZerosAndAScaledCopy) {
  const ModelSelection s =
      SelectModel(Data(), {Returning("zeros", Scaled(0.0)), Returning("exact", Truth()),
                           Returning("scaled", Scaled(1.1))});
  ASSERT_EQ(s.scores.size(), 3u);
  EXPECT_EQ(s.scores[0].name, "zeros");
  EXPECT_EQ(s.recommended, "exact");
  // Closed forms of sqrt(sum |prediction - z|^2 / sum |z|^2): 0, 1 and 0.1; the measured
  // coefficients are the +m / -m mean of equal copies (within an ulp of the truth).
  EXPECT_NEAR(s.scores[1].cv_error, 0.0, 1e-14);
  EXPECT_NEAR(s.scores[0].cv_error, 1.0, 1e-14);
  EXPECT_NEAR(s.scores[2].cv_error, 0.1, 1e-13);
  for (const ModelSelection::Score& score : s.scores) {
    EXPECT_TRUE(score.failure.empty()) << score.name;
    ASSERT_EQ(score.fold_errors.size(), 4u) << score.name;
  }
  for (int fold = 0; fold < 4; ++fold) {
    EXPECT_NEAR(s.scores[0].fold_errors[fold], 1.0, 1e-14);
    EXPECT_NEAR(s.scores[2].fold_errors[fold], 0.1, 1e-13);
  }
  EXPECT_NE(s.why.find("exact predicts"), std::string::npos) << s.why;
  EXPECT_NE(s.why.find("zeros 100.0%"), std::string::npos) << s.why;
  EXPECT_NE(s.why.find("scaled 10.0%"), std::string::npos) << s.why;
  const nlohmann::json j = s.ToJson();
  EXPECT_EQ(j["recommended"], "exact");
  ASSERT_EQ(j["candidates"].size(), 3u);
  EXPECT_EQ(j["candidates"][2]["model"], "scaled");
  EXPECT_NEAR(j["candidates"][2]["cv_error"].get<double>(), 0.1, 1e-13);
}

TEST(ModelSelectionTest, EachIsotropicEntryIsHeldOutInExactlyOneFold) {
  const ZonalTensor data = Data();
  const int n = data.size();
  for (const int folds : {2, 3, 4, 7, 16}) {
    std::vector<ZonalTensor> seen;
    const ModelCandidate recorder{"recorder", [&](const ZonalTensor& train) {
                                    seen.push_back(train);
                                    return Truth();
                                  }};
    const ModelSelection s = SelectModel(data, {recorder}, {.folds = folds});
    ASSERT_EQ(static_cast<int>(seen.size()), folds);
    double largest = 0;
    for (int c = 0; c < 3; ++c) largest = std::max(largest, data.z[c].cwiseAbs().maxCoeff());
    for (int k = 0; k < n; ++k) {
      for (int j = 0; j < n; ++j) {
        int l, m, lp, mp;
        DegreeAndOrder(k, &l, &m);
        DegreeAndOrder(j, &lp, &mp);
        // The isotropic entries z_(l,m),(l',m) (fit_data.h); the others an isotropic BRDF
        // leaves zero, and they are never held out.
        const bool isotropic = m == mp;
        int held_out = 0;
        for (int fold = 0; fold < folds; ++fold) {
          const ZonalTensor& train = seen[fold];
          const bool in_block = isotropic && CrossValidationBlock(l, lp, folds) == fold;
          for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(train.z[c](k, j), data.z[c](k, j));
            if (in_block) {
              // "1e30 times the tensor's largest square": weight 1e-30 of the others' at most
              // (relative to the data's variances of 1e-6 of that square, 1e-36).
              EXPECT_GE(train.variance[c](k, j), 1e29 * largest * largest);
            } else {
              EXPECT_EQ(train.variance[c](k, j), data.variance[c](k, j))
                  << folds << " folds, fold " << fold << ": (" << l << "," << m << "),(" << lp
                  << "," << mp << ")";
            }
          }
          held_out += in_block;
        }
        EXPECT_EQ(held_out, isotropic ? 1 : 0);
      }
    }
    EXPECT_EQ(s.recommended, "recorder");
    EXPECT_NEAR(s.scores[0].cv_error, 0.0, 1e-14);
  }
}

TEST(ModelSelectionTest, HeldOutEntriesCarryNoWeight) {
  // The data of block 1 (of 4) are twice the truth. A candidate fitting one scale factor to its
  // training tensor by weighted least squares, s = sum(t z / v) / sum(t^2 / v) over every entry
  // with t the truth's shape, finds s = 1 when block 1 is held out, if and only if the held-out
  // entries carry no weight: block 1's error is then |t - 2 t| / |2 t| = 1/2 exactly. (Weights of
  // 1e-30 move s by ~1e-30.)
  const int folds = 4, fold = 1;
  const IsotropicLayout layout(kOrder);
  Coefficients data_iso = Truth();
  for (int m = 0; m <= kOrder; ++m) {
    for (int l = m; l <= kOrder; ++l) {
      for (int lp = m; lp <= kOrder; ++lp) {
        if (CrossValidationBlock(l, lp, folds) != fold) continue;
        for (int c = 0; c < 3; ++c) data_iso[c][layout.Index(m, l, lp)] *= 2;
      }
    }
  }
  const ModelCandidate scale_fit{"scale", [&](const ZonalTensor& train) {
                                   Coefficients out;
                                   for (int c = 0; c < 3; ++c) {
                                     const Eigen::MatrixXd t = layout.Expand(Truth()[c]);
                                     const Eigen::ArrayXXd w = train.variance[c].array().inverse();
                                     const double s = (t.array() * train.z[c].array() * w).sum() /
                                                      (t.array() * t.array() * w).sum();
                                     out[c] = s * Truth()[c];
                                   }
                                   return out;
                                 }};
  const ModelSelection s = SelectModel(Data(data_iso), {scale_fit}, {.folds = folds});
  ASSERT_EQ(s.scores[0].fold_errors.size(), 4u);
  EXPECT_NEAR(s.scores[0].fold_errors[fold], 0.5, 1e-12);
  // The other folds see block 1's doubled data in training: s > 1 there.
  EXPECT_GT(s.scores[0].fold_errors[0], 1e-3);
}

TEST(ModelSelectionTest, FailingCandidatesAreReportedAndTheOthersRanked) {
  const ModelCandidate throwing{"diverges", [](const ZonalTensor&) -> Coefficients {
                                  throw InputError("the solver diverged at iteration 7");
                                }};
  const ModelSelection s = SelectModel(
      Data(), {throwing, Returning("zeros", Scaled(0.0)), Returning("close", Scaled(0.98))});
  ASSERT_EQ(s.scores.size(), 3u);
  EXPECT_NE(s.scores[0].failure.find("the solver diverged at iteration 7"), std::string::npos)
      << s.scores[0].failure;
  EXPECT_TRUE(std::isinf(s.scores[0].cv_error));
  EXPECT_EQ(s.recommended, "close");
  EXPECT_NEAR(s.scores[2].cv_error, 0.02, 1e-13);
  EXPECT_NE(s.why.find("diverges could not be fitted"), std::string::npos) << s.why;
  const nlohmann::json j = s.ToJson();
  EXPECT_TRUE(j["candidates"][0]["cv_error"].is_null());
  EXPECT_EQ(j["candidates"][0]["failure"], s.scores[0].failure);
  EXPECT_FALSE(j["candidates"][1].contains("failure"));

  const ModelSelection none = SelectModel(Data(), {throwing});
  EXPECT_EQ(none.recommended, "");
  EXPECT_EQ(none.why, "no candidate could be fitted");
}

TEST(ModelSelectionTest, CandidatesReturningNonsenseFailInsteadOfWinning) {
  // Coefficients that are not numbers, or not of the data's layout, predict nothing: they must
  // not count as a perfect prediction.
  Coefficients nan = Truth();
  nan[1][2] = std::nan("");
  Coefficients short_vector = Truth();
  short_vector[0].conservativeResize(short_vector[0].size() - 1);
  const ModelSelection s =
      SelectModel(Data(), {Returning("nan", nan), Returning("short", short_vector),
                           Returning("empty", Coefficients{}), Returning("close", Scaled(0.9))});
  ASSERT_EQ(s.scores.size(), 4u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_FALSE(s.scores[k].failure.empty()) << s.scores[k].name;
    EXPECT_TRUE(std::isinf(s.scores[k].cv_error)) << s.scores[k].name;
  }
  EXPECT_EQ(s.recommended, "close");
}

TEST(ModelSelectionTest, FoldsOutsideTheRangeAndMalformedDataThrow) {
  const std::vector<ModelCandidate> candidates = {Returning("exact", Truth())};
  for (const int folds : {-3, 0, 1, 17}) {
    EXPECT_THROW(SelectModel(Data(), candidates, {.folds = folds}), InputError) << folds;
  }
  EXPECT_NO_THROW(SelectModel(Data(), candidates, {.folds = 2}));
  EXPECT_NO_THROW(SelectModel(Data(), candidates, {.folds = 16}));
  for (const double margin : {-0.1, 1.0, std::nan("")}) {
    EXPECT_THROW(SelectModel(Data(), candidates, {.margin = margin}), InputError) << margin;
  }
  ZonalTensor bad = Data();
  bad.variance[1](2, 3) = -1;
  EXPECT_THROW(SelectModel(bad, candidates), InputError);
  bad = Data();
  bad.z[2](0, 0) = std::nan("");
  EXPECT_THROW(SelectModel(bad, candidates), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// The preferred candidate (the prior in zbrdf fit) is kept unless another predicts every block
// better and its error is at most (1 - margin) of the preferred one's.
TEST(ModelSelectionTest, PreferredCandidateIsReplacedOnlyByOneBetterInEveryBlockByTheMargin) {
  const ModelSelectionOptions prefer{.preferred = "prior", .margin = 0.25};
  const ModelCandidate prior = Returning("prior", Scaled(1.2));  // 20% in every block

  // Better in every block, 10% against 20%: beyond the margin (15%), replaced.
  ModelSelection s = SelectModel(Data(), {prior, Returning("ggx", Scaled(1.1))}, prefer);
  EXPECT_EQ(s.recommended, "ggx") << s.why;
  EXPECT_EQ(s.why.find("kept"), std::string::npos) << s.why;

  // Better in every block but within the margin (16% against 20%): kept.
  s = SelectModel(Data(), {prior, Returning("ggx", Scaled(1.16))}, prefer);
  EXPECT_EQ(s.recommended, "prior") << s.why;
  EXPECT_NE(s.why.find("prior predicts coefficients it was not fitted to with 20.0% error"),
            std::string::npos) << s.why;
  EXPECT_NE(s.why.find("ggx 16.0%"), std::string::npos) << s.why;
  EXPECT_NE(s.why.find("by less than the margin"), std::string::npos) << s.why;

  // Far better overall (exact in three blocks) but worse in one: kept.
  const std::array<double, 4> three_exact{1.0, 1.0, 1.0, 1.25};
  s = SelectModel(Data(), {Returning("dbrdf", BlockScaled(three_exact)), prior}, prefer);
  ASSERT_EQ(s.scores.size(), 2u);
  EXPECT_LT(s.scores[0].cv_error, 0.75 * s.scores[1].cv_error);
  EXPECT_NEAR(s.scores[0].fold_errors[3], 0.25, 1e-13);
  EXPECT_NEAR(s.scores[0].fold_errors[0], 0.0, 1e-13);
  EXPECT_EQ(s.recommended, "prior") << s.why;
  EXPECT_NE(s.why.find("not in every held-out block"), std::string::npos) << s.why;

  // Without a preference the lowest error wins.
  s = SelectModel(Data(), {Returning("dbrdf", BlockScaled(three_exact)), prior});
  EXPECT_EQ(s.recommended, "dbrdf");

  // A preferred candidate that cannot be fitted is no obstacle.
  const ModelCandidate failing{"prior", [](const ZonalTensor&) -> Coefficients {
                                 throw InputError("no prior");
                               }};
  s = SelectModel(Data(), {failing, Returning("ggx", Scaled(1.16))}, prefer);
  EXPECT_EQ(s.recommended, "ggx");
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
