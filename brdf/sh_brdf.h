// A BRDF given by spherical-harmonic coefficients (sh_file.h): what `zbrdf convert` produces.
//
// The coefficients describe f^ = f_r cos(theta_i) (band-limited, so it rings and can be negative,
// most of all outside the measured zone; docs/design.md section 3). Eval returns
//   f_r = max(0, f^) / max(cos(theta_i), kShMinCosTheta)
// and counts every evaluation where some channel of f^ was negative, so that clamping is never
// silent: negative_evaluations() / evaluations() is what a renderer hid. CosineWeighted() gives
// f^ unclamped. The cosine floor keeps grazing incidence finite for targets whose f^ does not
// vanish at the horizon (sh, sh-even, hsh); sh-odd's does.
//
// Evaluation uses the tensor form: T(w_o) is evaluated once per exitant direction and reused
// for runs of equal w_o in EvalBatch. Sampling is the cosine-weighted default (a band-limited
// function has no lobe to aim at); pair it with a D-BRDF fit's sampler for glossy materials
// (Ghosh 2007, section 3.4.2). Thread-safe.
#pragma once

#include <atomic>
#include <string>

#include "basis/target_basis.h"
#include "brdf/brdf.h"
#include "brdf/sh_file.h"

namespace zbrdf {

// cos(89.43 deg): below it f^ is divided by this instead of cos(theta_i).
inline constexpr double kShMinCosTheta = 0.01;

class ShBrdf final : public Brdf {
 public:
  // source: the file the data came from ("" if none), used by Spec(). Fills the per-exitant
  // tables if they are empty. Throws InputError if the data are inconsistent
  // (ShBrdfData::Problems()).
  explicit ShBrdf(ShBrdfData data, std::string source = "");

  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override;
  void EvalBatch(std::span<const Vec3> w_i, std::span<const Vec3> w_o,
                 std::span<Rgb> f) const override;
  bool IsReciprocal() const override { return false; }
  bool IsEnergyConserving() const override { return false; }
  // "file:PATH" for data read from a file, else "sh:target=..,order=.. (not saved)".
  std::string Spec() const override;

  // f^ = f_r cos(theta_i), unclamped (may be negative); 0 below the horizon. Not counted.
  Rgb CosineWeighted(const Vec3& w_i, const Vec3& w_o) const;
  // The same for one exitant direction and many incident ones (y(w_o) formed once).
  void CosineWeightedBatch(const Vec3& w_o, std::span<const Vec3> w_i, std::span<Rgb> f_hat) const;

  const ShBrdfData& data() const { return data_; }
  uint64_t evaluations() const { return evaluations_.load(std::memory_order_relaxed); }
  uint64_t negative_evaluations() const { return negatives_.load(std::memory_order_relaxed); }
  void ResetCounters() const;

 private:
  // f^ at w_i given y(w_o) = Y T(w_o) per channel.
  Rgb FromExitant(const Vec3& w_i, const Eigen::VectorXd* y, double* t_scratch) const;
  Rgb Clamped(const Rgb& f_hat, double cos_i) const;

  ShBrdfData data_;
  TargetBasis basis_;
  std::string source_;
  mutable std::atomic<uint64_t> evaluations_{0}, negatives_{0};
};

}  // namespace zbrdf
