#include "fitting/proxy_sampler.h"

#include <algorithm>
#include <cmath>

namespace zbrdf {
namespace {

constexpr double kProbeThetaStep = 0.15;
constexpr int kProbeCount = 11;  // theta_o = 0 .. 1.5 rad
constexpr double kFirstOffset = 1e-3;
constexpr double kOffsetRatio = 1.25;
constexpr double kLargestOffset = 1.2;
constexpr double kMinProbability = 0.05, kMaxProbability = 0.95;
constexpr double kMinExponent = 1.0, kMaxExponent = 1e6;

// Luminance of f_r, with negative (invalid) values treated as 0.
double Level(const Brdf& brdf, const Vec3& w_i, const Vec3& w_o) {
  const double y = brdf.Eval(w_i, w_o).Luminance();
  return std::isfinite(y) ? std::max(0.0, y) : 0.0;
}

// Luminance along cos(delta) r + sin(delta) axis for the offsets delta_k; stops below the horizon.
std::vector<double> Profile(const Brdf& brdf, const Vec3& w_o, const Vec3& r, const Vec3& axis,
                            std::vector<double>* offsets) {
  std::vector<double> levels;
  offsets->clear();
  for (double delta = kFirstOffset; delta <= kLargestOffset; delta *= kOffsetRatio) {
    const Vec3 w_i = std::cos(delta) * r + std::sin(delta) * axis;
    if (w_i.z <= 0) break;
    offsets->push_back(delta);
    levels.push_back(Level(brdf, w_i, w_o));
  }
  return levels;
}

// The lobe's energy as a function of the offset delta from r, treating the lobe as rotationally
// symmetric about r with excess(delta) = level - floor (clamped at 0): the energy within delta
// is proportional to integral_0^delta excess(t) sin(t) dt (trapezoid rule over the probed
// offsets; the integrand is 0 at delta = 0).
class RadialEnergy {
 public:
  RadialEnergy(const std::vector<double>& offsets, const std::vector<double>& levels, double floor)
      : offsets_(offsets), cumulative_(offsets.size() + 1, 0.0) {
    double previous_offset = 0, previous_value = 0;
    for (size_t k = 0; k < offsets.size(); ++k) {
      const double value = std::max(0.0, levels[k] - floor) * std::sin(offsets[k]);
      cumulative_[k + 1] =
          cumulative_[k] + 0.5 * (value + previous_value) * (offsets[k] - previous_offset);
      previous_offset = offsets[k];
      previous_value = value;
    }
  }

  double Total() const { return cumulative_.back(); }

  // The offset within which a fraction q of the energy lies (linear within a step); 0 when the
  // profile holds no energy.
  double Quantile(double q) const {
    if (!(Total() > 0)) return 0;
    const double target = q * Total();
    for (size_t k = 0; k < offsets_.size(); ++k) {
      if (cumulative_[k + 1] >= target) {
        const double start = k == 0 ? 0.0 : offsets_[k - 1];
        const double t = (target - cumulative_[k]) / (cumulative_[k + 1] - cumulative_[k]);
        return start + t * (offsets_[k] - start);
      }
    }
    return offsets_.back();
  }

