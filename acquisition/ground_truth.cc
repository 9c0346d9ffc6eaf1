#include "acquisition/ground_truth.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/hash.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "basis/quadrature.h"
#include "basis/spherical_harmonics.h"
#include "brdf/fingerprint.h"

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
  // An isotropic material is integrated at phi_r = 0 once per grid row and rotated (below);
  // otherwise every cell is integrated at its 2 x 2 points.
  const bool isotropic = material.IsIsotropic() && !material.IsDelta();
  const int items = isotropic ? grid.n_theta : cells;
  std::vector<std::array<std::vector<double>, 3>> row_sums(isotropic ? grid.n_theta : 0);
  ParallelFor(items, isotropic ? 1 : 4, [&](int64_t c0, int64_t c1) {
    std::vector<double> z(n);
    std::vector<Vec3> batch_in, batch_out;
    std::vector<double> batch_scale;
    std::vector<Rgb> batch_f;
    std::vector<int> lobe_order;
    for (int64_t ci = c0; ci < c1; ++ci) {
      const int cell = isotropic ? static_cast<int>(ci) * grid.n_phi : truth.cells[ci];
      const int row = cell / grid.n_phi, col = cell % grid.n_phi;
      const double x0 = std::cos(grid.ThetaHigh(row)), x1 = std::cos(grid.ThetaLow(row));
      std::array<std::vector<double>, 3> sum;
      for (auto& s : sum) s.assign(n, 0.0);
      for (int qi = 0; qi < 2; ++qi) {
        for (int qj = 0; qj < (isotropic ? 1 : 2); ++qj) {
          const double x = 0.5 * (x0 + x1) + 0.5 * (x1 - x0) * cell_rule.nodes[qi];
          const double phi =
              isotropic ? 0.0 : (col + 0.5 + 0.5 * cell_rule.nodes[qj]) * grid.phi_step_rad;
          const double w_cell = isotropic ? 0.5 * cell_rule.weights[qi]
                                          : 0.25 * cell_rule.weights[qi] * cell_rule.weights[qj];
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
            // An isotropic row takes 4 times the samples of a cell (two points instead of four,
            // each with 4x): at a fraction of the cells' cost it has half their noise variance.
            const int half = (isotropic ? 4 : 1) * options.samples / 2;
            const uint64_t point = isotropic ? (1ull << 40) + static_cast<uint64_t>(row) * 2 + qi
                                             : static_cast<uint64_t>(cell) * 4 + qi * 2 + qj;
            uint64_t state = Mix(options.seed ^ Mix(point));
            const uint32_t m0 = static_cast<uint32_t>(state), m1 = static_cast<uint32_t>(state >> 32);
            state = Mix(state);
            const uint32_t m2 = static_cast<uint32_t>(state), m3 = static_cast<uint32_t>(state >> 32);
            // The lobe choice u_lobe is stratified too, but paired with the points in a random
            // order: paired in index order it would correlate with the point's first coordinate
            // (a digitally shifted i / n), and a mixture sampler (HalfVectorProxySampler picks
            // its probe by u_lobe, its theta_h cell by u) would then draw each probe's samples
            // from a fixed part of [0, 1): a bias no sample count removes.
            lobe_order.resize(half);
            for (int i = 0; i < half; ++i) lobe_order[i] = i;
            for (int i = half - 1; i > 0; --i) {
              state = Mix(state);
              std::swap(lobe_order[i], lobe_order[static_cast<int>(state % static_cast<uint64_t>(i + 1))]);
            }
            const Brdf::GlossyView view = material.PrepareGlossy(w_r);  // once per point
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
                  const BrdfSample bs = material.SampleGlossyAt(view, (lobe_order[i] + 0.5) / half, u, v);
                  if (bs.pdf <= 0) continue;
                  w_i = bs.w_i;
                }
                if (w_i.z < a || w_i.z > b) continue;
                const double q = half * (w_i.z / projected) + half * material.GlossyPdfAt(view, w_i);
                if (!(q > 0)) continue;
                batch_in.push_back(w_i);
                batch_scale.push_back(w_i.z / q);
              }
            }
            // One batched evaluation per exitant point (a network evaluates blocks much faster
            // than single pairs); the sum runs in sample order as before.
            batch_out.assign(batch_in.size(), w_r);
            batch_f.resize(batch_in.size());
            material.EvalBatch(batch_in, batch_out, batch_f);
            for (size_t s = 0; s < batch_in.size(); ++s) add(batch_f[s] * batch_scale[s], batch_in[s]);
            batch_in.clear();
            batch_scale.clear();
          }
        }
      }
      if (isotropic) {
        row_sums[ci] = std::move(sum);
        continue;
      }
      for (int k = 0; k < n; ++k) {
        for (int ch = 0; ch < 3; ++ch) truth.value[k][ch][ci] = sum[ch][k];
      }
    }
  });
  if (isotropic) {
    // f_r(R w_i, R w_r) = f_r(w_i, w_r) for a rotation R by alpha about the normal, so with
    // c = z_l,m and s = z_l,-m at phi_r = 0 (m > 0; Z_lm ~ cos(m phi), Z_l,-m ~ sin(m phi)):
    //   z_l,m(alpha) = c cos(m alpha) - s sin(m alpha),  z_l,-m(alpha) = s cos(m alpha) + c sin(m alpha),
    // and z_l0 does not depend on alpha. A cell's average takes the exact averages of
    // cos(m alpha) and sin(m alpha) over its azimuth interval.
    for (int ci = 0; ci < cells; ++ci) {
      const int cell = truth.cells[ci];
      const int row = cell / grid.n_phi, col = cell % grid.n_phi;
      const double p0 = col * grid.phi_step_rad, p1 = (col + 1) * grid.phi_step_rad;
      for (int l = 0; l <= layout.order; ++l) {
        for (int ch = 0; ch < 3; ++ch) {
          truth.value[ShIndex(l, 0)][ch][ci] = row_sums[row][ch][ShIndex(l, 0)];
        }
        for (int m = 1; m <= l; ++m) {
          const double cos_avg = (std::sin(m * p1) - std::sin(m * p0)) / (m * (p1 - p0));
          const double sin_avg = (std::cos(m * p0) - std::cos(m * p1)) / (m * (p1 - p0));
          for (int ch = 0; ch < 3; ++ch) {
            const double c = row_sums[row][ch][ShIndex(l, m)], s = row_sums[row][ch][ShIndex(l, -m)];
            truth.value[ShIndex(l, m)][ch][ci] = c * cos_avg - s * sin_avg;
            truth.value[ShIndex(l, -m)][ch][ci] = s * cos_avg + c * sin_avg;
          }
        }
      }
    }
  }
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

