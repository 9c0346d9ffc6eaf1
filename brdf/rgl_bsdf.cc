#include "brdf/rgl_bsdf.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <random>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "brdf/dbrdf.h"
#include "brdf/ggx.h"
#include "brdf/merl_table.h"
#include "brdf/nbrdf.h"
#include "brdf/spectral.h"

namespace zbrdf {
namespace {

// The square-root elevation and linear azimuth coordinates of the format (Dupuy & Jakob 2018,
// section 5.2): u = sqrt(theta / (pi/2)) puts more nodes near the normal, where lobes are sharp.
double ThetaToU(double theta) { return std::sqrt(std::max(0.0, theta) * (2.0 / M_PI)); }
double UToTheta(double u) { return u * u * (0.5 * M_PI); }
double PhiToU(double phi) { return (phi + M_PI) * (0.5 / M_PI); }
double UToPhi(double u) { return (2.0 * u - 1.0) * M_PI; }
double Wrap01(double u) { return u - std::floor(u); }

// |d omega / d u| of the map u -> (theta, phi): dtheta = pi u_x du_x, dphi = 2 pi du_y.
double SolidAngleJacobian(double u_x, double theta) {
  return 2.0 * M_PI * M_PI * u_x * std::sin(theta);
}

// The highest elevation at which the exporter evaluates a BRDF: models with 1 / cos factors
// (Ward) are unbounded at exactly 90 deg.
constexpr double kMaxEvalTheta = 89.5 * M_PI / 180.0;

// The shares of the three densities mixed into the sample-space warp (see MakeRglTensors): the
// visible normals, the density that spreads w_i evenly over its elevations, and the one that
// follows the relative change of f_r. Chosen on MERL networks and GGX (docs/formats.md, "How
// zbrdf fills the tables"): half on the change of f_r brings blue-acrylic's median error at its
// highlight from 6.5% to 0.8% (with 48 x 48 samples); the rest keeps nodes in the body and tails.
constexpr double kVisibleFraction = 0.2;
constexpr double kSpreadFraction = 0.3;
constexpr double kVariationFraction = 0.5;

// A table on a grid of u nodes (x: theta, y: phi), bilinearly interpolated like the readers'.
struct UGrid {
  int nx = 0, ny = 0;
  std::vector<float> values;  // ny * nx, x fastest

  double At(int x, int y) const { return values[static_cast<size_t>(y) * nx + x]; }
  double Eval(double ux, double uy) const {
    const double px = std::clamp(ux, 0.0, 1.0) * (nx - 1), py = std::clamp(uy, 0.0, 1.0) * (ny - 1);
    const int x = std::min(static_cast<int>(px), nx - 2),
              y = std::min(static_cast<int>(py), ny - 2);
    const double s = px - x, t = py - y;
    return (1 - t) * ((1 - s) * At(x, y) + s * At(x + 1, y)) +
           t * ((1 - s) * At(x, y + 1) + s * At(x + 1, y + 1));
  }
};

// Midpoint quadrature over the upper hemisphere in u coordinates: directions and solid-angle
// weights (they sum to 2 pi up to the rule's error).
struct HemisphereRule {
  std::vector<Vec3> directions;
  std::vector<double> weights;
  std::vector<std::array<double, 2>> u;
};

HemisphereRule MakeRule(int nx, int ny) {
  HemisphereRule rule;
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      const double ux = (x + 0.5) / nx, uy = (y + 0.5) / ny;
      const double theta = UToTheta(ux);
      rule.u.push_back({ux, uy});
      rule.directions.push_back(SphericalDirection(theta, UToPhi(uy)));
      rule.weights.push_back(SolidAngleJacobian(ux, theta) / (static_cast<double>(nx) * ny));
    }
  }
  return rule;
}

// Values of the ndf table at the rule's points.
std::vector<double> SampleAtRule(const UGrid& ndf, const HemisphereRule& rule) {
  std::vector<double> d(rule.u.size());
  for (size_t q = 0; q < d.size(); ++q) d[q] = ndf.Eval(rule.u[q][0], rule.u[q][1]);
  return d;
}

