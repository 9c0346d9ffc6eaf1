// Independent numerical checks shared by the BRDF tests: fixed-seed random numbers, adaptive
// cubature over the sphere, directional albedo, reciprocity, and the chi-square test of a
// sampler against its Pdf (after pbrt-v4's bsdfs_test.cpp: histogram over (cos theta, phi) -- or
// over (sin(alpha / 2), phi) about a sharp lobe's axis --, expected counts from integrating Pdf
// over each bin, pooling of low-expectation bins, Sidak-corrected threshold).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "basis/vec3.h"
#include "brdf/brdf.h"

namespace zbrdf::testing {

// Uniform doubles in [0, 1) with 53 random bits, from a fixed seed.
class Rng {
 public:
  explicit Rng(uint64_t seed) : engine_(seed) {}
  double Uniform() { return static_cast<double>(engine_() >> 11) * 0x1p-53; }

 private:
  std::mt19937_64 engine_;
};

// Uniform direction on the upper hemisphere, z in (z_min, 1].
inline Vec3 RandomUpperDirection(Rng& rng, double z_min = 0.0) {
  const double z = z_min + (1.0 - z_min) * (1.0 - rng.Uniform());
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = 2.0 * M_PI * rng.Uniform();
  return {r * std::cos(phi), r * std::sin(phi), z};
}

inline Vec3 DirectionFromCosPhi(double cos_theta, double phi) {
  const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  return {s * std::cos(phi), s * std::sin(phi), cos_theta};
}

// Integral of g over a rectangle [x0, x1] x [y0, y1] by adaptive Simpson cubature on a
// quadtree: a cell's 3x3-point Simpson estimate is compared with the sum over its four children
// (a 5x5 grid); a cell is accepted, with Richardson's correction, when they differ by at most
// 15 max(abs_tol, rel_tol |sum|) after at least min_depth splits, or at max_depth. Children get
// half their parent's absolute tolerance, so that refinement along a discontinuity stops.
struct CubatureOptions {
  double abs_tol = 1e-10;
  double rel_tol = 1e-7;
  int min_depth = 2;
  int max_depth = 10;
};

class Cubature {
 public:
  Cubature(const std::function<double(double, double)>& g, const CubatureOptions& options)
      : g_(g), options_(options) {}

  double Integrate(double x0, double x1, double y0, double y1) {
    double v[3][3];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) v[i][j] = g_(x0 + 0.5 * i * (x1 - x0), y0 + 0.5 * j * (y1 - y0));
    }
    return Step(x0, x1, y0, y1, v, Simpson(v, x1 - x0, y1 - y0), options_.abs_tol, 0);
  }

 private:
  static double Simpson(const double (&v)[3][3], double width, double height) {
    static constexpr double w[3] = {1, 4, 1};
    double sum = 0;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) sum += w[i] * w[j] * v[i][j];
    }
    return sum * width * height / 36.0;
  }

  double Step(double x0, double x1, double y0, double y1, const double (&v)[3][3], double whole,
              double abs_tol, int depth) {
    double grid[5][5];
    for (int i = 0; i < 5; ++i) {
      for (int j = 0; j < 5; ++j) {
        grid[i][j] = (i % 2 == 0 && j % 2 == 0)
                         ? v[i / 2][j / 2]
                         : g_(x0 + 0.25 * i * (x1 - x0), y0 + 0.25 * j * (y1 - y0));
      }
    }
    double child[2][2][3][3];
    double parts[2][2];
    double sum = 0;
    for (int a = 0; a < 2; ++a) {
      for (int b = 0; b < 2; ++b) {
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) child[a][b][i][j] = grid[2 * a + i][2 * b + j];
        }
        parts[a][b] = Simpson(child[a][b], 0.5 * (x1 - x0), 0.5 * (y1 - y0));
        sum += parts[a][b];
      }
    }
    const double error = sum - whole;
    const double tol = std::max(abs_tol, options_.rel_tol * std::abs(sum));
    if (depth >= options_.max_depth ||
        (depth >= options_.min_depth && std::abs(error) <= 15.0 * tol)) {
      return sum + error / 15.0;
    }
    double total = 0;
    for (int a = 0; a < 2; ++a) {
      for (int b = 0; b < 2; ++b) {
        const double cx0 = x0 + 0.5 * a * (x1 - x0), cy0 = y0 + 0.5 * b * (y1 - y0);
        total += Step(cx0, cx0 + 0.5 * (x1 - x0), cy0, cy0 + 0.5 * (y1 - y0), child[a][b],
                      parts[a][b], 0.5 * abs_tol, depth + 1);
      }
    }
    return total;
  }

  const std::function<double(double, double)>& g_;
  CubatureOptions options_;
};

