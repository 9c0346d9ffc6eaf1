#include "tools/sh_conversion.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/zonal_basis.h"

namespace zbrdf {
namespace {

// Energy ratio (signal + noise) / noise from which a direction's data count as signal.
constexpr double kSignalToNoise = 8.0;
// The smallest automatic tau: noise gain at most 1e4.
constexpr double kMinimumTau = 1e-4;

struct AutomaticTau {
  double tau = 0;
  int kept = 0, available = 0;
};

AutomaticTau ChooseTau(const ZonalTensor& data, const ZonalBasis& zb, const TargetBasis& target) {
  // The moment matrix: any tau gives the same M.
  const ZonalToTarget probe(zb, target, 0.0);
  const Eigen::MatrixXd& m = probe.moment_matrix();  // zb x target
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(m, Eigen::ComputeThinU);
  const Eigen::VectorXd sigma = svd.singularValues();
  const Eigen::MatrixXd& u = svd.matrixU();
  const double s1 = sigma.size() > 0 ? sigma[0] : 0.0;
  int r = 0;
  while (r < sigma.size() && sigma[r] > 1e-15 * s1) ++r;
  AutomaticTau out;
  out.available = r;
  if (r == 0) return out;
  const Eigen::MatrixXd ur = u.leftCols(r);
  const Eigen::MatrixXd u2 = ur.cwiseProduct(ur);
  // Per direction a (as a row and as a column of W, all channels): energy and noise energy.
  Eigen::VectorXd energy = Eigen::VectorXd::Zero(r), noise = Eigen::VectorXd::Zero(r);
  for (int ch = 0; ch < 3; ++ch) {
    const Eigen::MatrixXd w = ur.transpose() * data.z[ch] * ur;
    Eigen::MatrixXd var = data.variance[ch];
    const double rms = std::sqrt(data.z[ch].squaredNorm() / static_cast<double>(data.z[ch].size()));
    for (Eigen::Index i = 0; i < var.size(); ++i) {
      const double z = data.z[ch].data()[i];
      var.data()[i] += 1e-14 * (z * z + rms * rms);
    }
    const Eigen::MatrixXd var_w = u2.transpose() * var * u2;
    for (int a = 0; a < r; ++a) {
      energy[a] += w.row(a).squaredNorm() + w.col(a).squaredNorm();
      noise[a] += var_w.row(a).sum() + var_w.col(a).sum();
    }
  }
  // The recorded variances hold photon noise only. Along directions the zone barely sees
  // (s_a <= 1e-3 s_1) a band-limited function of bounded norm leaves at most 1e-3 of its
  // amplitude, so what the data show there is error: noise, the capture's systematic errors, and
  // the out-of-band content of features sharper than the order (a specular peak's moments are
  // spread evenly over all directions). Its median energy floors every direction's noise.
  std::vector<double> deep;
  for (int a = 0; a < r; ++a) {
    if (sigma[a] <= 1e-3 * s1) deep.push_back(energy[a]);
  }
  if (deep.size() >= 3) {
    std::nth_element(deep.begin(), deep.begin() + deep.size() / 2, deep.end());
    noise = noise.cwiseMax(deep[deep.size() / 2]);
  }
  // Expected squared error in the target coefficients when the k largest directions are kept:
  // the kept directions' noise amplified by 1 / s_a^2, plus the truncated directions' signal
  // (their energy beyond noise, counted only where it is significant: at least kSignalToNoise
  // times the noise, so that error-level directions never pull tau down). k minimizes it.
  double kept_noise = 0, lost_signal = 0;
  std::vector<double> signal(r, 0.0);
  for (int a = 0; a < r; ++a) {
    if (energy[a] >= kSignalToNoise * noise[a]) signal[a] = (energy[a] - noise[a]) / (sigma[a] * sigma[a]);
    lost_signal += signal[a];
  }
  int best_k = 0;
  double best = INFINITY;
  for (int k = 1; k <= r; ++k) {
    kept_noise += noise[k - 1] / (sigma[k - 1] * sigma[k - 1]);
    lost_signal -= signal[k - 1];
    // Degenerate singular values (+m and -m blocks) are kept or dropped together.
    const bool split = k < r && sigma[k] > sigma[k - 1] * (1 - 1e-9);
    const double e = kept_noise + std::max(0.0, lost_signal);
    if (!split && e < best) {
      best = e;
      best_k = k;
    }
  }
  if (best_k == 0) best_k = 1;  // keep at least the strongest direction
  // Never beyond a noise gain of 1 / kMinimumTau: the tensor is stored in float (6e-8) and a
  // capture's coefficients carry ~1e-3 relative errors, so beyond it nothing is trustworthy,
  // whatever the error estimate says (clean, smooth data make it small).
  while (best_k > 1 && sigma[best_k - 1] < kMinimumTau * s1) --best_k;
  while (best_k > 1 && best_k < r && sigma[best_k] > sigma[best_k - 1] * (1 - 1e-9)) --best_k;
  out.kept = best_k;
  out.tau = best_k < r ? std::sqrt(sigma[best_k - 1] * sigma[best_k]) / s1 : 0.5 * sigma[r - 1] / s1;
  return out;
}

}  // namespace

void ShConversionOptions::Validate() const {
  OptionChecker check("ShConversionOptions");
  check.Require(order <= 30, "order",
                "must be in [0, 30], or < 0 for the data's order (--sh-order; got " +
                    std::to_string(order) + ")")
      .Require(tau < 1, "tau",
               "must be in [0, 1), or < 0 for the automatic threshold (got " +
                   FormatOptionValue(tau) + ")")
      .InRange("exitant_theta", exitant_theta, 1, 3600)
      .InRange("exitant_phi", exitant_phi, 1, 3600)
      .ThrowIfInvalid();
}

ShConversionResult ConvertToSh(const ZonalTensor& data, const ShConversionOptions& options) {
  options.Validate();
  if (const std::string problems = data.Problems(); !problems.empty()) {
    if (problems.find("not finite") != std::string::npos || problems.find("NaN") != std::string::npos) {
      throw NumericalError("SH conversion: " + problems + "; the session's zonal data are damaged");
    }
    throw InputError("SH conversion: " + problems);
  }
  const int order = options.order < 0 ? data.order : options.order;
  const Zone zone = data.zone();
  const ZonalBasis zb(zone, data.order);
  const TargetBasis target(options.target, order);
  ShConversionResult result;
  if (options.tau < 0) {
    const AutomaticTau automatic = ChooseTau(data, zb, target);
    result.tau = automatic.tau;
    result.tau_automatic = true;
    result.kept_directions = automatic.kept;
    result.singular_directions = automatic.available;
  } else {
    result.tau = options.tau;
  }
  const ZonalToTarget conversion(zb, target, result.tau);
  result.diagnostics = conversion.diagnostics();
  if (!result.tau_automatic) {
    result.singular_directions = static_cast<int>(result.diagnostics.singular_values.size());
    result.kept_directions = result.singular_directions - result.diagnostics.truncated_components;
  }
  ShBrdfData& sh = result.data;
  sh.theta_min_rad = data.theta_min_rad;
  sh.theta_max_rad = data.theta_max_rad;
  sh.target = options.target;
  sh.order = order;
  for (int ch = 0; ch < 3; ++ch) sh.coefficients[ch] = ConvertTensor(conversion, conversion, data.z[ch]);
  sh.exitant_theta = options.exitant_theta;
  sh.exitant_phi = options.exitant_phi;
  sh.FillExitantTables();

  const double a = zone.cos_lower(), b = zone.cos_upper();
  result.shannon_number = (order + 1.0) * (order + 1.0) * (b - a) / 2.0;
  const double coverage = b - a;  // fraction of the hemisphere's solid angle
  char text[400];
  if (options.target == TargetKind::kSh && coverage < 0.9) {
    std::snprintf(text, sizeof(text),
                  "the zone %s covers %.0f%% of the hemisphere: the data determine only about "
                  "%.0f (the Shannon number) of the %d SH functions, so the SH outside the zone "
                  "are extrapolation without a prior (docs/design.md section 3, item 5); for what "
                  "lies outside the zone prefer an analytic fit (zbrdf fit --model dbrdf)",
                  zone.ToString().c_str(), 100 * coverage, result.shannon_number, target.size());
    result.warnings.push_back(text);
  } else if (options.target != TargetKind::kSh && coverage < 0.9) {
    std::snprintf(text, sizeof(text),
                  "the zone %s covers %.0f%% of the hemisphere: outside it the %s function is "
                  "extrapolation; for what lies outside the zone prefer zbrdf fit --model dbrdf",
                  zone.ToString().c_str(), 100 * coverage, TargetName(options.target).c_str());
    result.warnings.push_back(text);
  }
  if (options.target == TargetKind::kSh && zone.theta_max_rad() >= DegToRad(89.0)) {
    result.warnings.push_back("the zone reaches the horizon: a hemispherical target (sh-odd for "
                              "cosine-weighted data, or hsh) is far better conditioned than all "
                              "SH (docs/design.md section 3, item 4)");
  }
  if (result.diagnostics.truncated_components > 0) {
    std::snprintf(text, sizeof(text),
                  "%d of %zu singular directions were truncated (tau %.3g): the data cannot "
                  "determine them above their noise; those target combinations are set to 0",
                  result.diagnostics.truncated_components, result.diagnostics.singular_values.size(),
                  result.tau);
    result.warnings.push_back(text);
  }
  if (result.diagnostics.underdetermined_components > 0) {
    std::snprintf(text, sizeof(text),
                  "%d target functions lie beyond what the zonal order %d can reach; their "
                  "coefficients are 0",
                  result.diagnostics.underdetermined_components, data.order);
    result.warnings.push_back(text);
  }
  nlohmann::json info = result.ToJson();
  info.erase("warnings");
  sh.info = info;
  return result;
}

nlohmann::json ShConversionResult::ToJson() const {
  nlohmann::json j;
  j["target"] = TargetName(data.target);
  j["sh_order"] = data.order;
  j["target_functions"] = data.size();
  j["tau"] = tau;
  j["tau_rule"] = tau_automatic ? "automatic: minimum of amplified noise plus truncated significant "
                                  "signal (docs/fitting.md)"
                                : "given";
  j["noise_gain"] = std::isfinite(diagnostics.noise_gain) ? nlohmann::json(diagnostics.noise_gain) : nlohmann::json(nullptr);
  j["truncated_components"] = diagnostics.truncated_components;
  j["underdetermined_components"] = diagnostics.underdetermined_components;
  j["kept_directions"] = kept_directions;
  j["singular_directions"] = singular_directions;
  j["largest_singular_value"] = diagnostics.largest_singular_value;
  j["smallest_kept_singular_value"] = diagnostics.smallest_kept_singular_value;
  j["shannon_number"] = shannon_number;
  j["exitant_grid"] = {data.exitant_theta, data.exitant_phi};
  j["warnings"] = warnings;
  return j;
}

}  // namespace zbrdf