// Scales the table so that integral ndf(m) cos(theta_m) dm = 1 under the rule.
void NormalizeNdf(UGrid* ndf, const HemisphereRule& rule) {
  const std::vector<double> d = SampleAtRule(*ndf, rule);
  double integral = 0;
  for (size_t q = 0; q < d.size(); ++q) integral += rule.weights[q] * d[q] * rule.directions[q].z;
  ZBRDF_ASSERT(integral > 0, "ndf table integrates to 0");
  for (float& v : ndf->values) v = static_cast<float>(v / integral);
}

// sigma(w) = integral max(0, w.m) ndf(m) dm on the nodes of a grid (x: theta, y: phi).
UGrid ProjectedArea(const UGrid& ndf, const HemisphereRule& rule, int nx, int ny) {
  const std::vector<double> d = SampleAtRule(ndf, rule);
  UGrid sigma{nx, ny, std::vector<float>(static_cast<size_t>(nx) * ny)};
  ParallelFor(static_cast<int64_t>(nx) * ny, 16, [&](int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      const int x = static_cast<int>(i % nx), y = static_cast<int>(i / nx);
      const Vec3 w = SphericalDirection(UToTheta(x / (nx - 1.0)), UToPhi(y / (ny - 1.0)));
      double sum = 0;
      for (size_t q = 0; q < d.size(); ++q) {
        const double c = Dot(w, rule.directions[q]);
        if (c > 0) sum += rule.weights[q] * c * d[q];
      }
      sigma.values[i] = static_cast<float>(sum);
    }
  });
  return sigma;
}

// The microfacet distribution explaining the retro-reflection of an arbitrary BRDF: for a
// microfacet model f(w, w) = F ndf(w) / (4 sigma(w)^2) (Smith masking, G1 = cos / sigma), so
// ndf is the fixed point of ndf <- f_Y(w, w) sigma(w)^2, normalized (Dupuy & Jakob 2018,
// section 4, "power iteration"). A small uniform floor keeps ndf > 0 where f(w, w) = 0.
UGrid RetroReflectionNdf(const Brdf& brdf, int nx, int ny, const HemisphereRule& rule) {
  UGrid retro{nx, ny, std::vector<float>(static_cast<size_t>(nx) * ny)};
  bool any = false;
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      const Vec3 w = SphericalDirection(std::min(UToTheta(x / (nx - 1.0)), kMaxEvalTheta),
                                        UToPhi(y / (ny - 1.0)));
      const double f = brdf.Eval(w, w).Luminance();
      const double value = std::isfinite(f) && f > 0 ? f : 0.0;
      retro.values[static_cast<size_t>(y) * nx + x] = static_cast<float>(value);
      any = any || value > 0;
    }
  }
  UGrid ndf = retro;
  if (!any) {
    std::fill(ndf.values.begin(), ndf.values.end(), static_cast<float>(1.0 / M_PI));
    return ndf;
  }
  // Start from sigma = cos(theta).
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      const double c = std::cos(UToTheta(x / (nx - 1.0)));
      ndf.values[static_cast<size_t>(y) * nx + x] *= static_cast<float>(c * c);
    }
  }
  NormalizeNdf(&ndf, rule);
  for (int iteration = 0; iteration < 6; ++iteration) {
    const UGrid sigma = ProjectedArea(ndf, rule, nx, ny);
    for (size_t i = 0; i < ndf.values.size(); ++i) {
      ndf.values[i] = static_cast<float>(retro.values[i] * sigma.values[i] * sigma.values[i]);
    }
    NormalizeNdf(&ndf, rule);
  }
  for (float& v : ndf.values) v = static_cast<float>(0.999 * v + 0.001 / M_PI);
  NormalizeNdf(&ndf, rule);
  return ndf;
}

