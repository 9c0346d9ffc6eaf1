// Choosing among fitted models by how well each predicts coefficients it was not fitted to
// (`zbrdf fit --model auto`, docs/prior.md).
//
// The isotropic coefficients (fit_data.h) are split into `folds` blocks by the diagonal of their
// degrees, block = (l + l') mod folds: each block holds every band of the zone's basis, so a
// model must interpolate across frequencies rather than fill in neighbours of the same one. For
// each block a candidate is fitted to the tensor with that block's entries given a variance so
// large (1e30 times the tensor's largest square) that they carry no weight, and predicts them.
// The cross-validated error is sqrt(sum over blocks of |prediction - z|^2 / sum |z|^2), all
// channels: in-zone predictive accuracy, in the measured quantity. The candidate with the
// lowest error is recommended, with one exception. A model that explains the zone can still be
// wrong where the rig does not look, and cross-validation over the zone cannot see that. A
// `preferred` candidate (zbrdf fit: the prior, whose extrapolation is bounded by measured
// materials, while GGX's Schlick Fresnel and the D-BRDF's lobe extrapolate without bound) is
// kept unless another one predicts EVERY held-out block better AND its error is at most (1 -
// margin) times the preferred one's: evidence that the material lies outside what the
// preferred model can represent. Measured on the simulated thesis rig (order 8, MERL leave-one-
// out, 76 materials): the plain lowest-error rule picked GGX or the D-BRDF for 7, and 6 of those
// were worse than the prior over the hemisphere (black-phenolic 30x, grease-covered-steel 8.6x);
// their CV errors were 1-32% lower than the prior's and better in only 1-2 of 4 blocks
// (docs/prior.md). Candidates may report how much they extrapolate (the prior's uncertainty),
// and the recommendation's text says so.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "fitting/fit_data.h"

namespace zbrdf {

struct ModelCandidate {
  std::string name;
  // Fits `train` and returns the model's isotropic coefficients (IsotropicLayout of the data's
  // order) per channel. May throw InputError; the candidate is then reported as failed.
  std::function<std::array<Eigen::VectorXd, 3>(const ZonalTensor& train)> fit_and_predict;
};

struct ModelSelection {
  struct Score {
    std::string name;
    double cv_error = 0;              // relative, all held-out entries and channels
    std::vector<double> fold_errors;  // per block
    std::string failure;              // non-empty when the candidate could not be fitted
  };
  std::vector<Score> scores;          // in the candidates' order
  std::string recommended;            // empty if every candidate failed
  std::string why;                    // one sentence for people
  nlohmann::json ToJson() const;
};

// The block of isotropic entry (l, l') for `folds` blocks.
inline int CrossValidationBlock(int l, int l_prime, int folds) { return (l + l_prime) % folds; }

struct ModelSelectionOptions {
  int folds = 4;           // in [2, 16]
  std::string preferred{}; // a candidate's name, or empty: the lowest error wins
  double margin = 0.25;    // in [0, 1): how much lower another's error must be to replace it

  // Throws InvalidOptions (an InputError) naming every field out of range.
  void Validate() const;
};

// Throws InputError for bad options or malformed data.
ModelSelection SelectModel(const ZonalTensor& data, const std::vector<ModelCandidate>& candidates,
                           const ModelSelectionOptions& options = {});

}  // namespace zbrdf