 private:
  const std::vector<double>& offsets_;
  std::vector<double> cumulative_;
};

}  // namespace

LobeProxySampler::LobeProxySampler(const Brdf& brdf) {
  probes_.reserve(kProbeCount);
  std::vector<double> offsets_across, offsets_in;
  for (int n = 0; n < kProbeCount; ++n) {
    Probe probe;
    probe.theta_o_rad = n * kProbeThetaStep;
    const double s = std::sin(probe.theta_o_rad), c = std::cos(probe.theta_o_rad);
    const Vec3 w_o{s, 0.0, c};
    const Vec3 r{-s, 0.0, c};
    const double peak = Level(brdf, r, w_o);
    // Across the plane of incidence, and within it towards the normal.
    const std::vector<double> across = Profile(brdf, w_o, r, {0.0, 1.0, 0.0}, &offsets_across);
    const std::vector<double> in = Profile(brdf, w_o, r, {c, 0.0, s}, &offsets_in);
    double floor = peak;
    for (double level : across) floor = std::min(floor, level);
    for (double level : in) floor = std::min(floor, level);
    // Two Phong lobes, each sampled with half the lobe probability, whose medians are the
    // angles holding a quarter and three quarters of the energy: the mixture then matches the
    // profile's quartiles, covering both a sharp core and broad wings.
    const RadialEnergy energy_across(offsets_across, across, floor);
    const RadialEnergy energy_in(offsets_in, in, floor);
    for (int lobe = 0; lobe < 2; ++lobe) {
      const double q = lobe == 0 ? 0.25 : 0.75;
      const double across_q = energy_across.Quantile(q), in_q = energy_in.Quantile(q);
      double angle = kLargestOffset;
      if (across_q > 0 && in_q > 0) {
        angle = std::sqrt(across_q * in_q);
      } else if (across_q > 0 || in_q > 0) {
        angle = std::max(across_q, in_q);
      }
      probe.median_angle_rad[lobe] = angle;
      // A cos^m lobe about r holds half its probability within the angle where
      // 1 - cos^(m + 1) = 1/2.
      probe.exponent[lobe] =
          std::clamp(std::log(0.5) / std::log(std::cos(angle)) - 1.0, kMinExponent, kMaxExponent);
    }
    // Energies: the lobe's 2 pi integral excess(t) sin(t) dt (from the profile across the plane
    // of incidence, which the horizon never cuts) times cos(theta_i) ~ cos(theta_o); the floor's,
    // as a Lambertian, pi floor.
    const double lobe_energy = 2.0 * M_PI * energy_across.Total() * c;
    const double floor_energy = M_PI * floor;
    const double total = lobe_energy + floor_energy;
    probe.specular_probability =
        std::clamp(total > 0 ? lobe_energy / total : 0.0, kMinProbability, kMaxProbability);
    probes_.push_back(probe);
    log_exponents_.push_back(std::log(probe.exponent[0]));
    log_exponents_.push_back(std::log(probe.exponent[1]));
  }
}

LobeProxySampler::Mixture LobeProxySampler::MixtureFor(double theta_o_rad) const {
  const double u = std::clamp(theta_o_rad / kProbeThetaStep, 0.0, kProbeCount - 1.0);
  const int n = std::min(static_cast<int>(u), kProbeCount - 2);
  const double t = u - n;
  const Probe& a = probes_[n];
  const Probe& b = probes_[n + 1];
  const double* log_a = &log_exponents_[2 * n];
  const double* log_b = &log_exponents_[2 * (n + 1)];
  Mixture mixture;
  for (int lobe = 0; lobe < 2; ++lobe) {
    mixture.exponent[lobe] = std::exp((1.0 - t) * log_a[lobe] + t * log_b[lobe]);
  }
  mixture.lobe_probability = (1.0 - t) * a.specular_probability + t * b.specular_probability;
  return mixture;
}

BrdfSample LobeProxySampler::Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const {
  BrdfSample s;
  if (w_o.z <= 0) return s;
  const Mixture mixture = MixtureFor(SphericalTheta(w_o));
  if (u_lobe < mixture.lobe_probability) {
    const double m = mixture.exponent[u_lobe < 0.5 * mixture.lobe_probability ? 0 : 1];
    // cos(alpha) from the inverse CDF of (m + 1) cos^m over [0, 1]; alpha measured from r.
    const Vec3 r{-w_o.x, -w_o.y, w_o.z};
    const double cos_a = std::pow(u0, 1.0 / (m + 1.0));
    const double sin_a = std::sqrt(std::max(0.0, 1.0 - cos_a * cos_a));
    const double phi = 2.0 * M_PI * u1;
    Vec3 t, b;
    OrthonormalBasis(r, &t, &b);
    s.w_i = Normalize(sin_a * std::cos(phi) * t + sin_a * std::sin(phi) * b + cos_a * r);
  } else {
    s.w_i = SampleCosineHemisphere(u0, u1);
  }
  s.pdf = Pdf(w_o, s.w_i);
  return s;
}

double LobeProxySampler::Pdf(const Vec3& w_o, const Vec3& w_i) const {
  if (w_o.z <= 0) return 0;
  const Mixture mixture = MixtureFor(SphericalTheta(w_o));
  const Vec3 r{-w_o.x, -w_o.y, w_o.z};
  const double cos_a = Dot(w_i, r);
  double lobes = 0;
  if (cos_a > 0) {
    for (double m : mixture.exponent) lobes += 0.5 * (m + 1.0) / (2.0 * M_PI) * std::pow(cos_a, m);
  }
  return mixture.lobe_probability * lobes +
         (1.0 - mixture.lobe_probability) * CosineHemispherePdf(w_i);
}

}  // namespace zbrdf