// |grad_u log Y(f_r(w_i, w_o))| at the nodes of an n x n grid in u, w_i = reflect(w_o, m(u)):
// the relative change of f_r per unit of u, averaged from the cells around each node (cells with
// a corner where w_i is below the horizon or Y(f_r) <= 0 count 0). As a warp density it spreads
// the sample nodes evenly over the decades of f_r, so that a narrow highlight gets as many nodes
// as its drop in log f_r asks for, whatever its share of the energy or of the ndf's mass.
template <typename NormalAt>
std::vector<double> LogVariation(const Brdf& brdf, const Vec3& w_o, int n,
                                 const NormalAt& normal_at) {
  const size_t count = static_cast<size_t>(n) * n;
  std::vector<Vec3> w_i(count);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const Vec3 m = normal_at(x / (n - 1.0), y / (n - 1.0));
      w_i[static_cast<size_t>(y) * n + x] = 2.0 * Dot(w_o, m) * m - w_o;
    }
  }
  const std::vector<Vec3> w_o_all(count, w_o);
  std::vector<Rgb> f(count);
  brdf.EvalBatch(w_i, w_o_all, f);
  std::vector<double> log_f(count, 0.0);
  std::vector<char> valid(count, 0);
  for (size_t i = 0; i < count; ++i) {
    const double luminance = f[i].Luminance();
    if (w_i[i].z > 0 && luminance > 0 && std::isfinite(luminance)) {
      valid[i] = 1;
      log_f[i] = std::log(luminance);
    }
  }
  std::vector<double> variation(count, 0.0);
  for (int y = 0; y + 1 < n; ++y) {
    for (int x = 0; x + 1 < n; ++x) {
      const size_t i = static_cast<size_t>(y) * n + x;
      const size_t corners[4] = {i, i + 1, i + n, i + n + 1};
      if (!(valid[corners[0]] && valid[corners[1]] && valid[corners[2]] && valid[corners[3]])) {
        continue;
      }
      // Central differences of the cell, in log units per unit of u.
      const double gx = 0.5 * (n - 1) * (log_f[i + 1] - log_f[i] + log_f[i + n + 1] - log_f[i + n]);
      const double gy = 0.5 * (n - 1) * (log_f[i + n] - log_f[i] + log_f[i + n + 1] - log_f[i + 1]);
      const double g = std::sqrt(gx * gx + gy * gy);
      for (size_t c : corners) variation[c] += 0.25 * g;
    }
  }
  return variation;
}

struct SliceResult {
  std::vector<float> vndf, luminance;
  std::vector<Rgb> r;  // R at the sample nodes
  ValueCheck check;
};

}  // namespace

bool LooksIsotropic(const Brdf& brdf) {
  if (dynamic_cast<const MerlBrdf*>(&brdf) || dynamic_cast<const NbrdfBrdf*>(&brdf)) return true;
  if (const auto* rgl = dynamic_cast<const RglBrdf*>(&brdf)) return rgl->isotropic();
  std::mt19937_64 rng(0x15075);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  auto direction = [&]() {
    return SphericalDirection(std::acos(0.05 + 0.95 * uniform(rng)), 2 * M_PI * uniform(rng));
  };
  for (int probe = 0; probe < 48; ++probe) {
    const Vec3 w_i = direction(), w_o = direction();
    const double angle = 2 * M_PI * uniform(rng);
    const double c = std::cos(angle), s = std::sin(angle);
    auto rotate = [&](const Vec3& v) { return Vec3{c * v.x - s * v.y, s * v.x + c * v.y, v.z}; };
    const Rgb a = brdf.Eval(w_i, w_o), b = brdf.Eval(rotate(w_i), rotate(w_o));
    for (int k = 0; k < 3; ++k) {
      if (!(std::abs(a[k] - b[k]) <= 1e-6 * std::max(std::abs(a[k]), std::abs(b[k])) + 1e-300)) {
        return false;
      }
    }
  }
  return true;
}

void RglExportOptions::Validate() const {
  OptionChecker check("RglExportOptions");
  check.InRange("theta_nodes", theta_nodes, 2, 1024)
      .InRange("phi_nodes", phi_nodes, 3, 1024)
      .InRange("ndf_resolution", ndf_resolution, 8, 4096)
      .InRange("vndf_resolution", vndf_resolution, 4, 4096)
      .InRange("vndf_resolution_anisotropic", vndf_resolution_anisotropic, 4, 4096)
      .InRange("sample_resolution", sample_resolution, 4, 4096)
      .ThrowIfInvalid();
}

