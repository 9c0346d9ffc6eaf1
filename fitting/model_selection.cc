#include "fitting/model_selection.h"

#include <cmath>
#include <cstdio>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/spherical_harmonics.h"

namespace zbrdf {

void ModelSelectionOptions::Validate() const {
  OptionChecker("ModelSelectionOptions")
      .InRange("folds", folds, 2, 16)
      .InRangeBelow("margin", margin, 0, 1)
      .ThrowIfInvalid();
}

ModelSelection SelectModel(const ZonalTensor& data, const std::vector<ModelCandidate>& candidates,
                           const ModelSelectionOptions& options) {
  options.Validate();
  const int folds = options.folds;
  if (const std::string problems = data.Problems(); !problems.empty()) {
    throw InputError("model selection: " + problems);
  }
  const int order = data.order, n = data.size();
  const IsotropicData truth = IsotropicCoefficients(data);
  const IsotropicLayout& layout = truth.layout;
  double largest = 0;
  for (int c = 0; c < 3; ++c) largest = std::max(largest, data.z[c].cwiseAbs().maxCoeff());
  const double ignored_variance = 1e30 * std::max(largest * largest, 1e-300);
  // Degree and signed order of each tensor index. The isotropic entries are (l, m), (l', m);
  // entries an isotropic BRDF leaves zero, (l, m), (l', -m) included, are kept in training.
  std::vector<int> degree(n), sh_order(n);
  for (int l = 0; l <= order; ++l) {
    for (int m = -l; m <= l; ++m) {
      degree[ShIndex(l, m)] = l;
      sh_order[ShIndex(l, m)] = m;
    }
  }
  ModelSelection selection;
  for (const ModelCandidate& candidate : candidates) {
    ModelSelection::Score score;
    score.name = candidate.name;
    double diff = 0, norm = 0;
    for (int fold = 0; fold < folds && score.failure.empty(); ++fold) {
      ZonalTensor train = data;
      for (int k = 0; k < n; ++k) {
        for (int j = 0; j < n; ++j) {
          if (sh_order[k] != sh_order[j]) continue;
          if (CrossValidationBlock(degree[k], degree[j], folds) != fold) continue;
          for (int c = 0; c < 3; ++c) train.variance[c](k, j) = ignored_variance;
        }
      }
      std::array<Eigen::VectorXd, 3> predicted;
      try {
        predicted = candidate.fit_and_predict(train);
      } catch (const InputError& e) {
        score.failure = e.what();
        break;
      }
      // Coefficients of another layout or not finite predict nothing; skipping them would score
      // as a perfect prediction.
      for (int c = 0; c < 3 && score.failure.empty(); ++c) {
        if (predicted[c].size() != layout.size() || !predicted[c].allFinite()) {
          score.failure = "predicted " + std::to_string(predicted[c].size()) +
                          " coefficients for channel " + std::to_string(c) + " (expected " +
                          std::to_string(layout.size()) + ", all finite)";
        }
      }
      if (!score.failure.empty()) break;
      double d = 0, t = 0;
      for (int m = 0; m <= order; ++m) {
        for (int l = m; l <= order; ++l) {
          for (int lp = m; lp <= order; ++lp) {
            if (CrossValidationBlock(l, lp, folds) != fold) continue;
            const int i = layout.Index(m, l, lp);
            for (int c = 0; c < 3; ++c) {
              d += std::pow(predicted[c][i] - truth.z[c][i], 2);
              t += truth.z[c][i] * truth.z[c][i];
            }
          }
        }
      }
      score.fold_errors.push_back(t > 0 ? std::sqrt(d / t) : 0.0);
      diff += d;
      norm += t;
    }
    score.cv_error = score.failure.empty() ? (norm > 0 ? std::sqrt(diff / norm) : 0.0) : INFINITY;
    selection.scores.push_back(score);
  }
  const ModelSelection::Score* best = nullptr;
  for (const auto& s : selection.scores) {
    if (s.failure.empty() && (!best || s.cv_error < best->cv_error)) best = &s;
  }
  if (!best) {
    selection.why = "no candidate could be fitted";
    return selection;
  }
  // The preferred candidate stays unless another beats it in every block and by the margin.
  std::string kept_because;
  for (const auto& s : selection.scores) {
    if (s.name != options.preferred || !s.failure.empty() || &s == best) continue;
    bool every_block = best->fold_errors.size() == s.fold_errors.size();
    for (size_t k = 0; every_block && k < s.fold_errors.size(); ++k) {
      every_block = best->fold_errors[k] < s.fold_errors[k];
    }
    const bool by_margin = best->cv_error <= (1 - options.margin) * s.cv_error;
    if (!every_block || !by_margin) {
      char reason[240];
      std::snprintf(reason, sizeof(reason),
                    "; %s predicts %.0f%% better but %s, so %s is kept: it extrapolates from "
                    "measured materials where the rig does not look",
                    best->name.c_str(), 100 * (1 - best->cv_error / s.cv_error),
                    !every_block ? "not in every held-out block"
                                 : "by less than the margin an analytic model must show",
                    s.name.c_str());
      kept_because = reason;
      best = &s;
    }
  }
  selection.recommended = best->name;
  char line[160];
  std::snprintf(line, sizeof(line), "%s predicts coefficients it was not fitted to with %.1f%% error",
                best->name.c_str(), 100 * best->cv_error);
  selection.why = line;
  std::string others;
  for (const auto& s : selection.scores) {
    if (&s == best) continue;
    if (s.failure.empty()) {
      std::snprintf(line, sizeof(line), "%s %.1f%%", s.name.c_str(), 100 * s.cv_error);
    } else {
      std::snprintf(line, sizeof(line), "%s could not be fitted", s.name.c_str());
    }
    others += (others.empty() ? "" : ", ") + std::string(line);
  }
  if (!others.empty()) selection.why += " (" + others + ")";
  selection.why += kept_because;
  return selection;
}

nlohmann::json ModelSelection::ToJson() const {
  nlohmann::json j;
  j["recommended"] = recommended;
  j["why"] = why;
  nlohmann::json list = nlohmann::json::array();
  for (const Score& s : scores) {
    nlohmann::json e = {{"model", s.name}, {"fold_errors", s.fold_errors}};
    e["cv_error"] = std::isfinite(s.cv_error) ? nlohmann::json(s.cv_error) : nlohmann::json(nullptr);
    if (!s.failure.empty()) e["failure"] = s.failure;
    list.push_back(e);
  }
  j["candidates"] = list;
  return j;
}

}  // namespace zbrdf
