#include "brdf/proxy_sampler.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>

#include "basis/table_trig.h"

namespace zbrdf {
namespace {

constexpr int kCells = 128;
constexpr int kProbes = 21;
constexpr double kProbeStep = 0.075;  // theta_o = 0, 0.075, ..., 1.5 rad
constexpr int kAzimuths = 6;         // phi_h relative to w_o: 0, 30, ..., 150 deg (symmetric)
constexpr double kMinProbability = 0.05, kMaxProbability = 0.95;

// Luminance of f_r, with negative or invalid values treated as 0.
double Level(const Brdf& brdf, const Vec3& w_i, const Vec3& w_o) {
  const double y = brdf.Eval(w_i, w_o).Luminance();
  return std::isfinite(y) ? std::max(0.0, y) : 0.0;
}

}  // namespace

HalfVectorProxySampler::HalfVectorProxySampler(const Brdf& brdf) {
  theta_edges_.resize(kCells + 1);
  cos_edges_.resize(kCells + 1);
  for (int k = 0; k <= kCells; ++k) {
    const double x = static_cast<double>(k) / kCells;
    theta_edges_[k] = 0.5 * M_PI * x * x;
    cos_edges_[k] = std::cos(theta_edges_[k]);
  }
  cos_edges_[kCells] = 0.0;
  // Each bucket's first cell: that of the smallest u in it (u = 0 for the first).
  for (int b = 0; b < kGuideBuckets; ++b) {
    const uint64_t first_bits =
        (static_cast<uint64_t>(1023 - kGuideOctaves) << kGuideMantissaBits) + b;
    const double u = b == 0 ? 0.0 : std::bit_cast<double>(first_bits << (52 - kGuideMantissaBits));
    guide_[b] = CellBySearch(1.0 - u);
  }
  probes_.resize(kProbes);
  for (int p = 0; p < kProbes; ++p) {
    Probe& probe = probes_[p];
    probe.theta_o_rad = p * kProbeStep;
    const Vec3 w_o = SphericalDirection(probe.theta_o_rad, 0.0);
    // Mean level per theta_h cell over the azimuths where w_i stays above the horizon.
    std::vector<double> level(kCells, 0.0);
    std::vector<bool> seen(kCells, false);
    for (int k = 0; k < kCells; ++k) {
      const double theta_h = 0.5 * (theta_edges_[k] + theta_edges_[k + 1]);
      double sum = 0;
      int count = 0;
      for (int a = 0; a < kAzimuths; ++a) {
        const Vec3 h = SphericalDirection(theta_h, M_PI * a / kAzimuths);
        const Vec3 w_i = ReflectAboutHalfVector(w_o, h);
        if (w_i.z <= 1e-3) continue;
        sum += Level(brdf, w_i, w_o);
        ++count;
      }
      if (count > 0) {
        level[k] = sum / count;
        seen[k] = true;
      }
    }
    double floor = INFINITY;
    for (int k = 0; k < kCells; ++k) {
      if (seen[k]) floor = std::min(floor, level[k]);
    }
    if (!std::isfinite(floor)) floor = 0;
    probe.lobe_levels.assign(kCells, 0.0);
    std::vector<double> weights(kCells, 0.0);
    double lobe_albedo = 0;
    for (int k = 0; k < kCells; ++k) {
      if (!seen[k]) continue;
      probe.lobe_levels[k] = std::max(0.0, level[k] - floor);
      const double solid_angle = 2 * M_PI * (cos_edges_[k] - cos_edges_[k + 1]);
      weights[k] = probe.lobe_levels[k] * solid_angle;
      // Albedo of the lobe: integral e cos(theta_i) dw_i with dw_i = 4 |w_o.h| dw_h; the
      // azimuthal mean of cos(theta_i) |w_o.h| is approximated at the cell's first azimuth.
      const double theta_h = 0.5 * (theta_edges_[k] + theta_edges_[k + 1]);
      const Vec3 h = SphericalDirection(theta_h, 0.0);
      const Vec3 w_i = ReflectAboutHalfVector(w_o, h);
      if (w_i.z > 0) lobe_albedo += probe.lobe_levels[k] * w_i.z * 4 * Dot(w_o, h) * solid_angle;
    }
    double weight_sum = 0;
    for (double w : weights) weight_sum += w;
    if (weight_sum > 0 && lobe_albedo > 0) {
      probe.cells = std::make_unique<Distribution1D>(weights);
      probe.cell_density.resize(kCells);
      for (int k = 0; k < kCells; ++k) probe.cell_density[k] = probe.lobe_levels[k] / weight_sum;
      const double floor_albedo = floor * M_PI;
      probe.lobe_probability = std::clamp(lobe_albedo / (lobe_albedo + floor_albedo),
                                          kMinProbability, kMaxProbability);
    }
  }
}

HalfVectorProxySampler::Lobe HalfVectorProxySampler::LobeAt(double theta_o_rad) const {
  // The two probes around theta_o: the lobe probability interpolated linearly (weights a and
  // 1 - a), the lobe itself the nearer probe's (the other's where only one has a lobe). A
  // mixture of both lobes, chosen at random per sample, cost the simulator's transport 1.6x
  // the variance of its glossy samples for merl:blue-acrylic (docs/simulator.md, "Where the
  // transport's error comes from"): the random choice splits any stratified point set into
  // two unstratified halves.
  const double t = std::clamp(theta_o_rad * (1.0 / kProbeStep), 0.0, kProbes - 1.0);
  const int k = std::min(static_cast<int>(t), kProbes - 2);
  const double a = 1.0 - (t - k);
  const Probe &lower = probes_[k], &upper = probes_[k + 1];
  Lobe lobe;
  lobe.probability = a * lower.lobe_probability + (1 - a) * upper.lobe_probability;
  const bool use_lower = upper.cells == nullptr || (lower.cells != nullptr && a >= 0.5);
  lobe.probe = use_lower ? k : k + 1;
  return lobe;
}

Vec3 HalfVectorProxySampler::SampleHalfVector(const Probe& probe, double u0, double u1,
                                              int* cell) const {
  double u_within = 0;
  const int k = probe.cells->SampleDiscrete(u0, nullptr, &u_within);
  if (cell != nullptr) *cell = k;
  const double cos_theta = cos_edges_[k] + u_within * (cos_edges_[k + 1] - cos_edges_[k]);
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  double sin_phi, cos_phi;
  TurnSinCos(u1, &sin_phi, &cos_phi);  // phi = 2 pi u1
  return {sin_theta * cos_phi, sin_theta * sin_phi, cos_theta};
}

int HalfVectorProxySampler::CellBySearch(double cos_theta) const {
  // Cell k holds theta_h in [theta_edges_[k], theta_edges_[k + 1]), i.e. cos(theta_h) in
  // (cos_edges_[k + 1], cos_edges_[k]]: the first edge below cos_theta closes its cell.
  const auto it =
      std::upper_bound(cos_edges_.begin(), cos_edges_.end(), cos_theta, std::greater<>());
  return std::clamp(static_cast<int>(it - cos_edges_.begin()) - 1, 0, kCells - 1);
}

int HalfVectorProxySampler::CellOf(const Vec3& h) const {
  // CellBySearch(h.z), started from a guide table indexed by the exponent and top 5 mantissa
  // bits of u = 1 - h.z (32 buckets per octave of u, from 2^-40 up): no bucket holds two cell
  // edges, so the guide's cell is h's or the one before it. Integer operations only (no acos, no
  // sqrt); the binary search's branches are unpredictable for the simulator's random half
  // vectors. Measured: a fast simulation's CPU time -4%, the sampler's pdf check (whose cubature
  // asks for neighbouring half vectors, so the search's branches are predicted) 20.4 -> 22.9 s;
  // a guide over sqrt(sqrt(1 - h.z)) saved 9% and cost that check 37%.
  if (!(h.z >= 0 && h.z <= 1)) return CellBySearch(h.z);
  int cell = guide_[GuideBucket(1.0 - h.z)];
  while (cell > 0 && cos_edges_[cell] < h.z) --cell;
  while (cell + 1 < kCells && cos_edges_[cell + 1] >= h.z) ++cell;
  return cell;
}

int HalfVectorProxySampler::GuideBucket(double u) {
  // u in [0, 1]: its bits, exponent and mantissa, are monotonic in u.
  const int64_t bits =
      static_cast<int64_t>(std::bit_cast<uint64_t>(u) >> (52 - kGuideMantissaBits));
  constexpr int64_t kFirst = static_cast<int64_t>(1023 - kGuideOctaves) << kGuideMantissaBits;
  return static_cast<int>(std::clamp<int64_t>(bits - kFirst, 0, kGuideBuckets - 1));
}

double HalfVectorProxySampler::LobeProbability(const Vec3& w_o) const {
  if (w_o.z <= 0) return 0.0;
  return LobeAt(SphericalTheta(w_o)).probability;
}

double HalfVectorProxySampler::LobeDensity(const Lobe& lobe, const Vec3& h) const {
  if (!(lobe.probability > 0) || h.z < 0) return 0.0;
  return LobeDensityInCell(lobe, CellOf(h));
}

double HalfVectorProxySampler::LobeDensityInCell(const Lobe& lobe, int cell) const {
  // A lobe probability above 0 comes with a probe that has a lobe (LobeAt).
  return probes_[lobe.probe].cell_density[cell];
}

double HalfVectorProxySampler::HalfVectorPdf(double theta_o_rad, const Vec3& h) const {
  return LobeDensity(LobeAt(theta_o_rad), h);
}

double HalfVectorProxySampler::LobePdfOf(const Lobe& lobe, const Vec3& w_o, const Vec3& w_i) const {
  Vec3 h;
  if (!(lobe.probability > 0) || !UpperHalfVector(w_i, w_o, &h)) return 0.0;
  return HalfVectorToIncidentPdf(LobeDensity(lobe, h), w_o, h);
}

double HalfVectorProxySampler::PdfOf(const Lobe& lobe, const Vec3& w_o, const Vec3& w_i) const {
  const double p = lobe.probability;
  return p * LobePdfOf(lobe, w_o, w_i) + (1.0 - p) * CosineHemispherePdf(w_i);
}

BrdfSample HalfVectorProxySampler::Sample(const Vec3& w_o, double u_lobe, double u0,
                                          double u1) const {
  BrdfSample s;
  if (w_o.z <= 0) return s;
  const Lobe lobe = LobeAt(SphericalTheta(w_o));
  if (u_lobe < lobe.probability) {
    s.w_i = ReflectAboutHalfVector(w_o, SampleHalfVector(probes_[lobe.probe], u0, u1));
  } else {
    s.w_i = SampleCosineHemisphere(u0, u1);
  }
  s.pdf = PdfOf(lobe, w_o, s.w_i);
  return s;
}

double HalfVectorProxySampler::Pdf(const Vec3& w_o, const Vec3& w_i) const {
  if (w_o.z <= 0) return 0.0;
  return PdfOf(LobeAt(SphericalTheta(w_o)), w_o, w_i);
}

Brdf::GlossyView HalfVectorProxySampler::PrepareLobe(const Vec3& w_o) const {
  Brdf::GlossyView view;
  view.w_o = w_o;
  if (w_o.z <= 0) return view;
  const Lobe lobe = LobeAt(SphericalTheta(w_o));
  view.index = lobe.probe;
  view.probability = lobe.probability;
  return view;
}

BrdfSample HalfVectorProxySampler::SampleLobe(const Brdf::GlossyView& view, double /*u_lobe*/,
                                              double u0, double u1) const {
  if (!(view.probability >= Brdf::kMinGlossyProbability)) return {};
  const Lobe lobe{view.index, view.probability};
  int cell = 0;
  const Vec3 h = SampleHalfVector(probes_[lobe.probe], u0, u1, &cell);
  BrdfSample s;
  s.w_i = ReflectAboutHalfVector(view.w_o, h);
  // LobePdfOf(lobe, w_o, w_i) without finding h again: the half vector drawn and the cell it
  // was drawn in, where LobePdfOf normalizes w_i + w_o and searches its cell (the same h and
  // cell but for rounding; 10% of a simulator's transport build).
  s.pdf = HalfVectorToIncidentPdf(LobeDensityInCell(lobe, cell), view.w_o, h);
  return s;
}

double HalfVectorProxySampler::LobePdf(const Brdf::GlossyView& view, const Vec3& w_i) const {
  if (!(view.probability >= Brdf::kMinGlossyProbability)) return 0.0;
  return LobePdfOf({view.index, view.probability}, view.w_o, w_i);
}

}  // namespace zbrdf