void MakeRglTensors(const Brdf& brdf, const RglExportOptions& options, RglExportReport* report,
                    TensorFile* rgb, TensorFile* spectral) {
  if (brdf.IsDelta()) {
    throw InputError("rgl export: " + brdf.Spec() +
                     " is a delta (mirror) material; a .bsdf file tabulates densities and cannot "
                     "hold it. Use the renderer's own conductor material instead");
  }
  options.Validate();
  RglExportReport local_report;
  RglExportReport& rep = report ? *report : local_report;
  rep = RglExportReport();
  rep.values.clamp = options.clamp_invalid;
  rep.isotropic = LooksIsotropic(brdf);

  // The microfacet distribution, on the ndf grid.
  const int ndf_nx = options.ndf_resolution,
            ndf_ny = rep.isotropic ? 2 : options.ndf_resolution / 2;
  const HemisphereRule rule = rep.isotropic
                                  ? MakeRule(2 * options.ndf_resolution, options.ndf_resolution)
                                  : MakeRule(options.ndf_resolution, options.ndf_resolution / 2);
  UGrid ndf{ndf_nx, ndf_ny, std::vector<float>(static_cast<size_t>(ndf_nx) * ndf_ny)};
  auto tabulate = [&](const auto& d_of_h) {
    for (int y = 0; y < ndf_ny; ++y) {
      for (int x = 0; x < ndf_nx; ++x) {
        const Vec3 h = SphericalDirection(UToTheta(x / (ndf_nx - 1.0)), UToPhi(y / (ndf_ny - 1.0)));
        ndf.values[static_cast<size_t>(y) * ndf_nx + x] = static_cast<float>(d_of_h(h));
      }
    }
  };
  if (const auto* ggx = dynamic_cast<const GgxBrdf*>(&brdf)) {
    rep.ndf_source = "ggx D";
    tabulate([&](const Vec3& h) { return ggx->D(h); });
  } else if (const auto* dbrdf = dynamic_cast<const DBrdf*>(&brdf)) {
    rep.ndf_source = "dbrdf p(h)";
    tabulate(
        [&](const Vec3& h) { return dbrdf->table().Eval(SphericalTheta(h), SphericalPhi(h)); });
  } else {
    rep.ndf_source = "retro-reflection (power iteration)";
    ndf = RetroReflectionNdf(brdf, ndf_nx, ndf_ny, rule);
  }
  const int sigma_nx = 64, sigma_ny = rep.isotropic ? 2 : 64;
  const UGrid sigma = ProjectedArea(ndf, rule, sigma_nx, sigma_ny);

  // Parameter nodes: w_o elevations and azimuths.
  const int nt = options.theta_nodes, np = rep.isotropic ? 1 : options.phi_nodes;
  std::vector<float> theta_nodes(nt), phi_nodes(np, 0.0f);
  for (int k = 0; k < nt; ++k) theta_nodes[k] = static_cast<float>(0.5 * M_PI * k / (nt - 1));
  for (int m = 0; m < np && np > 1; ++m) {
    phi_nodes[m] = static_cast<float>(-M_PI + 2 * M_PI * m / (np - 1));
  }

  const int vn = rep.isotropic ? options.vndf_resolution : options.vndf_resolution_anisotropic;
  const int sn = options.sample_resolution;
  std::vector<SliceResult> slices(static_cast<size_t>(np) * nt);
  ParallelFor(static_cast<int64_t>(slices.size()), 1, [&](int64_t begin, int64_t end) {
    for (int64_t index = begin; index < end; ++index) {
      SliceResult& out = slices[index];
      out.check.clamp = options.clamp_invalid;
      const int m = static_cast<int>(index / nt), k = static_cast<int>(index % nt);
      const double theta_o = theta_nodes[k], phi_o = phi_nodes[m];
      const Vec3 w_o = SphericalDirection(std::min(theta_o, kMaxEvalTheta), phi_o);
      const double azimuth_offset = rep.isotropic ? phi_o : 0.0;
      auto normal_at = [&](double ux, double uy) {
        return SphericalDirection(UToTheta(ux), UToPhi(uy) + azimuth_offset);
      };
      // The warp of the sample space: the visible normals of w_o as a density in u,
      // ndf(m) max(0, w_o.m) |d omega / d u|, mixed with the density that spreads w_i evenly in
      // (theta_i, phi_i), |d w_i / d u| / sin(theta_i) = 4 (w_o.m) |d omega / d u| / sin(theta_i),
      // both cut off where w_i falls below the horizon, and with |grad_u log f_r| (LogVariation).
      // Any density is a valid warp for the readers. The spread keeps sample nodes in the tails
      // of the lobe, and the cut-off makes every row of the sample grid end at the horizon of
      // w_i (within one warp cell), where f_r cos(theta_i) falls linearly to 0: bilinear
      // interpolation then follows it instead of overshooting. The variation term is there for
      // measured materials, whose ndf comes from retro-reflection: blue-acrylic's highlight falls
      // 20x within 0.5 deg of the mirror direction, yet the visible normals put 95% of their mass
      // more than 1 deg from the normal (the ndf's diffuse floor), while the stored f_r / ndf
      // varies within the highlight by up to 2x (the lobe at oblique w_o is not the
      // retro-reflection's). Without the term the highlight (theta_m < 0.3 deg) lay within the
      // first column of a 32 x 32 sample grid, with it it spans 3-6 (docs/formats.md).
      std::vector<double> visible(static_cast<size_t>(vn) * vn), spread(visible.size());
      double visible_sum = 0, spread_sum = 0;
      for (int y = 0; y < vn; ++y) {
        for (int x = 0; x < vn; ++x) {
          const double ux = x / (vn - 1.0), uy = y / (vn - 1.0);
          const Vec3 h = normal_at(ux, uy);
          const double cos_oh = std::max(0.0, Dot(w_o, h));
          const double jacobian = SolidAngleJacobian(ux, UToTheta(ux));
          const size_t i = static_cast<size_t>(y) * vn + x;
          const bool above = 2.0 * cos_oh * h.z - w_o.z > 0;  // w_i = reflect(w_o, h) above
          visible[i] = above ? ndf.Eval(ux, uy) * cos_oh * jacobian : 0.0;
          const double cos_i = 2.0 * cos_oh * h.z - w_o.z;
          const double sin_i = std::sqrt(std::max(0.0, 1.0 - cos_i * cos_i));
          spread[i] = above ? 4.0 * cos_oh * jacobian / std::max(sin_i, 1e-3) : 0.0;
          visible_sum += visible[i];
          spread_sum += spread[i];
        }
      }
      const std::vector<double> variation = LogVariation(brdf, w_o, vn, normal_at);
      double variation_sum = 0;
      for (double g : variation) variation_sum += g;
      // A term that is 0 everywhere (a Lambertian slice) gives its share to the visible normals.
      const double variation_fraction = variation_sum > 0 ? kVariationFraction : 0.0;
      const double visible_fraction = kVisibleFraction + (kVariationFraction - variation_fraction);
      out.vndf.resize(visible.size());
      for (size_t i = 0; i < visible.size(); ++i) {
        const double v = visible_sum > 0 ? visible[i] / visible_sum : 0.0;
        const double u = spread_sum > 0 ? spread[i] / spread_sum : 0.0;
        const double g = variation_sum > 0 ? variation[i] / variation_sum : 0.0;
        out.vndf[i] =
            static_cast<float>(visible_fraction * v + kSpreadFraction * u + variation_fraction * g);
      }
      const BilinearWarp2D warp(vn, vn, out.vndf, {}, true);
      const double sigma_o = sigma.Eval(ThetaToU(theta_o), PhiToU(phi_o));
      out.r.resize(static_cast<size_t>(sn) * sn);
      out.luminance.resize(out.r.size());
      for (int y = 0; y < sn; ++y) {
        for (int x = 0; x < sn; ++x) {
          const auto [ux, uy, density] = warp.Sample({x / (sn - 1.0), y / (sn - 1.0)});
          const Vec3 h = normal_at(ux, uy);
          const double cos_oh = Dot(w_o, h);
          const Vec3 w_i = 2.0 * cos_oh * h - w_o;
          const double d = ndf.Eval(ux, uy);
          Rgb r;
          double importance = 0;
          if (w_i.z > 0 && d > 0 && cos_oh > 0) {
            const Rgb f = out.check.Apply(brdf.Eval(w_i, w_o));
            r = f * (w_i.z * 4.0 * sigma_o / d);
            // The luminance warp turns the sample-space density into one proportional to
            // Y(f_r) cos(theta_i) over w_i: divide that target, in u, by the warp's density.
            if (density > 0) {
              importance = std::max(0.0, f.Luminance()) * w_i.z * 4.0 * cos_oh *
                           SolidAngleJacobian(ux, UToTheta(ux)) / density;
            }
          }
          out.r[static_cast<size_t>(y) * sn + x] = r;
          out.luminance[static_cast<size_t>(y) * sn + x] = static_cast<float>(importance);
        }
      }
    }
  });
  for (const SliceResult& s : slices) rep.values.Merge(s.check);
  rep.values.Finish("rgl export of " + brdf.Spec());

  const uint64_t n_phi = np, n_theta = nt, s_n = sn;
  std::vector<float> vndf, luminance;
  for (const SliceResult& s : slices) {
    vndf.insert(vndf.end(), s.vndf.begin(), s.vndf.end());
    luminance.insert(luminance.end(), s.luminance.begin(), s.luminance.end());
  }
  TensorFile common;
  common["theta_i"] = TensorField::Float32({n_theta}, theta_nodes);
  common["phi_i"] = TensorField::Float32({n_phi}, phi_nodes);
  common["ndf"] = TensorField::Float32(
      {static_cast<uint64_t>(ndf_ny), static_cast<uint64_t>(ndf_nx)}, ndf.values);
  common["sigma"] = TensorField::Float32(
      {static_cast<uint64_t>(sigma_ny), static_cast<uint64_t>(sigma_nx)}, sigma.values);
  common["vndf"] = TensorField::Float32(
      {n_phi, n_theta, static_cast<uint64_t>(vn), static_cast<uint64_t>(vn)}, vndf);
  common["luminance"] = TensorField::Float32({n_phi, n_theta, s_n, s_n}, luminance);
  const uint8_t jacobian = 1;
  common["jacobian"] = TensorField::UInt8({1}, std::span<const uint8_t>(&jacobian, 1));
  const std::string description =
      options.description.empty() ? "zbrdf export of " + brdf.Spec() : options.description;
  common["description"] = TensorField::UInt8(
      {description.size()},
      std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(description.data()),
                               description.size()));
  const size_t slice_size = static_cast<size_t>(sn) * sn;
  if (spectral) {
    *spectral = common;
    const SpectralBasis basis = SpectralBasis::Default();
    const size_t n_lambda = basis.wavelengths_nm().size();
    std::vector<float> spectra;
    spectra.reserve(slices.size() * n_lambda * slice_size);
    for (const SliceResult& s : slices) {
      std::vector<std::vector<double>> per_node(slice_size);
      for (size_t i = 0; i < slice_size; ++i) {
        double error = 0;
        per_node[i] = basis.Upsample(s.r[i], &error);
        const double scale = s.r[i].Max();
        if (scale > 0 && error > 1e-9 * scale) {
          ++rep.out_of_gamut;
          rep.max_gamut_error = std::max(rep.max_gamut_error, error / scale);
        }
      }
      for (size_t l = 0; l < n_lambda; ++l) {
        for (size_t i = 0; i < slice_size; ++i) {
          spectra.push_back(static_cast<float>(per_node[i][l]));
        }
      }
    }
    std::vector<float> wavelengths(basis.wavelengths_nm().begin(), basis.wavelengths_nm().end());
    (*spectral)["spectra"] = TensorField::Float32({n_phi, n_theta, n_lambda, s_n, s_n}, spectra);
    (*spectral)["wavelengths"] = TensorField::Float32({n_lambda}, wavelengths);
  }
  if (rgb) {
    *rgb = std::move(common);
    std::vector<float> values;
    values.reserve(slices.size() * 3 * slice_size);
    for (const SliceResult& s : slices) {
      for (int c = 0; c < 3; ++c) {
        for (size_t i = 0; i < slice_size; ++i) values.push_back(static_cast<float>(s.r[i][c]));
      }
    }
    (*rgb)["rgb"] = TensorField::Float32({n_phi, n_theta, 3, s_n, s_n}, values);
  }
}

