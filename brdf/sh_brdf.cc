#include "brdf/sh_brdf.h"

#include <algorithm>
#include <vector>

#include "basis/error.h"

namespace zbrdf {
namespace {

ShBrdfData Checked(ShBrdfData data) {
  if (data.exitant[0].empty() && data.order >= 0 && data.order <= 30) data.FillExitantTables();
  if (const std::string problems = data.Problems(); !problems.empty()) throw InputError(problems);
  return data;
}

}  // namespace

ShBrdf::ShBrdf(ShBrdfData data, std::string source)
    : data_(Checked(std::move(data))), basis_(data_.target, data_.order), source_(std::move(source)) {}

std::string ShBrdf::Spec() const {
  if (!source_.empty()) return "file:" + source_;
  return "sh:target=" + TargetName(data_.target) + ",order=" + std::to_string(data_.order) +
         " (not saved)";
}

void ShBrdf::ResetCounters() const {
  evaluations_.store(0);
  negatives_.store(0);
}

Rgb ShBrdf::FromExitant(const Vec3& w_i, const Eigen::VectorXd* y, double* t_scratch) const {
  basis_.Eval(w_i, t_scratch);
  const Eigen::Map<const Eigen::VectorXd> t(t_scratch, basis_.size());
  return {y[0].dot(t), y[1].dot(t), y[2].dot(t)};
}

Rgb ShBrdf::Clamped(const Rgb& f_hat, double cos_i) const {
  evaluations_.fetch_add(1, std::memory_order_relaxed);
  if (f_hat.r < 0 || f_hat.g < 0 || f_hat.b < 0) negatives_.fetch_add(1, std::memory_order_relaxed);
  const double inv = 1.0 / std::max(cos_i, kShMinCosTheta);
  return {std::max(0.0, f_hat.r) * inv, std::max(0.0, f_hat.g) * inv, std::max(0.0, f_hat.b) * inv};
}

Rgb ShBrdf::CosineWeighted(const Vec3& w_i, const Vec3& w_o) const {
  if (w_i.z <= 0 || w_o.z <= 0) return {};
  std::vector<double> t(basis_.size());
  basis_.Eval(w_o, t.data());
  const Eigen::Map<const Eigen::VectorXd> to(t.data(), basis_.size());
  Eigen::VectorXd y[3];
  for (int ch = 0; ch < 3; ++ch) y[ch] = data_.coefficients[ch] * to;
  return FromExitant(w_i, y, t.data());
}

void ShBrdf::CosineWeightedBatch(const Vec3& w_o, std::span<const Vec3> w_i,
                                 std::span<Rgb> f_hat) const {
  ZBRDF_ASSERT(w_i.size() == f_hat.size(), "batch sizes differ");
  const int n = basis_.size();
  std::vector<double> t(n);
  Eigen::VectorXd y[3];
  basis_.Eval(w_o, t.data());
  const Eigen::Map<const Eigen::VectorXd> to(t.data(), n);
  for (int ch = 0; ch < 3; ++ch) y[ch] = data_.coefficients[ch] * to;
  for (size_t k = 0; k < w_i.size(); ++k) {
    f_hat[k] = (w_i[k].z <= 0 || w_o.z <= 0) ? Rgb() : FromExitant(w_i[k], y, t.data());
  }
}

Rgb ShBrdf::Eval(const Vec3& w_i, const Vec3& w_o) const {
  if (w_i.z <= 0 || w_o.z <= 0) return {};
  return Clamped(CosineWeighted(w_i, w_o), w_i.z);
}

void ShBrdf::EvalBatch(std::span<const Vec3> w_i, std::span<const Vec3> w_o,
                       std::span<Rgb> f) const {
  ZBRDF_ASSERT(w_i.size() == w_o.size() && f.size() == w_i.size(), "batch sizes differ");
  const int n = basis_.size();
  std::vector<double> t(n);
  Eigen::VectorXd y[3];
  bool have = false;
  Vec3 current;
  for (size_t k = 0; k < w_i.size(); ++k) {
    if (w_i[k].z <= 0 || w_o[k].z <= 0) {
      f[k] = {};
      continue;
    }
    if (!have || !(w_o[k] == current)) {
      basis_.Eval(w_o[k], t.data());
      const Eigen::Map<const Eigen::VectorXd> to(t.data(), n);
      for (int ch = 0; ch < 3; ++ch) y[ch] = data_.coefficients[ch] * to;
      current = w_o[k];
      have = true;
    }
    f[k] = Clamped(FromExitant(w_i[k], y, t.data()), w_i[k].z);
  }
}

}  // namespace zbrdf