// Coordinates of directions about a unit axis: a radial coordinate x and the azimuth phi in
// the frame OrthonormalBasis(axis) gives. x is cos(alpha), alpha the angle to the axis
// (dw = dx dphi, equal-area bins), or sin(alpha / 2) (dw = 4 x dx dphi), which resolves the
// neighbourhood of the axis finely and turns a 1 / |w - axis| singularity at the axis into a
// bounded integrand.
struct AxisFrame {
  enum class Radial { kCosine, kSinHalfAngle };

  Vec3 t{1, 0, 0}, b{0, 1, 0}, n{0, 0, 1};
  Radial radial = Radial::kCosine;

  AxisFrame() = default;
  AxisFrame(const Vec3& axis, Radial radial_coordinate) : n(axis), radial(radial_coordinate) {
    OrthonormalBasis(axis, &t, &b);
  }

  double RadialMin() const { return radial == Radial::kCosine ? -1.0 : 0.0; }
  Vec3 Direction(double x, double phi) const {
    const double cos_alpha = radial == Radial::kCosine ? x : 1.0 - 2.0 * x * x;
    const Vec3 local = DirectionFromCosPhi(cos_alpha, phi);
    return local.x * t + local.y * b + local.z * n;
  }
  double Jacobian(double x) const { return radial == Radial::kCosine ? 1.0 : 4.0 * x; }
  void Coordinates(const Vec3& w, double* x, double* phi) const {
    const double cos_alpha = std::clamp(Dot(w, n), -1.0, 1.0);
    *x = radial == Radial::kCosine ? cos_alpha : std::sqrt(0.5 * (1.0 - cos_alpha));
    *phi = std::atan2(Dot(w, b), Dot(w, t));
    if (*phi < 0) *phi += 2.0 * M_PI;
  }
};

// A point of (x, phi) where the integrand may be singular (the half-vector samplers' density
// grows like 1 / |w_i + w_o| near w_i = -w_o). Cells containing it are split there, so that the
// point is a corner, where the cubature refines, instead of a spike it can miss.
struct SingularPoint {
  double x = 2.0;  // outside [-1, 1]: none
  double phi = 0.0;
};

// Integral of g(direction) dw over the cell x in [x0, x1], phi in [p0, p1] about the frame's
// axis.
inline double IntegrateCell(const std::function<double(const Vec3&)>& g, double x0, double x1,
                            double p0, double p1, const CubatureOptions& options,
                            const AxisFrame& frame = {}, const SingularPoint& singular = {}) {
  if (singular.x > x0 && singular.x < x1) {
    return IntegrateCell(g, x0, singular.x, p0, p1, options, frame, singular) +
           IntegrateCell(g, singular.x, x1, p0, p1, options, frame, singular);
  }
  if (singular.x >= x0 && singular.x <= x1 && singular.phi > p0 && singular.phi < p1) {
    return IntegrateCell(g, x0, x1, p0, singular.phi, options, frame, singular) +
           IntegrateCell(g, x0, x1, singular.phi, p1, options, frame, singular);
  }
  const std::function<double(double, double)> in_coordinates = [&](double x, double phi) {
    return g(frame.Direction(x, phi)) * frame.Jacobian(x);
  };
  return Cubature(in_coordinates, options).Integrate(x0, x1, p0, p1);
}