RglExportReport WriteRglFile(const std::string& path, const Brdf& brdf,
                             const RglExportOptions& options, bool spectral) {
  RglExportReport report;
  TensorFile tensors;
  MakeRglTensors(brdf, options, &report, spectral ? nullptr : &tensors,
                 spectral ? &tensors : nullptr);
  WriteTensorFile(path, tensors);
  return report;
}

namespace {

const TensorField& RequireField(const TensorFile& file, const std::string& path,
                                const std::string& name) {
  auto it = file.find(name);
  if (it == file.end()) {
    throw InputError("RGL file " + path + ": the field '" + name +
                     "' is missing; it is not a measured-material .bsdf file");
  }
  return it->second;
}

void RequireShape(const std::string& path, const std::string& name, const TensorField& field,
                  const std::vector<int64_t>& expected) {
  bool ok = field.shape.size() == expected.size();
  for (size_t k = 0; ok && k < expected.size(); ++k) {
    ok = expected[k] < 0 || static_cast<int64_t>(field.shape[k]) == expected[k];
  }
  if (!ok) {
    std::string got, want;
    for (uint64_t s : field.shape) got += (got.empty() ? "" : " x ") + std::to_string(s);
    for (int64_t s : expected)
      want += (want.empty() ? "" : " x ") + (s < 0 ? "N" : std::to_string(s));
    throw InputError("RGL file " + path + ": field '" + name + "' has shape [" + got +
                     "], expected [" + want + "]");
  }
}

}  // namespace

