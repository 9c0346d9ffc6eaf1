#include "basis/conditioning.h"

#include <cmath>
#include <cstdio>
#include <random>

#include "basis/conversion.h"
#include "basis/gram.h"
#include "basis/legendre.h"
#include "basis/option_checker.h"
#include "basis/projection.h"
#include "basis/quadrature.h"

namespace zbrdf {

namespace {

std::string Format(const char* fmt, double value) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), fmt, value);
  return buf;
}

}  // namespace

double BandError::Relative() const { return norm_sq > 0 ? std::sqrt(error_sq / norm_sq) : 0; }

BandError ErrorOverBand(const TargetBasis& target, const Eigen::VectorXd& y,
                        const Eigen::VectorXd& y_est, double lo_rad, double hi_rad) {
  BandError band;
  if (hi_rad - lo_rad < 1e-12) return band;
  const SphereRule rule =
      ProductRule(CosThetaGaussRule(Zone(lo_rad, hi_rad), 2 * target.order() + 12),
                  2 * target.order() + 3);
  std::vector<double> t(target.size());
  double err = 0, norm = 0;
  for (size_t q = 0; q < rule.weights.size(); ++q) {
    target.Eval(rule.directions[q], t.data());
    double f = 0, f_est = 0;
    for (int i = 0; i < target.size(); ++i) {
      f += y(i) * t[i];
      f_est += y_est(i) * t[i];
    }
    err += rule.weights[q] * (f_est - f) * (f_est - f);
    norm += rule.weights[q] * f * f;
  }
  band.norm_sq = norm;
  band.error_sq = norm > 0 ? err : 0;
  return band;
}