// Integral of g(direction) dw over the zone cos theta in [cos_lo, cos_hi] (about +z), on a grid
// of cells each integrated adaptively.
struct SphereGrid {
  int cos_cells = 16;
  int phi_cells = 32;
  CubatureOptions cubature;
};

inline double IntegrateZone(const std::function<double(const Vec3&)>& g, double cos_lo,
                            double cos_hi, const SphereGrid& grid = {}) {
  double total = 0;
  for (int i = 0; i < grid.cos_cells; ++i) {
    const double c0 = cos_lo + (cos_hi - cos_lo) * i / grid.cos_cells;
    const double c1 = cos_lo + (cos_hi - cos_lo) * (i + 1) / grid.cos_cells;
    for (int j = 0; j < grid.phi_cells; ++j) {
      total += IntegrateCell(g, c0, c1, 2.0 * M_PI * j / grid.phi_cells,
                             2.0 * M_PI * (j + 1) / grid.phi_cells, grid.cubature, AxisFrame());
    }
  }
  return total;
}

// Directional albedo integral f_r(w_i, w_o)[channel] cos(theta_i) dw_i, by quadrature.
inline double DirectionalAlbedo(const Brdf& brdf, const Vec3& w_o, int channel = 0,
                                const SphereGrid& grid = {}) {
  return IntegrateZone([&](const Vec3& w_i) { return brdf.Eval(w_i, w_o)[channel] * w_i.z; }, 0.0,
                       1.0, grid);
}

// Largest relative asymmetry |f(a, b) - f(b, a)| / max(|f|, floor) over random pairs of
// upper-hemisphere directions, all channels.
inline double MaxReciprocityError(const Brdf& brdf, uint64_t seed, int pairs = 2000,
                                  double floor = 1e-12) {
  Rng rng(seed);
  double worst = 0;
  for (int n = 0; n < pairs; ++n) {
    const Vec3 a = RandomUpperDirection(rng), b = RandomUpperDirection(rng);
    const Rgb fab = brdf.Eval(a, b), fba = brdf.Eval(b, a);
    for (int c = 0; c < 3; ++c) {
      const double scale = std::max({std::abs(fab[c]), std::abs(fba[c]), floor});
      worst = std::max(worst, std::abs(fab[c] - fba[c]) / scale);
    }
  }
  return worst;
}

