// Two BRDFs side by side (`zbrdf compare`, `zbrdf report`): both balls rendered with the same
// light, camera and pixel samples (so that their noise is correlated and the difference shows
// the materials, not the sampling), a difference image, and error metrics: the RMSE of the
// renders and the cosine-weighted L2 between the BRDFs (brdf_metrics.h).
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "brdf/brdf.h"
#include "brdf/brdf_metrics.h"
#include "pictures/environment.h"
#include "pictures/material_ball.h"

namespace zbrdf {

struct MaterialComparison {
  BallImage a, b;
  double rmse = 0;           // linear RGB, over pixels where both see the ball
  double relative_rmse = 0;  // rmse / RMS of a's pixels
  BrdfDistance distance;
  cv::Mat side_by_side;  // a | b | difference, tone-mapped (8-bit BGR)
  cv::Mat difference;    // |Y_a - Y_b| / max Y_a over the ball, inferno color map
  nlohmann::json ToJson() const;
};

MaterialComparison CompareMaterials(const Brdf& a, const Brdf& b, const Environment* env,
                                    const BallOptions& options, double exposure_ev,
                                    int64_t metric_samples);

}  // namespace zbrdf
