// Sampling utilities shared by the BRDF models, renderers and the simulator.
//
// Distribution1D and Distribution2D are piecewise-constant densities on [0, 1) and [0, 1)^2
// built from non-negative cell weights (the tabulated-distribution sampler of Pharr, Jakob &
// Humphreys, "Physically Based Rendering", 4th ed., section A.4). Sample() inverts the CDF and
// Pdf() returns exactly the density Sample() draws from, so the two can be mixed and combined by
// multiple importance sampling.
//
// The half-vector helpers turn a density over microfacet normals h into a density over incident
// directions w_i = 2 (w_o.h) h - w_o (Walter et al. 2007, "Microfacet Models for Refraction
// through Rough Surfaces", eq. 14; Ghosh's thesis eq. 2.30): p(w_i) = p_h(h) / (4 |w_o.h|).
#pragma once

#include <array>
#include <span>
#include <vector>

#include "basis/vec3.h"
#include "brdf/brdf.h"

namespace zbrdf {

// A density on [0, 1) that is constant on each of n equal cells, proportional to the weights.
class Distribution1D {
 public:
  // Throws InputError if weights is empty, has a negative or non-finite entry, or sums to 0.
  explicit Distribution1D(std::span<const double> weights);

  int size() const { return static_cast<int>(weights_.size()); }
  double WeightSum() const { return sum_; }

  // x in [0, 1) with density Pdf(x), from u in [0, 1). Optionally returns the density and the
  // cell holding x. Never returns a point in a zero-weight cell.
  double Sample(double u, double* pdf = nullptr, int* cell = nullptr) const;
  // Density at x; 0 outside [0, 1).
  double Pdf(double x) const;

  // Cell index with probability Pmf(index) = weight / WeightSum(). u_remapped (optional) is u
  // rescaled to [0, 1) within the chosen cell, independent of the choice: reusable as a fresh
  // uniform number.
  int SampleDiscrete(double u, double* pmf = nullptr, double* u_remapped = nullptr) const;
  double Pmf(int cell) const;

 private:
  int FindCell(double u) const;
  int FindCellBySearch(double u) const;

  std::vector<double> weights_;
  std::vector<double> cdf_;  // size n + 1; cdf_[0] = 0, cdf_[n] = 1
  std::vector<int> guide_;   // size n; guide_[g] = FindCellBySearch(g / n)
  double sum_ = 0;
};

// A density on [0, 1)^2, constant on each of nx * ny equal cells, proportional to the weights
// (row-major: weights[iy * nx + ix]). Sampled as the marginal over rows (y) and then the
// conditional within the chosen row (x).
class Distribution2D {
 public:
  // Throws InputError if nx, ny < 1, the size is not nx * ny, a weight is negative or not
  // finite, or all weights are 0.
  Distribution2D(std::span<const double> weights, int nx, int ny);

  int nx() const { return nx_; }
  int ny() const { return ny_; }

  // (x, y) in [0, 1)^2 from (u0, u1) in [0, 1)^2: u1 picks the row, u0 the point in it.
  std::array<double, 2> Sample(double u0, double u1, double* pdf = nullptr) const;
  // Density at (x, y); 0 outside [0, 1)^2.
  double Pdf(double x, double y) const;
  // Probability of the cell (ix, iy): Pdf on that cell / (nx * ny).
  double CellProbability(int ix, int iy) const;

 private:
  int nx_ = 0, ny_ = 0;
  std::vector<Distribution1D> rows_;  // conditional densities of x given the row
  Distribution1D marginal_;           // density of y
};

// Microfacet normal of the pair (w_i, w_o): normalize(w_i + w_o), negated if its z is < 0 so
// that it lies in the upper hemisphere, like the normals a half-vector sampler draws.
// Returns false (and leaves *h alone) when w_i = -w_o, where it is undefined.
bool UpperHalfVector(const Vec3& w_i, const Vec3& w_o, Vec3* h);

// w_i = 2 (w_o.h) h - w_o: the mirror reflection of w_o about h (Ghosh eq. 2.29).
inline Vec3 ReflectAboutHalfVector(const Vec3& w_o, const Vec3& h) {
  return 2.0 * Dot(w_o, h) * h - w_o;
}

// Density of w_i = ReflectAboutHalfVector(w_o, h) when h has solid-angle density pdf_h over the
// upper hemisphere: pdf_h / (4 |w_o.h|). 0 when w_o.h = 0.
double HalfVectorToIncidentPdf(double pdf_h, const Vec3& w_o, const Vec3& h);

// The proposal most models use: with probability p_specular a specular lobe drawn as a half
// vector h (sample_h(u0, u1) returns a unit h with z >= 0) and reflected, w_i =
// ReflectAboutHalfVector(w_o, h); otherwise cosine-weighted hemisphere sampling for the diffuse
// part. u_lobe picks the lobe.
template <typename SampleHalfVector>
Vec3 SampleHalfVectorMixture(const Vec3& w_o, double p_specular, double u_lobe, double u0,
                             double u1, const SampleHalfVector& sample_h) {
  if (u_lobe < p_specular) return ReflectAboutHalfVector(w_o, sample_h(u0, u1));
  return SampleCosineHemisphere(u0, u1);
}

// Density of SampleHalfVectorMixture at w_i, given the half-vector sampler's solid-angle
// density pdf_h(h) for unit h with z >= 0: p_specular pdf_h(h) / (4 |w_o.h|) with h the upper
// half vector of (w_i, w_o), plus (1 - p_specular) max(0, cos theta_i) / pi.
template <typename HalfVectorDensity>
double HalfVectorMixturePdf(const Vec3& w_o, const Vec3& w_i, double p_specular,
                            const HalfVectorDensity& pdf_h) {
  double lobe = 0;
  Vec3 h;
  if (p_specular > 0 && UpperHalfVector(w_i, w_o, &h)) {
    lobe = HalfVectorToIncidentPdf(pdf_h(h), w_o, h);
  }
  return p_specular * lobe + (1.0 - p_specular) * CosineHemispherePdf(w_i);
}

// Turns a direction given in the frame (t, b, n) into the frame the vectors are expressed in.
inline Vec3 FromLocalFrame(const Vec3& local, const Vec3& t, const Vec3& b, const Vec3& n) {
  return local.x * t + local.y * b + local.z * n;
}

}  // namespace zbrdf