std::unique_ptr<RglBrdf> RglBrdf::FromFile(const std::string& path) {
  const TensorFile file = ReadTensorFile(path);
  std::unique_ptr<RglBrdf> brdf(new RglBrdf());
  brdf->path_ = path;
  auto floats = [&](const std::string& name) {
    return RequireField(file, path, name).AsFloat32("RGL file " + path + ": field '" + name + "'");
  };
  const std::vector<float> theta = floats("theta_i"), phi = floats("phi_i");
  const int64_t nt = static_cast<int64_t>(theta.size()), np = static_cast<int64_t>(phi.size());
  const TensorField& ndf = RequireField(file, path, "ndf");
  const TensorField& sigma = RequireField(file, path, "sigma");
  const TensorField& vndf = RequireField(file, path, "vndf");
  const TensorField& luminance = RequireField(file, path, "luminance");
  RequireShape(path, "ndf", ndf, {-1, -1});
  RequireShape(path, "sigma", sigma, {-1, -1});
  RequireShape(path, "vndf", vndf, {np, nt, -1, -1});
  RequireShape(path, "luminance", luminance, {np, nt, -1, -1});
  const int64_t sn = static_cast<int64_t>(luminance.shape[2]);
  RequireShape(path, "luminance", luminance, {np, nt, sn, sn});
  const TensorField& jacobian = RequireField(file, path, "jacobian");
  if (jacobian.type != TensorField::Type::kUInt8 || jacobian.Count() != 1) {
    throw InputError("RGL file " + path + ": field 'jacobian' must be one uint8");
  }
  brdf->jacobian_ = jacobian.bytes[0] != 0;
  if (auto it = file.find("description"); it != file.end()) {
    brdf->description_.assign(it->second.bytes.begin(), it->second.bytes.end());
  }
  brdf->isotropic_ = np <= 2;
  if (!brdf->isotropic_) {
    const int reduction = static_cast<int>(std::lrint(2 * M_PI / (phi.back() - phi.front())));
    if (reduction != 1) {
      throw InputError("RGL file " + path + ": phi_i covers 1/" + std::to_string(reduction) +
                       " of the circle (a symmetry reduction); only full-circle files are read");
    }
  }
  // RGB per node: the rgb field, or the spectra reduced with the observer.
  std::vector<float> rgb;
  if (file.count("wavelengths")) {
    const std::vector<float> lambda = floats("wavelengths");
    const TensorField& spectra = RequireField(file, path, "spectra");
    RequireShape(path, "spectra", spectra, {np, nt, static_cast<int64_t>(lambda.size()), sn, sn});
    const std::vector<float> values = floats("spectra");
    const SpectralBasis basis(std::vector<double>(lambda.begin(), lambda.end()));
    const size_t slice = static_cast<size_t>(sn) * sn, n_lambda = lambda.size();
    rgb.resize(static_cast<size_t>(np * nt) * 3 * slice);
    for (int64_t p = 0; p < np * nt; ++p) {
      for (size_t i = 0; i < slice; ++i) {
        Rgb sum;
        for (size_t l = 0; l < n_lambda; ++l) {
          sum += basis.NodeWeight(static_cast<int>(l)) * values[(p * n_lambda + l) * slice + i];
        }
        for (int c = 0; c < 3; ++c) rgb[(p * 3 + c) * slice + i] = static_cast<float>(sum[c]);
      }
    }
  } else {
    RequireShape(path, "rgb", RequireField(file, path, "rgb"), {np, nt, 3, sn, sn});
    rgb = floats("rgb");
  }
  const std::vector<std::vector<float>> params = {phi, theta};
  brdf->ndf_ = BilinearWarp2D(static_cast<int>(ndf.shape[1]), static_cast<int>(ndf.shape[0]),
                              floats("ndf"), {}, false);
  brdf->sigma_ = BilinearWarp2D(static_cast<int>(sigma.shape[1]), static_cast<int>(sigma.shape[0]),
                                floats("sigma"), {}, false);
  brdf->vndf_ = BilinearWarp2D(static_cast<int>(vndf.shape[3]), static_cast<int>(vndf.shape[2]),
                               floats("vndf"), params, true);
  brdf->luminance_ =
      BilinearWarp2D(static_cast<int>(sn), static_cast<int>(sn), floats("luminance"), params, true);
  brdf->rgb_ = BilinearWarp2D(static_cast<int>(sn), static_cast<int>(sn), rgb,
                              {phi, theta, {0.0f, 1.0f, 2.0f}}, false);
  return brdf;
}