// Upper regularized incomplete gamma function Q(a, x) (series for x < a + 1, else Lentz's
// continued fraction; Press et al., "Numerical Recipes", 3rd ed., section 6.2).
inline double RegularizedGammaQ(double a, double x) {
  if (x <= 0) return 1.0;
  const double log_prefix = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 100000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return 1.0 - sum * std::exp(log_prefix);
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int n = 1; n < 100000; ++n) {
    const double an = -n * (n - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return std::exp(log_prefix) * h;
}

// p-value of a chi-square statistic with dof degrees of freedom.
inline double ChiSquarePValue(double chi2, int dof) {
  return RegularizedGammaQ(0.5 * dof, 0.5 * chi2);
}

// Significance of one chi-square test such that up to kChiSquareTests tests in this binary (it
// has about 30) together reject correct samplers with probability at most 1% (Sidak correction).
constexpr int kChiSquareTests = 100;
inline double ChiSquareSignificance() { return 1.0 - std::pow(1.0 - 0.01, 1.0 / kChiSquareTests); }

struct SamplingCheck {
  double p_value = 0;  // chi-square test of the histogram against Pdf
  double chi2 = 0;
  int dof = 0;
  double pdf_integral = 0;      // quadrature of Pdf over the sphere
  double max_pdf_mismatch = 0;  // max |sample.pdf - Pdf(w_i)| / Pdf(w_i)
  double max_length_error = 0;  // max ||w_i| - 1|
  int no_sample = 0;            // Sample() calls that returned pdf = 0
  int unexpected = 0;           // samples in bins where Pdf integrates to ~0
  std::string summary;          // for failure messages
};

struct SamplingCheckOptions {
  int samples = 200000;
  int radial_bins = 20;  // over x in [-1, 1] (cosine) or [0, 1] (sine of the half angle)
  int phi_bins = 40;
  double min_expected = 5.0;  // pool bins expecting fewer samples (pbrt-v4: 5)
  // Bins are laid out over (cos theta, phi) about +z by default. Laying them out about a sharp
  // lobe's axis with the sin(alpha / 2) coordinate resolves the lobe and puts its peak on the
  // cells' corners, where the cubature sees it.
  AxisFrame bins;
  // Per bin: the expected counts need relative accuracy well below 1 / sqrt(count) (~1e-3).
  CubatureOptions cubature{1e-12, 1e-6, 2, 9};
  // Per cell of the normalization integral (PdfIntegral).
  CubatureOptions integral_cubature{1e-13, 1e-7, 2, 10};
  // For densities piecewise constant over cells of theta_h, the half vector's polar angle (a
  // half-vector table, the proxy's cells): the cells' edges, from 0 to pi/2. Given, the
  // normalization integral is taken over half vectors (PdfIntegralOverHalfVectors), where those
  // cells are the quadrature's and the density has no jump inside one.
  std::vector<double> half_vector_theta_edges;
};

// For densities that are piecewise constant over cells of theta_h (a measured or fitted p(h)
// table, the half-vector proxy's 128 cells): they jump at every cell edge, where adaptive
// cubature refines slowly. 1e-4 relative per bin is ample against the ~1/sqrt(300) sampling noise
// of a bin, and 1e-6 per normalization cell resolves the edges to ~1e-4 of the total, so a 1e-3
// bound on the normalization still catches a wrong factor or exponent (>= 1e-2).
inline SamplingCheckOptions PiecewiseDensityCubature() {
  SamplingCheckOptions options;
  options.cubature = {1e-10, 1e-4, 2, 8};
  options.integral_cubature = {1e-11, 1e-6, 2, 9};
  return options;
}

// integral Pdf(w_o, w) dw over the sphere, in sin(alpha / 2) coordinates about -w_o, where the
// half-vector samplers' 1 / |w + w_o| singularity becomes a bounded integrand; an 8 x 16 grid of
// cells integrated adaptively.
inline double PdfIntegral(const Brdf& brdf, const Vec3& w_o, const CubatureOptions& options) {
  const AxisFrame frame(-w_o, AxisFrame::Radial::kSinHalfAngle);
  const auto pdf = [&](const Vec3& w_i) { return brdf.Pdf(w_o, w_i); };
  double total = 0;
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 16; ++j) {
      total += IntegrateCell(pdf, i / 8.0, (i + 1) / 8.0, 2 * M_PI * j / 16,
                             2 * M_PI * (j + 1) / 16, options, frame);
    }
  }
  return total;
}

// integral Pdf(w_o, w) dw over the sphere, over half vectors instead: w = 2 (w_o.h) h - w_o maps
// the upper hemisphere of h onto the sphere once (w's two half vectors are +-(w + w_o) / |w +
// w_o|, and one of them has h.z >= 0) with dw = 4 |w_o.h| dh (Walter et al. 2007, "Microfacet
// models for refraction", eq. 14). A half-vector sampler's lobe density p_h(h) / (4 |w_o.h|)
// becomes p_h(h) itself there, so a p_h that is piecewise constant over cells of theta_h has no
// jump inside the quadrature's cells when these are the density's: theta_edges (0 .. pi/2) by
// 8 azimuth cells, each integrated adaptively in (theta_h, phi_h) with dh = sin theta_h. In
// (sin(alpha / 2), phi) about -w_o (PdfIntegral) the same edges are 128 curves across the cells,
// each refined to the tolerance at every depth. A cell's nodes stay 1e-6 of its width inside its
// edges: a node on an edge would take either cell's value by rounding (theta_h is resolved to
// ~1e-12 rad near the normal). The integral over the narrower cell is scaled by the ratio of the
// widths: the slivers left out (2e-6 of the cell) are filled with the cell's mean, an error of
// 2e-6 times the density's relative change across the cell.
inline double PdfIntegralOverHalfVectors(const Brdf& brdf, const Vec3& w_o,
                                         const std::vector<double>& theta_edges,
                                         const CubatureOptions& options) {
  const std::function<double(double, double)> integrand = [&](double theta, double phi) {
    const Vec3 h = SphericalDirection(theta, phi);
    const double cos_oh = Dot(w_o, h);
    const Vec3 w_i = 2.0 * cos_oh * h - w_o;
    return brdf.Pdf(w_o, w_i) * 4.0 * std::abs(cos_oh) * std::sin(theta);
  };
  constexpr int kPhiCells = 8;
  double total = 0;
  for (size_t k = 0; k + 1 < theta_edges.size(); ++k) {
    const double width = theta_edges[k + 1] - theta_edges[k], margin = 1e-6 * width;
    const double t0 = theta_edges[k] + margin, t1 = theta_edges[k + 1] - margin;
    double cell = 0;
    for (int j = 0; j < kPhiCells; ++j) {
      cell += Cubature(integrand, options)
                  .Integrate(t0, t1, 2.0 * M_PI * j / kPhiCells, 2.0 * M_PI * (j + 1) / kPhiCells);
    }
    total += cell * width / (t1 - t0);
  }
  return total;
}