namespace zbrdf {

GroundTruth TrueZonalCoefficientsCached(const Brdf& material, const ZonalData& layout,
                                        const GroundTruthOptions& options,
                                        const std::string& cache_dir) {
  if (cache_dir.empty()) return TrueZonalCoefficients(material, layout, options);
  options.Validate();
  // Bump the version when TrueZonalCoefficients changes its values for the same inputs (v7:
  // the half-vector proxy's lobe is the nearer probe's, brdf/proxy_sampler.h).
  char text[320];
  const ExitantGrid& g = layout.grid;
  std::snprintf(text, sizeof(text),
                "zbrdf truth v7 zone %.17g %.17g grid %.17g %.17g %.17g %.17g %d %d order %d "
                "samples %d phi_stride %d seed %llu material ",
                layout.theta_min_rad, layout.theta_max_rad, g.theta_min_rad, g.theta_max_rad,
                g.theta_step_rad, g.phi_step_rad, g.n_theta, g.n_phi, layout.order, options.samples,
                options.phi_stride, static_cast<unsigned long long>(options.seed));
  const std::string key = text + MaterialCacheKey(material);
  char name[48];
  std::snprintf(name, sizeof(name), "truth-%016llx.bin", static_cast<unsigned long long>(Fnv1a64(key)));
  const std::string path = (std::filesystem::path(cache_dir) / name).string();
  {
    std::ifstream in(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // Layout: key, '\n', cells (uint32), functions (uint32), cells x int32, then per function
    // and channel cells x double, then the FNV-1a of everything before it.
    const size_t head = key.size() + 1 + 8;
    if (bytes.size() > head + 8 && bytes.compare(0, key.size(), key) == 0 && bytes[key.size()] == '\n') {
      uint32_t cells = 0, functions = 0;
      std::memcpy(&cells, bytes.data() + key.size() + 1, 4);
      std::memcpy(&functions, bytes.data() + key.size() + 5, 4);
      const size_t body = static_cast<size_t>(cells) * 4 + static_cast<size_t>(functions) * 3 * cells * 8;
      uint64_t stored = 0;
      if (bytes.size() == head + body + 8) {
        std::memcpy(&stored, bytes.data() + head + body, 8);
        if (stored == Fnv1a64(bytes.data(), head + body)) {
          GroundTruth truth;
          truth.cells.resize(cells);
          std::memcpy(truth.cells.data(), bytes.data() + head, cells * 4);
          const char* p = bytes.data() + head + cells * 4;
          truth.value.resize(functions);
          for (auto& channels : truth.value) {
            for (auto& v : channels) {
              v.resize(cells);
              std::memcpy(v.data(), p, cells * 8);
              p += cells * 8;
            }
          }
          return truth;
        }
      }
    }
  }
  GroundTruth truth = TrueZonalCoefficients(material, layout, options);
  std::string bytes = key + "\n";
  const uint32_t cells = static_cast<uint32_t>(truth.cells.size());
  const uint32_t functions = static_cast<uint32_t>(truth.value.size());
  bytes.append(reinterpret_cast<const char*>(&cells), 4);
  bytes.append(reinterpret_cast<const char*>(&functions), 4);
  bytes.append(reinterpret_cast<const char*>(truth.cells.data()), cells * 4);
  for (const auto& channels : truth.value) {
    for (const auto& v : channels) bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * 8);
  }
  const uint64_t sum = Fnv1a64(bytes);
  bytes.append(reinterpret_cast<const char*>(&sum), 8);
  WriteCacheFile(path, {bytes});  // a failure only means the next run computes it again
  return truth;
}

}  // namespace zbrdf