ConditioningReport AnalyzeConditioning(const ConditioningOptions& options) {
  options.Validate();
  const Zone zone(options.theta_min_rad, options.theta_max_rad);
  const ZonalBasis zb(zone, options.zb_order);
  const TargetBasis target(options.target, options.target_order);
  ConditioningReport report;
  report.options = options;
  report.zb_size = zb.size();
  report.target_size = target.size();

  const Eigen::MatrixXd zb_gram =
      ZonalGramByQuadrature(zb, options.zb_order + 1, 2 * options.zb_order + 1);
  report.zb_orthonormality_max_error =
      (zb_gram - Eigen::MatrixXd::Identity(zb.size(), zb.size())).cwiseAbs().maxCoeff();

  for (int m = 0; m <= options.target_order; ++m) {
    const Eigen::MatrixXd g = TargetGramBlock(target, zone, m);
    if (g.size() == 0) {
      report.gram_condition_per_m.push_back(1.0);
      report.gram_condition_saturated.push_back(false);
      continue;
    }
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(g);
    const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
    // Eigenvalues below ~eps of the largest are rounding: the condition exceeds 1/eps.
    constexpr double kEps = 2.220446049250313e-16;
    const bool saturated = lo <= kEps * hi;
    report.gram_condition_per_m.push_back(saturated ? 1.0 / kEps : hi / lo);
    report.gram_condition_saturated.push_back(saturated);
    report.shannon_number += (m == 0 ? 1 : 2) * g.trace();
  }

  const ZonalToTarget conversion(zb, target, options.tau);
  const ConversionDiagnostics& d = conversion.diagnostics();
  report.noise_gain = d.noise_gain;
  report.truncated_components = d.truncated_components;
  report.underdetermined_components = d.underdetermined_components;
  report.largest_singular_value = d.largest_singular_value;
  report.smallest_kept_singular_value = d.smallest_kept_singular_value;

  // Round trip of a random band-limited function in the target space.
  std::mt19937_64 rng(options.seed);
  std::normal_distribution<double> normal(0, 1);
  Eigen::VectorXd y(target.size());
  for (int i = 0; i < target.size(); ++i) y(i) = normal(rng);
  std::vector<double> t(target.size());
  const int degree = options.zb_order + options.target_order;
  const Eigen::VectorXd z = ProjectOntoZonalBasis(
      zb,
      [&](const Vec3& w) {
        target.Eval(w, t.data());
        double f = 0;
        for (int i = 0; i < target.size(); ++i) f += y(i) * t[i];
        return f;
      },
      2 * degree + 60, 2 * degree + 3);
  const Eigen::VectorXd y_est = conversion.Apply(z);
  const BandError in = ErrorOverBand(target, y, y_est, zone.theta_min_rad(), zone.theta_max_rad());
  report.roundtrip_error_in_zone = in.Relative();
  const BandError cap = ErrorOverBand(target, y, y_est, 0.0, zone.theta_min_rad());
  const BandError band = ErrorOverBand(target, y, y_est, zone.theta_max_rad(), M_PI / 2);
  const double norm_outside = cap.norm_sq + band.norm_sq;
  report.has_outside = norm_outside > 0;
  report.roundtrip_error_outside_zone =
      report.has_outside ? std::sqrt((cap.error_sq + band.error_sq) / norm_outside) : 0;

  // The same with noise on the moments, as a capture delivers them.
  Eigen::VectorXd z_noisy = z;
  const double z_rms = z.norm() / std::sqrt(static_cast<double>(z.size()));
  for (int j = 0; j < z.size(); ++j) z_noisy(j) += options.noise_relative * z_rms * normal(rng);
  const Eigen::VectorXd y_noisy = conversion.Apply(z_noisy);
  const BandError noisy_in =
      ErrorOverBand(target, y, y_noisy, zone.theta_min_rad(), zone.theta_max_rad());
  report.noisy_roundtrip_error_in_zone =
      in.norm_sq > 0 ? std::sqrt(noisy_in.error_sq / in.norm_sq) : 0;
  if (report.has_outside) {
    const double e_cap = ErrorOverBand(target, y, y_noisy, 0.0, zone.theta_min_rad()).error_sq;
    const double e_band =
        ErrorOverBand(target, y, y_noisy, zone.theta_max_rad(), M_PI / 2).error_sq;
    report.noisy_roundtrip_error_outside_zone = std::sqrt((e_cap + e_band) / norm_outside);
  }

  // Advice (docs/design.md section 3, items 4 and 5).
  if (report.has_outside && report.noisy_roundtrip_error_outside_zone > 0.1) {
    report.warnings.push_back(
        "outside the zone the data determine only about " +
        Format("%.0f", report.shannon_number) + " of " + std::to_string(target.size()) +
        " target functions; with " + Format("%.2g", options.noise_relative) +
        " relative noise on the data the round trip there errs by " +
        Format("%.2g", report.noisy_roundtrip_error_outside_zone) +
        " (relative). Extrapolated values are not measurements: prefer an analytic fit (zbrdf "
        "fit) for what lies outside, or a hemispherical target (sh-even, sh-odd, hsh) with a "
        "zone that reaches the horizon");
  }
  if (report.noise_gain > 1e6) {
    report.warnings.push_back("noise gain " + Format("%.3g", report.noise_gain) +
                              ": measurement noise is amplified this much in the target "
                              "coefficients; raise --tau or lower --sh-order for noisy data");
  }
  if (report.underdetermined_components > 0) {
    report.warnings.push_back(std::to_string(report.underdetermined_components) +
                              " target functions have no zonal data to determine them (target "
                              "order above the zonal order); they are set to minimum norm (0)");
  }
  return report;
}

void ConditioningOptions::Validate() const {
  OptionChecker check("ConditioningOptions");
  check.ValidZone("theta_min_rad, theta_max_rad", theta_min_rad, theta_max_rad)
      .InRange("zb_order", zb_order, 0, kMaxLegendreDegree)
      .InRange("target_order", target_order, 0, kMaxLegendreDegree)
      .InRangeBelow("tau", tau, 0, 1)
      .InRange("noise_relative", noise_relative, 0, 1)
      .ThrowIfInvalid();
}

}  // namespace zbrdf
