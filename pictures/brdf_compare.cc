#include "pictures/brdf_compare.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "pictures/image.h"

namespace zbrdf {
namespace {

void Label(cv::Mat& image, const std::string& text) {
  cv::rectangle(image, cv::Point(0, 0), cv::Point(image.cols, 22), cv::Scalar(0, 0, 0), cv::FILLED);
  cv::putText(image, text, cv::Point(6, 16), cv::FONT_HERSHEY_SIMPLEX, 0.45,
              cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
}

// Means over the pixels both images see and their channels.
double MeanSquaredDifference(const BallImage& x, const BallImage& y) {
  const double rmse = BallRmse(x, y);
  return rmse * rmse;
}

double MeanProduct(const BallImage& x, const BallImage& y) {
  double sum = 0;
  int64_t count = 0;
  for (size_t i = 0; i < x.image.pixels.size(); ++i) {
    if (!x.coverage[i] || !y.coverage[i]) continue;
    for (int c = 0; c < 3; ++c) sum += x.image.pixels[i][c] * y.image.pixels[i][c];
    count += 3;
  }
  return count > 0 ? sum / count : 0.0;
}

}  // namespace

ImageError NoiseCorrectedImageError(const Brdf& a, const Brdf& b, const Environment* env,
                                    const BallOptions& options, const BallImage* a1,
                                    const BallImage* b1) {
  std::optional<BallImage> own_a1, own_b1;
  if (a1 == nullptr) a1 = &own_a1.emplace(RenderBall(a, env, options));
  if (b1 == nullptr) b1 = &own_b1.emplace(RenderBall(b, env, options));
  // Another seed: PixelRng hashes (seed, pixel), so the second renders are independent of the
  // first.
  BallOptions second = options;
  second.seed = options.seed + 0x9E3779B97F4A7C15ull;
  const BallImage a2 = RenderBall(a, env, second), b2 = RenderBall(b, env, second);
  const double cross = 0.5 * (MeanSquaredDifference(*a1, b2) + MeanSquaredDifference(a2, *b1));
  const double variances = 0.5 * (MeanSquaredDifference(*a1, a2) + MeanSquaredDifference(*b1, b2));
  const double a_square = MeanProduct(*a1, a2);
  ImageError e;
  if (!(a_square > 0)) {
    e.relative_rmse = e.relative_noise = std::numeric_limits<double>::quiet_NaN();
    return e;
  }
  e.relative_rmse = std::sqrt(std::max(0.0, cross - variances) / a_square);
  e.relative_noise = std::sqrt(variances / a_square);
  return e;
}

nlohmann::json MaterialComparison::ToJson() const {
  return {{"render", {{"rmse", rmse}, {"relative_rmse", relative_rmse}}},
          {"brdf_cosine_weighted_l2", distance.ToJson()}};
}

MaterialComparison CompareMaterials(const Brdf& a, const Brdf& b, const Environment* env,
                                    const BallOptions& options, double exposure_ev,
                                    int64_t metric_samples) {
  MaterialComparison c;
  c.a = RenderBall(a, env, options);
  c.b = RenderBall(b, env, options);
  c.rmse = BallRmse(c.a, c.b);
  double sum = 0, y_max = 0;
  int64_t count = 0;
  for (size_t i = 0; i < c.a.image.pixels.size(); ++i) {
    if (!c.a.coverage[i]) continue;
    const Rgb& v = c.a.image.pixels[i];
    sum += v.r * v.r + v.g * v.g + v.b * v.b;
    count += 3;
    y_max = std::max(y_max, v.Luminance());
  }
  const double rms = count > 0 ? std::sqrt(sum / count) : 0.0;
  c.relative_rmse = rms > 0 ? c.rmse / rms : 0.0;
  c.distance = CosineWeightedL2(a, b, metric_samples, options.seed);

  const int size = c.a.image.width;
  cv::Mat gray(size, size, CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const size_t i = static_cast<size_t>(y) * size + x;
      if (!c.a.coverage[i]) continue;
      const double d = std::abs(c.a.image.pixels[i].Luminance() - c.b.image.pixels[i].Luminance());
      const double t = y_max > 0 ? std::clamp(d / y_max, 0.0, 1.0) : 0.0;
      gray.at<uint8_t>(y, x) = static_cast<uint8_t>(std::lround(255 * t));
    }
  }
  cv::applyColorMap(gray, c.difference, cv::COLORMAP_INFERNO);
  cv::Mat left = ToneMap(c.a.image, exposure_ev), middle = ToneMap(c.b.image, exposure_ev);
  cv::Mat right = c.difference.clone();
  Label(left, "A");
  Label(middle, "B");
  char text[96];
  std::snprintf(text, sizeof(text), "|Y_A - Y_B| / %.3g", y_max);
  Label(right, text);
  cv::hconcat(std::vector<cv::Mat>{left, middle, right}, c.side_by_side);
  return c;
}

}  // namespace zbrdf