// For the half-vector proxy (HalfVectorProxySampler, which samples measured materials): the
// piecewise-constant cubature, and the normalization over half vectors on the proxy's cells as
// brdf/proxy_sampler.h documents them (128 cells of theta_h = (pi/2) x^2 for x uniform), where
// its density has no jump.
inline SamplingCheckOptions ProxyCellsCubature() {
  SamplingCheckOptions options = PiecewiseDensityCubature();
  for (int k = 0; k <= 128; ++k) {
    options.half_vector_theta_edges.push_back(0.5 * M_PI * k * k / (128.0 * 128.0));
  }
  return options;
}

// Draws opts.samples directions from brdf.Sample(w_o, ...) with a fixed seed, and compares their
// histogram over the bins with the integral of brdf.Pdf over each bin.
inline SamplingCheck CheckSampling(const Brdf& brdf, const Vec3& w_o, uint64_t seed,
                                   const SamplingCheckOptions& opts = {}) {
  SamplingCheck check;
  const AxisFrame& frame = opts.bins;
  const double x_min = frame.RadialMin(), x_range = 1.0 - x_min;
  const int bins = opts.radial_bins * opts.phi_bins;
  std::vector<double> observed(bins, 0.0), expected(bins, 0.0);
  Rng rng(seed);
  for (int n = 0; n < opts.samples; ++n) {
    const double u_lobe = rng.Uniform(), u0 = rng.Uniform(), u1 = rng.Uniform();
    const BrdfSample s = brdf.Sample(w_o, u_lobe, u0, u1);
    if (!(s.pdf > 0)) {
      ++check.no_sample;
      continue;
    }
    const double pdf = brdf.Pdf(w_o, s.w_i);
    check.max_pdf_mismatch = std::max(check.max_pdf_mismatch, std::abs(s.pdf - pdf) / pdf);
    check.max_length_error = std::max(check.max_length_error, std::abs(Length(s.w_i) - 1.0));
    double x = 0, phi = 0;
    frame.Coordinates(s.w_i, &x, &phi);
    const int ix =
        std::min(static_cast<int>((x - x_min) / x_range * opts.radial_bins), opts.radial_bins - 1);
    const int ip =
        std::min(static_cast<int>(phi / (2.0 * M_PI) * opts.phi_bins), opts.phi_bins - 1);
    observed[ix * opts.phi_bins + ip] += 1;
  }
  const auto pdf = [&](const Vec3& w_i) { return brdf.Pdf(w_o, w_i); };
  SingularPoint singular;
  frame.Coordinates(-w_o, &singular.x, &singular.phi);
  for (int ix = 0; ix < opts.radial_bins; ++ix) {
    const double x0 = x_min + x_range * ix / opts.radial_bins;
    const double x1 = x_min + x_range * (ix + 1) / opts.radial_bins;
    for (int ip = 0; ip < opts.phi_bins; ++ip) {
      const double p0 = 2.0 * M_PI * ip / opts.phi_bins;
      const double p1 = 2.0 * M_PI * (ip + 1) / opts.phi_bins;
      expected[ix * opts.phi_bins + ip] =
          IntegrateCell(pdf, x0, x1, p0, p1, opts.cubature, frame, singular) * opts.samples;
    }
  }
  check.pdf_integral =
      opts.half_vector_theta_edges.empty()
          ? PdfIntegral(brdf, w_o, opts.integral_cubature)
          : PdfIntegralOverHalfVectors(brdf, w_o, opts.half_vector_theta_edges,
                                       opts.integral_cubature);
  // Pool bins in increasing order of expectation until the pool expects min_expected samples.
  std::vector<int> order(bins);
  for (int k = 0; k < bins; ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return expected[a] < expected[b]; });
  double pooled_observed = 0, pooled_expected = 0;
  for (int k : order) {
    if (expected[k] <= 1e-9 * opts.samples) {
      // Bins the density (nearly) never reaches: a sample there is a sampler bug, unless a
      // handful come from the bin's sliver of positive density.
      if (observed[k] > 1e-5 * opts.samples) ++check.unexpected;
      pooled_observed += observed[k];
      pooled_expected += expected[k];
    } else if (expected[k] < opts.min_expected ||
               (pooled_expected > 0 && pooled_expected < opts.min_expected)) {
      // Keep pooling until the pool itself expects enough samples.
      pooled_observed += observed[k];
      pooled_expected += expected[k];
    } else {
      const double diff = observed[k] - expected[k];
      check.chi2 += diff * diff / expected[k];
      ++check.dof;
    }
  }
  if (pooled_expected > 0) {
    const double diff = pooled_observed - pooled_expected;
    check.chi2 += diff * diff / pooled_expected;
    ++check.dof;
  }
  check.dof -= 1;  // the counts sum to the number of samples
  check.p_value = check.dof > 0 ? ChiSquarePValue(check.chi2, check.dof) : 0.0;
  std::ostringstream out;
  out << brdf.Spec().substr(0, 80) << " w_o=(" << w_o.x << "," << w_o.y << "," << w_o.z
      << "): chi2=" << check.chi2 << " dof=" << check.dof << " p=" << check.p_value
      << " pdf_integral-1=" << check.pdf_integral - 1.0 << " no_sample=" << check.no_sample
      << " unexpected=" << check.unexpected << " max_pdf_mismatch=" << check.max_pdf_mismatch;
  check.summary = out.str();
  return check;
}

