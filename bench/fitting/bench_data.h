// What the fitting benchmarks fit: the thesis rig's zone at the fast preset and a GGX material's
// zonal tensor with 1% noise (fixed seed), made once per order outside the timed regions.
#pragma once

#include <array>
#include <cmath>
#include <memory>
#include <random>

#include "basis/zone.h"
#include "brdf/ggx.h"
#include "fitting/fit_data.h"
#include "fitting/fit_quadrature.h"

namespace zbrdf::bench {

inline const Zone& ThesisZone() {
  static const Zone zone = Zone::FromDegrees(11.3, 54.9);  // the thesis rig at the fast preset
  return zone;
}

inline const ZonalTensor& NoisyGgxTensor(int order) {
  static std::array<std::unique_ptr<ZonalTensor>, 31> cache;
  if (!cache[order]) {
    const GgxBrdf ggx(0.15, 0.15, Rgb(0.3), Rgb(0.1, 0.2, 0.3));
    const auto iso = PairQuadrature(ThesisZone(), order).ProjectIsotropicBrdf(ggx);
    auto data = std::make_unique<ZonalTensor>();
    data->theta_min_rad = ThesisZone().theta_min_rad();
    data->theta_max_rad = ThesisZone().theta_max_rad();
    data->order = order;
    std::mt19937_64 rng(5);
    std::normal_distribution<double> normal;
    for (int ch = 0; ch < 3; ++ch) {
      data->z[ch] = IsotropicLayout(order).Expand(iso[ch]);
      const double sigma = 0.01 * std::sqrt(data->z[ch].squaredNorm() / data->z[ch].size());
      data->variance[ch] =
          Eigen::MatrixXd::Constant(data->z[ch].rows(), data->z[ch].cols(), sigma * sigma);
      for (Eigen::Index i = 0; i < data->z[ch].size(); ++i) {
        data->z[ch].data()[i] += sigma * normal(rng);
      }
    }
    cache[order] = std::move(data);
  }
  return *cache[order];
}

}  // namespace zbrdf::bench