Rgb RglBrdf::Eval(const Vec3& w_i, const Vec3& w_o) const {
  if (w_i.z <= 0 || w_o.z <= 0) return {};
  const Vec3 m = Normalize(w_i + w_o);
  const double theta_o = SphericalTheta(w_o), phi_o = std::atan2(w_o.y, w_o.x);
  const double phi_m = std::atan2(m.y, m.x);
  const std::array<double, 2> u_m = {ThetaToU(SphericalTheta(m)),
                                     Wrap01(PhiToU(isotropic_ ? phi_m - phi_o : phi_m))};
  const double params[2] = {phi_o, theta_o};
  const auto [sx, sy, vndf_density] = vndf_.Invert(u_m, params);
  (void)vndf_density;
  Rgb value;
  for (int c = 0; c < 3; ++c) {
    const double channel_params[3] = {phi_o, theta_o, static_cast<double>(c)};
    value[c] = std::max(0.0, rgb_.Eval({sx, sy}, channel_params));
  }
  if (jacobian_) {
    const double sigma = sigma_.Eval({ThetaToU(theta_o), PhiToU(phi_o)});
    if (!(sigma > 0)) return {};
    value *= ndf_.Eval(u_m) / (4.0 * sigma);
  }
  // The table holds f_r cos(theta_i).
  return value / w_i.z;
}

