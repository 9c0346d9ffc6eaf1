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

// The relative RMSE of two BRDFs' balls without the Monte Carlo noise of the renders, which at
// preview sample counts can be most of MaterialComparison::relative_rmse (a fit and its truth
// that look alike read 20% at 32 spp under the sky). A second render of each ball with an
// independent seed (A2, B2 beside A1 = a1, B1 = b1; rendered here if not given) makes the
// noise measurable: for independent renders E|X - Y|^2 = |x - y|^2 + var X + var Y and
// E|X1 - X2|^2 = 2 var X, so over the pixels both see (means over pixels and channels)
//   |a - b|^2 ~ (|A1 - B2|^2 + |A2 - B1|^2) / 2 - (|A1 - A2|^2 + |B1 - B2|^2) / 2,
// clamped at 0, and the converged RMS of a is sqrt(mean(A1 A2)). Both are unbiased; relative_rmse
// is the square root of their ratio. relative_noise is what one render's noise adds in quadrature
// (sqrt((var A + var B) / RMS^2)). NaN if a's balls are black.
struct ImageError {
  double relative_rmse = 0;
  double relative_noise = 0;
};
ImageError NoiseCorrectedImageError(const Brdf& a, const Brdf& b, const Environment* env,
                                    const BallOptions& options, const BallImage* a1 = nullptr,
                                    const BallImage* b1 = nullptr);

}  // namespace zbrdf
