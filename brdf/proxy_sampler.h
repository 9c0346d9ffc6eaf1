// An importance-sampling proposal for isotropic BRDFs without an analytic sampler (MERL tables,
// measured-material networks), in the spirit of the D-BRDF (Ashikhmin & Premoze 2007):
// tabulated distributions of half vectors, reflected about w_o, mixed with cosine sampling.
//
// At construction the BRDF is probed for 21 viewing angles theta_o (0 .. 1.5 rad): for each,
// along half-vector angles theta_h (128 cells, finer near the normal: theta_h = (pi/2) x^2 for
// x uniform) at 6 azimuths phi_h, with w_i = w_o reflected about h. The luminance above the
// BRDF's floor (its minimum over the probes) becomes that viewing angle's half-vector density
// p_h (piecewise constant in cos theta_h, uniform in phi_h), and the lobe's share of the energy
// its lobe probability P (in [0.05, 0.95] when the lobe has energy, 0 without one). Reflecting
// w_o about h places the lobe correctly for every w_o, off-specular peaks included. For a
// viewing angle between two probes k and k + 1 (linear weights a_k, a_k+1) the lobe probability
// is interpolated, P = a_k P_k + a_k+1 P_k+1, and the lobe is the nearer probe's, n:
//   p(w_i) = P p_h,n(h) / (4 |w_o.h|) + (1 - P) max(0, cos theta_i) / pi.
// (A mixture of both probes' lobes, drawn by a random choice per sample, broke the
// stratification of the simulator's point sets; the nearer lobe is at most 2.15 deg of theta_o
// away.) Sample() draws the glossy part for u_lobe < P, as Brdf::SampleGlossy expects.
//
// It is only a proposal for Monte Carlo with multiple importance sampling: Pdf() is exactly the
// density Sample() draws from. Probing costs about 16000 evaluations of the BRDF.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "brdf/brdf.h"
#include "brdf/sampling.h"

namespace zbrdf {

class HalfVectorProxySampler {
 public:
  // Probes brdf (assumed isotropic); it is used only during construction.
  explicit HalfVectorProxySampler(const Brdf& brdf);

  // The mixture above; no sample (pdf = 0) for w_o below the horizon.
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const;
  double Pdf(const Vec3& w_o, const Vec3& w_i) const;

  // P: the probability of sampling the half-vector lobe for this viewing direction.
  double LobeProbability(const Vec3& w_o) const;
  // The lobe alone, for Brdf::PrepareGlossy, SampleGlossyAt and GlossyPdfAt of the models it
  // samples: the view keeps the lobe (index: the nearer probe n; probability: P), SampleLobe
  // draws from it whatever u_lobe, and the lobe's density p_h,n(h) / (4 |w_o.h|) is taken
  // without the cosine part.
  Brdf::GlossyView PrepareLobe(const Vec3& w_o) const;
  BrdfSample SampleLobe(const Brdf::GlossyView& view, double u_lobe, double u0, double u1) const;
  double LobePdf(const Brdf::GlossyView& view, const Vec3& w_i) const;
  // Solid-angle density of the half vector h drawn for viewing angle theta_o (its lobe's).
  double HalfVectorPdf(double theta_o_rad, const Vec3& h) const;

  struct Probe {
    double theta_o_rad = 0;
    double lobe_probability = 0;       // P
    std::vector<double> lobe_levels;   // luminance above the floor per theta_h cell (1/sr)
    std::vector<double> cell_density;  // solid-angle density of h within each cell
    std::unique_ptr<Distribution1D> cells;  // null when the probe found no lobe
  };
  const std::vector<Probe>& probes() const { return probes_; }
  const std::vector<double>& theta_edges() const { return theta_edges_; }

 private:
  // A viewing angle's lobe: the nearer probe n (with a lobe) and the interpolated P.
  struct Lobe {
    int probe = 0;
    double probability = 0;
  };
  Lobe LobeAt(double theta_o_rad) const;
  double LobeDensity(const Lobe& lobe, const Vec3& h) const;   // p_h,n(h)
  double LobeDensityInCell(const Lobe& lobe, int cell) const;  // the same for h in a cell
  double PdfOf(const Lobe& lobe, const Vec3& w_o, const Vec3& w_i) const;
  double LobePdfOf(const Lobe& lobe, const Vec3& w_o, const Vec3& w_i) const;  // lobe alone
  // A half vector from the probe's cell distribution; *cell (optional): the cell drawn.
  Vec3 SampleHalfVector(const Probe& probe, double u0, double u1, int* cell = nullptr) const;
  int CellOf(const Vec3& h) const;  // theta_h cell of h (h.z >= 0), by its cosine: no acos
  int CellBySearch(double cos_theta) const;
  // The guide for CellOf: 32 buckets per octave of u = 1 - h.z over [2^-40, 1], and one below.
  static constexpr int kGuideMantissaBits = 5, kGuideOctaves = 40;
  static constexpr int kGuideBuckets = (kGuideOctaves << kGuideMantissaBits) + 1;
  static int GuideBucket(double u);
  std::array<int, kGuideBuckets> guide_{};  // the cell of each bucket's smallest u

  std::vector<double> theta_edges_, cos_edges_;
  std::vector<Probe> probes_;
};

// The sampling half of a Brdf sampled by a HalfVectorProxySampler (measured networks, MERL
// tables, tabulated fits): Sample, Pdf, GlossyProbability and the glossy part are the sampler's.
// The derived class fits the sampler at the end of its constructor, once Eval works
// (FitProxySampler), or shares one fitted to an identical BRDF.
class ProxySampledBrdf : public Brdf {
 public:
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const final {
    return sampler_->Sample(w_o, u_lobe, u0, u1);
  }
  double Pdf(const Vec3& w_o, const Vec3& w_i) const final { return sampler_->Pdf(w_o, w_i); }
  double GlossyProbability(const Vec3& w_o) const final { return sampler_->LobeProbability(w_o); }
  // The glossy part is the sampler's lobes (HalfVectorProxySampler::PrepareLobe).
  GlossyView PrepareGlossy(const Vec3& w_o) const final { return sampler_->PrepareLobe(w_o); }
  BrdfSample SampleGlossyAt(const GlossyView& view, double u_lobe, double u0,
                            double u1) const final {
    return sampler_->SampleLobe(view, u_lobe, u0, u1);
  }
  double GlossyPdfAt(const GlossyView& view, const Vec3& w_i) const final {
    return sampler_->LobePdf(view, w_i);
  }

  const HalfVectorProxySampler& sampler() const { return *sampler_; }

 protected:
  // Probes this BRDF's Eval (about 16000 evaluations).
  void FitProxySampler() { sampler_ = std::make_shared<const HalfVectorProxySampler>(*this); }
  std::shared_ptr<const HalfVectorProxySampler> sampler_;
};

}  // namespace zbrdf
