#include "brdf/spectral.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "basis/error.h"

namespace zbrdf {
namespace {

// Piecewise Gaussian of Wyman et al. 2013: inverse widths below and above the mean.
double Lobe(double lambda, double mean, double inv_width_below, double inv_width_above) {
  const double t = (lambda - mean) * (lambda < mean ? inv_width_below : inv_width_above);
  return std::exp(-0.5 * t * t);
}

double Logistic(double x) { return 1.0 / (1.0 + std::exp(-x)); }

// The three basis spectra (blue, green, red bands); they sum to 1 at every wavelength.
std::array<double, 3> BasisAt(double lambda_nm) {
  const double above_blue = Logistic((lambda_nm - 495.0) / 12.0);
  const double red = Logistic((lambda_nm - 585.0) / 12.0);
  return {1.0 - above_blue, above_blue - red, red};
}

// Integration range and step of the observer (nm); the fit is negligible outside.
constexpr double kLambdaMin = 360.0, kLambdaMax = 830.0, kLambdaStep = 1.0;

}  // namespace

Vec3 CieXyz1931(double lambda) {
  const double x = 1.056 * Lobe(lambda, 599.8, 0.0264, 0.0323) +
                   0.362 * Lobe(lambda, 442.0, 0.0624, 0.0374) -
                   0.065 * Lobe(lambda, 501.1, 0.0490, 0.0382);
  const double y =
      0.821 * Lobe(lambda, 568.8, 0.0213, 0.0247) + 0.286 * Lobe(lambda, 530.9, 0.0613, 0.0322);
  const double z =
      1.217 * Lobe(lambda, 437.0, 0.0845, 0.0278) + 0.681 * Lobe(lambda, 459.0, 0.0385, 0.0725);
  return {x, y, z};
}

Rgb LinearSrgbFromXyz(const Vec3& v) {
  return {3.2404542 * v.x - 1.5371385 * v.y - 0.4985314 * v.z,
          -0.9692660 * v.x + 1.8760108 * v.y + 0.0415560 * v.z,
          0.0556434 * v.x - 0.2040259 * v.y + 1.0572252 * v.z};
}

SpectralBasis::SpectralBasis(std::vector<double> wavelengths_nm)
    : wavelengths_(std::move(wavelengths_nm)) {
  const int n = static_cast<int>(wavelengths_.size());
  if (n < 2) throw InputError("spectral basis: at least two wavelengths are needed");
  for (int k = 1; k < n; ++k) {
    if (!(wavelengths_[k] > wavelengths_[k - 1])) {
      throw InputError("spectral basis: wavelengths must be strictly ascending");
    }
  }
  node_weights_.assign(n, Rgb());
  Rgb norm;
  for (double lambda = kLambdaMin + 0.5 * kLambdaStep; lambda < kLambdaMax; lambda += kLambdaStep) {
    const Rgb rbar = LinearSrgbFromXyz(CieXyz1931(lambda)) * kLambdaStep;
    norm += rbar;
    // Tent weights of the piecewise-linear interpolant with constant ends.
    if (lambda <= wavelengths_.front()) {
      node_weights_.front() += rbar;
    } else if (lambda >= wavelengths_.back()) {
      node_weights_.back() += rbar;
    } else {
      const int k =
          static_cast<int>(std::upper_bound(wavelengths_.begin(), wavelengths_.end(), lambda) -
                           wavelengths_.begin() - 1);
      const double t = (lambda - wavelengths_[k]) / (wavelengths_[k + 1] - wavelengths_[k]);
      node_weights_[k] += rbar * (1.0 - t);
      node_weights_[k + 1] += rbar * t;
    }
  }
  for (Rgb& w : node_weights_) w = Rgb(w.r / norm.r, w.g / norm.g, w.b / norm.b);
  for (int b = 0; b < 3; ++b) {
    basis_at_nodes_[b].resize(n);
    for (int k = 0; k < n; ++k) basis_at_nodes_[b][k] = BasisAt(wavelengths_[k])[b];
    basis_rgb_[b] = Project(basis_at_nodes_[b]);
  }
}

SpectralBasis SpectralBasis::Default() {
  std::vector<double> nodes;
  for (int lambda = 380; lambda <= 780; lambda += 10) nodes.push_back(lambda);
  return SpectralBasis(std::move(nodes));
}

Rgb SpectralBasis::Project(const std::vector<double>& values) const {
  ZBRDF_ASSERT(values.size() == wavelengths_.size(), "spectrum size differs from the nodes");
  Rgb rgb;
  for (size_t k = 0; k < values.size(); ++k) rgb += node_weights_[k] * values[k];
  return rgb;
}

std::vector<double> SpectralBasis::Upsample(const Rgb& rgb, double* gamut_error) const {
  // Non-negative least squares on three unknowns: the best feasible solution over the seven
  // sets of free coefficients (the others held at 0).
  Eigen::Matrix3d a;
  for (int b = 0; b < 3; ++b) a.col(b) << basis_rgb_[b].r, basis_rgb_[b].g, basis_rgb_[b].b;
  const Eigen::Vector3d target(rgb.r, rgb.g, rgb.b);
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  double best_residual = target.squaredNorm();
  for (int mask = 1; mask < 8; ++mask) {
    std::vector<int> free;
    for (int b = 0; b < 3; ++b) {
      if (mask & (1 << b)) free.push_back(b);
    }
    Eigen::MatrixXd sub(3, free.size());
    for (size_t j = 0; j < free.size(); ++j) sub.col(j) = a.col(free[j]);
    const Eigen::VectorXd x = sub.colPivHouseholderQr().solve(target);
    if ((x.array() < -1e-14).any()) continue;
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (size_t j = 0; j < free.size(); ++j) c[free[j]] = std::max(0.0, x[j]);
    const double residual = (a * c - target).squaredNorm();
    if (residual < best_residual * (1 - 1e-12)) {
      best_residual = residual;
      best = c;
    }
  }
  std::vector<double> values(wavelengths_.size(), 0.0);
  for (size_t k = 0; k < values.size(); ++k) {
    for (int b = 0; b < 3; ++b) values[k] += best[b] * basis_at_nodes_[b][k];
  }
  if (gamut_error) {
    const Eigen::Vector3d error = a * best - target;
    *gamut_error = error.cwiseAbs().maxCoeff();
  }
  return values;
}

}  // namespace zbrdf
