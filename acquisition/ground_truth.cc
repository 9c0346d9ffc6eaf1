#include "acquisition/ground_truth.h"

#include <cmath>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "basis/quadrature.h"

namespace zbrdf {

namespace {

uint64_t Mix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

uint32_t Reverse(uint32_t v) {
  v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  v = ((v >> 4) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4);
  v = ((v >> 8) & 0x00FF00FFu) | ((v & 0x00FF00FFu) << 8);
  return (v >> 16) | (v << 16);
}

// Point i of n of a 2-D Hammersley set, digitally shifted by (mask_u, mask_v).
void Point(int i, int n, uint32_t mask_u, uint32_t mask_v, double* u, double* v) {
  int bits = 0;
  while ((1 << bits) < n) ++bits;
  const uint32_t first = bits == 0 ? 0u : static_cast<uint32_t>(i) << (32 - bits);
  *u = (first ^ mask_u) * 0x1.0p-32;
  *v = (Reverse(static_cast<uint32_t>(i)) ^ mask_v) * 0x1.0p-32;
}

}  // namespace

void GroundTruthOptions::Validate() const {
  OptionChecker check("GroundTruthOptions");
  check.Require(samples >= 16 && (samples & (samples - 1)) == 0, "samples",
                "must be a power of two >= 16 (got " + std::to_string(samples) + ")")
      .AtLeast("phi_stride", phi_stride, 1)
      .ThrowIfInvalid();
}

GroundTruth TrueZonalCoefficients(const Brdf& material, const ZonalData& layout,
                                  const GroundTruthOptions& options) {
  options.Validate();
  const ExitantGrid& grid = layout.grid;
  const Zone zone = layout.zone();
  const ZonalBasis zb(zone, layout.order);
  const int n = zb.size();
  GroundTruth truth;
  for (int i = 0; i < grid.n_theta; ++i) {
    for (int j = 0; j < grid.n_phi; j += std::max(1, options.phi_stride)) truth.cells.push_back(i * grid.n_phi + j);
  }
  const int cells = static_cast<int>(truth.cells.size());
  truth.value.assign(n, {std::vector<double>(cells, 0.0), std::vector<double>(cells, 0.0),
                         std::vector<double>(cells, 0.0)});
  const bool glossy_or_delta = material.IsDelta() || [&] {
    for (double t : {0.3, 0.7, 1.1}) {
      if (material.GlossyProbability(SphericalDirection(t, 0.5)) > 0) return true;
    }
    return false;
  }();
  // Product rule over the zone for smooth materials.
  const SphereRule product = ProductRule(CosThetaPsiRule(zone, 48), 96);
  std::vector<std::vector<double>> product_z;
  if (!glossy_or_delta) {
    product_z.resize(product.weights.size(), std::vector<double>(n));
    for (size_t q = 0; q < product.weights.size(); ++q) zb.Eval(product.directions[q], product_z[q].data());
  }
  const double a = zone.cos_lower(), b = zone.cos_upper();
  const double sin2_lo = 1 - b * b, sin2_hi = 1 - a * a;
  const double projected = M_PI * (sin2_hi - sin2_lo);  // integral of cos over the zone
  const GaussLegendreRule cell_rule = GaussLegendre(2);
  ParallelFor(cells, 4, [&](int64_t c0, int64_t c1) {
    std::vector<double> z(n);
    for (int64_t ci = c0; ci < c1; ++ci) {
      const int cell = truth.cells[ci];
      const int row = cell / grid.n_phi, col = cell % grid.n_phi;
      const double x0 = std::cos(grid.ThetaHigh(row)), x1 = std::cos(grid.ThetaLow(row));
      std::array<std::vector<double>, 3> sum;
      for (auto& s : sum) s.assign(n, 0.0);
      for (int qi = 0; qi < 2; ++qi) {
        for (int qj = 0; qj < 2; ++qj) {
          const double x = 0.5 * (x0 + x1) + 0.5 * (x1 - x0) * cell_rule.nodes[qi];
          const double phi = (col + 0.5 + 0.5 * cell_rule.nodes[qj]) * grid.phi_step_rad;
          const double w_cell = 0.25 * cell_rule.weights[qi] * cell_rule.weights[qj];
          const double s = std::sqrt(std::max(0.0, 1 - x * x));
          const Vec3 w_r{s * std::cos(phi), s * std::sin(phi), x};
          auto add = [&](const Rgb& f_cos_over_p, const Vec3& w_i) {
            zb.Eval(w_i, z.data());
            for (int k = 0; k < n; ++k) {
              for (int ch = 0; ch < 3; ++ch) sum[ch][k] += w_cell * f_cos_over_p[ch] * z[k];
            }
          };
          if (material.IsDelta()) {
            const BrdfSample d = material.Sample(w_r, 0.5, 0.5, 0.5);
            if (d.is_delta && d.w_i.z > 0) add(d.delta_reflectance, d.w_i);
          } else if (!glossy_or_delta) {
            for (size_t q = 0; q < product.weights.size(); ++q) {
              const Vec3& w_i = product.directions[q];
              const Rgb f = material.Eval(w_i, w_r) * (w_i.z * product.weights[q]);
              for (int k = 0; k < n; ++k) {
                for (int ch = 0; ch < 3; ++ch) sum[ch][k] += w_cell * f[ch] * product_z[q][k];
              }
            }
          } else {
            // MIS: cosine-weighted over the zone and the glossy lobe, half the samples each.
            const int half = options.samples / 2;
            uint64_t state = Mix(options.seed ^ Mix(static_cast<uint64_t>(cell) * 4 + qi * 2 + qj));
            const uint32_t m0 = static_cast<uint32_t>(state), m1 = static_cast<uint32_t>(state >> 32);
            state = Mix(state);
            const uint32_t m2 = static_cast<uint32_t>(state), m3 = static_cast<uint32_t>(state >> 32);
            for (int strategy = 0; strategy < 2; ++strategy) {
              for (int i = 0; i < half; ++i) {
                double u, v;
                Point(i, half, strategy ? m2 : m0, strategy ? m3 : m1, &u, &v);
                Vec3 w_i;
                if (strategy == 0) {
                  const double sin2 = sin2_lo + u * (sin2_hi - sin2_lo);
                  const double st = std::sqrt(sin2), ct = std::sqrt(std::max(0.0, 1 - sin2));
                  w_i = {st * std::cos(2 * M_PI * v), st * std::sin(2 * M_PI * v), ct};
                } else {
                  const BrdfSample bs = material.SampleGlossy(w_r, (i + 0.5) / half, u, v);
                  if (bs.pdf <= 0) continue;
                  w_i = bs.w_i;
                }
                if (w_i.z < a || w_i.z > b) continue;
                const double q = half * (w_i.z / projected) + half * material.GlossyPdf(w_r, w_i);
                if (!(q > 0)) continue;
                add(material.Eval(w_i, w_r) * (w_i.z / q), w_i);
              }
            }
          }
        }
      }
      for (int k = 0; k < n; ++k) {
        for (int ch = 0; ch < 3; ++ch) truth.value[k][ch][ci] = sum[ch][k];
      }
    }
  });
  return truth;
}

double CoefficientError(const ZonalData& measured, const GroundTruth& truth) {
  const ExitantGrid& grid = measured.grid;
  double err = 0, norm = 0;
  for (size_t k = 0; k < truth.value.size() && k < measured.functions.size(); ++k) {
    for (size_t ci = 0; ci < truth.cells.size(); ++ci) {
      const int cell = truth.cells[ci];
      const double omega = grid.CellSolidAngle(cell / grid.n_phi);
      for (int ch = 0; ch < 3; ++ch) {
        const double d = measured.functions[k].value[ch][cell] - truth.value[k][ch][ci];
        err += omega * d * d;
        norm += omega * truth.value[k][ch][ci] * truth.value[k][ch][ci];
      }
    }
  }
  return norm > 0 ? std::sqrt(err / norm) : 0.0;
}

}  // namespace zbrdf
