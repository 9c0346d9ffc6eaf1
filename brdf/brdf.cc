#include "brdf/brdf.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "basis/error.h"

namespace zbrdf {

void Brdf::EvalBatch(std::span<const Vec3> w_i, std::span<const Vec3> w_o,
                     std::span<Rgb> f) const {
  ZBRDF_ASSERT(w_i.size() == w_o.size() && w_i.size() == f.size(), "EvalBatch size mismatch");
  for (size_t k = 0; k < w_i.size(); ++k) f[k] = Eval(w_i[k], w_o[k]);
}

void Brdf::EvalChannelBatchSinglePrecision(std::span<const Vec3> w_i, std::span<const Vec3> w_o,
                                           int channel, std::span<double> value) const {
  ZBRDF_ASSERT(
      w_i.size() == w_o.size() && w_i.size() == value.size() && channel >= -1 && channel < 3,
      "EvalChannelBatchSinglePrecision: size mismatch or channel outside -1..2");
  constexpr size_t kChunk = 128;
  std::array<Rgb, kChunk> f;
  for (size_t start = 0; start < w_i.size(); start += kChunk) {
    const size_t count = std::min(kChunk, w_i.size() - start);
    EvalBatchSinglePrecision(w_i.subspan(start, count), w_o.subspan(start, count),
                             std::span<Rgb>(f.data(), count));
    for (size_t k = 0; k < count; ++k) {
      value[start + k] = channel < 0 ? f[k].Luminance() : f[k][channel];
    }
  }
}

BrdfSample Brdf::Sample(const Vec3& w_o, double /*u_lobe*/, double u0, double u1) const {
  (void)w_o;
  BrdfSample s;
  s.w_i = SampleCosineHemisphere(u0, u1);
  s.pdf = CosineHemispherePdf(s.w_i);
  return s;
}

double Brdf::Pdf(const Vec3& /*w_o*/, const Vec3& w_i) const { return CosineHemispherePdf(w_i); }

Brdf::GlossyView Brdf::PrepareGlossy(const Vec3& w_o) const {
  GlossyView view;
  view.w_o = w_o;
  view.probability = GlossyProbability(w_o);
  return view;
}

BrdfSample Brdf::SampleGlossyAt(const GlossyView& view, double u_lobe, double u0,
                                double u1) const {
  const double p = view.probability;
  if (!(p >= kMinGlossyProbability)) return {};
  // Sample() takes its glossy part for u_lobe < p: rescale to stay there.
  BrdfSample s = Sample(view.w_o, std::min(u_lobe, 1.0 - 1e-12) * p, u0, u1);
  if (s.pdf <= 0 || s.is_delta) return s;
  s.pdf = Brdf::GlossyPdfAt(view, s.w_i);  // the density of this derivation, not an override's
  return s;
}

double Brdf::GlossyPdfAt(const GlossyView& view, const Vec3& w_i) const {
  const double p = view.probability;
  if (!(p >= kMinGlossyProbability)) return 0.0;
  return std::max(0.0, (Pdf(view.w_o, w_i) - (1.0 - p) * CosineHemispherePdf(w_i)) / p);
}

Vec3 SampleCosineHemisphere(double u0, double u1) {
  // Malley's method: uniform disk sample lifted to the hemisphere.
  const double r = std::sqrt(u0);
  const double phi = 2.0 * M_PI * u1;
  const double z = std::sqrt(std::max(0.0, 1.0 - u0));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

double CosineHemispherePdf(const Vec3& w) { return w.z > 0 ? w.z / M_PI : 0.0; }

}  // namespace zbrdf