// The assertions every sampler must pass: Sample's pdf is Pdf(), directions are unit vectors,
// every call gives a sample, no samples where Pdf is ~0, the chi-square test passes at the
// Sidak-corrected level, and Pdf integrates to 1 over the sphere to within pdf_integral_tol
// (set by the caller from the quadrature's accuracy on the density's shape; a normalization
// mistake, such as a wrong exponent or factor, is 1e-3 or more).
// Optional last argument: SamplingCheckOptions.
#define EXPECT_SAMPLING_MATCHES_PDF(brdf, w_o, seed, pdf_integral_tol, ...)                 \
  do {                                                                                      \
    const ::zbrdf::testing::SamplingCheck check_ =                                          \
        ::zbrdf::testing::CheckSampling((brdf), (w_o), (seed)__VA_OPT__(, ) __VA_ARGS__);   \
    /* Sample calls Pdf-equivalent code; agreement to rounding. */                          \
    EXPECT_LE(check_.max_pdf_mismatch, 1e-9) << check_.summary;                             \
    EXPECT_LE(check_.max_length_error, 1e-12) << check_.summary;                            \
    EXPECT_EQ(check_.no_sample, 0) << check_.summary;                                       \
    EXPECT_EQ(check_.unexpected, 0) << check_.summary;                                      \
    EXPECT_GT(check_.p_value, ::zbrdf::testing::ChiSquareSignificance()) << check_.summary; \
    EXPECT_NEAR(check_.pdf_integral, 1.0, (pdf_integral_tol)) << check_.summary;            \
  } while (0)

}  // namespace zbrdf::testing