BrdfSample RglBrdf::Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const {
  (void)u_lobe;
  BrdfSample s;
  if (w_o.z <= 0) return s;
  const double theta_o = SphericalTheta(w_o), phi_o = std::atan2(w_o.y, w_o.x);
  const double params[2] = {phi_o, theta_o};
  const auto [sx, sy, luminance_density] = luminance_.Sample({u0, u1}, params);
  const auto [ux, uy, vndf_density] = vndf_.Sample({sx, sy}, params);
  const double theta_m = UToTheta(ux);
  const double phi_m = UToPhi(uy) + (isotropic_ ? phi_o : 0.0);
  const Vec3 m = SphericalDirection(theta_m, phi_m);
  const double cos_om = Dot(w_o, m);
  const double jacobian = std::max(SolidAngleJacobian(ux, theta_m), 1e-6) * 4.0 * cos_om;
  if (!(cos_om > 0) || !(jacobian > 0)) return s;
  s.w_i = 2.0 * cos_om * m - w_o;
  s.pdf = vndf_density * luminance_density / jacobian;
  return s;
}

double RglBrdf::Pdf(const Vec3& w_o, const Vec3& w_i) const {
  if (w_o.z <= 0) return 0;
  const Vec3 sum = w_i + w_o;
  if (Dot(sum, sum) == 0) return 0;
  const Vec3 m = Normalize(sum);
  const double cos_om = Dot(w_o, m);
  if (m.z <= 0 || cos_om <= 0) return 0;
  const double theta_o = SphericalTheta(w_o), phi_o = std::atan2(w_o.y, w_o.x);
  const double theta_m = SphericalTheta(m), phi_m = std::atan2(m.y, m.x);
  const std::array<double, 2> u_m = {ThetaToU(theta_m),
                                     Wrap01(PhiToU(isotropic_ ? phi_m - phi_o : phi_m))};
  const double params[2] = {phi_o, theta_o};
  const auto [sx, sy, vndf_density] = vndf_.Invert(u_m, params);
  const double luminance_density = luminance_.Eval({sx, sy}, params);
  const double jacobian = std::max(SolidAngleJacobian(u_m[0], theta_m), 1e-6) * 4.0 * cos_om;
  return vndf_density * luminance_density / jacobian;
}

}  // namespace zbrdf
