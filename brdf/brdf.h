// The BRDF interface every material and fitted model implements.
//
// Conventions (docs/design.md section 2): directions are unit vectors in the sample frame
// (normal +z, azimuth from +x); w_i points toward the light, w_o toward the viewer; f_r is in
// 1/sr, linear RGB, and does NOT include any cosine. Eval returns 0 when either direction is
// below the horizon (z <= 0).
//
// Every model can be importance-sampled: Sample() proposes w_i given w_o, and Pdf() returns the
// solid-angle density of that proposal. The density is defined over the whole sphere of w_i
// (a proposal may land below the horizon, where f_r = 0), so it integrates to 1 over the
// sphere. Models without an analytic sampler inherit cosine-weighted hemisphere sampling.
// The density is only a proposal: it need not be proportional to f_r, but it must be positive
// wherever f_r cos(theta_i) is, for unbiased Monte Carlo estimates. For w_o below the horizon
// (z <= 0), where f_r = 0, a model may produce no sample (pdf = 0); its Pdf() is then 0 too.
//
// A delta material (a perfect mirror) has f_r = 0 everywhere as a function; Sample() returns the
// single reflected direction with is_delta set, pdf = 1 (the probability of that direction) and
// the reflectance in delta_reflectance; its Pdf() is 0 for every pair.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>

#include "basis/vec3.h"

namespace zbrdf {

struct BrdfSample {
  Vec3 w_i;               // proposed incident direction (unit length)
  double pdf = 0;         // solid-angle density at w_i; 0 means no sample was produced
  bool is_delta = false;  // a Dirac lobe: pdf is 1, not a density; use delta_reflectance
  Rgb delta_reflectance;  // for is_delta: the fraction of radiance reflected along w_i
};

class Brdf {
 public:
  virtual ~Brdf() = default;

  // f_r(w_i, w_o) in 1/sr. Zero below the horizon.
  virtual Rgb Eval(const Vec3& w_i, const Vec3& w_o) const = 0;

  // Evaluates many pairs; f[k] = Eval(w_i[k], w_o[k]). Override where batching is faster.
  virtual void EvalBatch(std::span<const Vec3> w_i, std::span<const Vec3> w_o,
                         std::span<Rgb> f) const;
  // EvalBatch where single-precision arithmetic inside is acceptable (errors of ~1e-6 relative):
  // Monte Carlo sums whose own error is orders of magnitude larger (the simulator's light
  // transport). Models whose arithmetic is cheaper in float override it; the rest evaluate
  // EvalBatch.
  virtual void EvalBatchSinglePrecision(std::span<const Vec3> w_i, std::span<const Vec3> w_o,
                                        std::span<Rgb> f) const {
    EvalBatch(w_i, w_o, f);
  }
  // One channel of EvalBatchSinglePrecision, for callers that use one: value[k] = f[k][channel]
  // for channel 0, 1, 2, or f[k].Luminance() for channel -1 (the simulator's transport: each
  // camera pixel sees one colour, or luminance on a monochrome sensor). The same numbers as
  // EvalBatchSinglePrecision; models override it to skip the other channels' work.
  virtual void EvalChannelBatchSinglePrecision(std::span<const Vec3> w_i, std::span<const Vec3> w_o,
                                               int channel, std::span<double> value) const;

  // Proposes w_i for the given w_o from uniform random numbers u_lobe, u0, u1 in [0, 1).
  // u_lobe chooses among lobes of a mixture; (u0, u1) place the direction.
  virtual BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const;

  // Solid-angle density of Sample() producing w_i given w_o (over the whole sphere of w_i).
  virtual double Pdf(const Vec3& w_o, const Vec3& w_i) const;

  // The probability with which Sample() draws from the model's glossy (peaked) part; the rest
  // of its samples are cosine-weighted about the normal (the diffuse part), so that
  //   Pdf = p_glossy * GlossyPdf + (1 - p_glossy) * cos(theta_i) / pi.
  // Models that only sample the cosine lobe return 0.
  virtual double GlossyProbability(const Vec3& w_o) const {
    (void)w_o;
    return 0.0;
  }
  // Below this glossy probability the glossy density would be the difference of two nearly
  // equal numbers; such a model is treated as purely diffuse.
  static constexpr double kMinGlossyProbability = 1e-6;
  // Samples of the glossy part alone, and their density, for integrators that handle the
  // smooth part of an integrand by other means (the rig simulator). No sample (pdf = 0) when
  // GlossyProbability is below kMinGlossyProbability.
  BrdfSample SampleGlossy(const Vec3& w_o, double u_lobe, double u0, double u1) const {
    return SampleGlossyAt(PrepareGlossy(w_o), u_lobe, u0, u1);
  }
  double GlossyPdf(const Vec3& w_o, const Vec3& w_i) const {
    return GlossyPdfAt(PrepareGlossy(w_o), w_i);
  }

  // The same for many samples of one viewing direction, with what depends only on w_o worked
  // out once by PrepareGlossy (the simulator draws 32-64 samples per camera ray, the true
  // coefficients thousands per exitant direction). SampleGlossyAt(PrepareGlossy(w_o), ...)
  // equals SampleGlossy(w_o, ...) up to rounding, and GlossyPdfAt likewise. A model overrides
  // all three or none: a view is read only by the class whose PrepareGlossy made it.
  struct GlossyView {
    Vec3 w_o;
    double probability = 0;  // GlossyProbability(w_o)
    // What a model's PrepareGlossy keeps for later calls (the half-vector proxy: the probe
    // whose lobe serves theta_o); unused by the default.
    int index = 0;
  };
  virtual GlossyView PrepareGlossy(const Vec3& w_o) const;
  virtual BrdfSample SampleGlossyAt(const GlossyView& view, double u_lobe, double u0,
                                    double u1) const;
  virtual double GlossyPdfAt(const GlossyView& view, const Vec3& w_i) const;

  // f_r(w_i, w_o) == f_r(w_o, w_i) for this model by construction.
  virtual bool IsReciprocal() const = 0;
  // The directional albedo integral f_r cos(theta_i) d w_i is <= 1 for every w_o by construction
  // (for physically valid parameters).
  virtual bool IsEnergyConserving() const = 0;
  virtual bool IsDelta() const { return false; }
  // The value of f_r when it is the same for every pair of directions above the horizon (an
  // ideal diffuse reflector), else nullopt. Equal to what Eval returns there. Integrators may
  // then integrate in closed form (the rig simulator's transport, docs/simulator.md).
  virtual std::optional<Rgb> ConstantValue() const { return std::nullopt; }
  // f_r(R w_i, R w_o) == f_r(w_i, w_o) for every rotation R about the normal, by construction.
  // Integrators may then work at one azimuth and rotate (acquisition/ground_truth.h).
  virtual bool IsIsotropic() const { return false; }

  // A material spec (see material_spec.h) that recreates this model, e.g. "lambert:0.18".
  virtual std::string Spec() const = 0;
};

// Cosine-weighted hemisphere sampling about +z: pdf = cos(theta) / pi (zero below the horizon).
Vec3 SampleCosineHemisphere(double u0, double u1);
double CosineHemispherePdf(const Vec3& w);

}  // namespace zbrdf
