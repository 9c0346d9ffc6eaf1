#include "brdf/merl_export.h"

#include <cmath>
#include <mutex>
#include <vector>

#include "basis/parallel.h"

namespace zbrdf {

void MerlPairAt(double theta_h, double theta_d, double phi_d, Vec3* w_i, Vec3* w_o) {
  const Vec3 d = SphericalDirection(theta_d, phi_d);
  // Rotate the difference vector by theta_h about y (h lies in the x-z plane at phi_h = 0).
  const double c = std::cos(theta_h), s = std::sin(theta_h);
  *w_i = {c * d.x + s * d.z, d.y, -s * d.x + c * d.z};
  const Vec3 h{s, 0.0, c};
  *w_o = 2.0 * Dot(*w_i, h) * h - *w_i;
}

void MerlBinCenter(int i, int j, int k, double* theta_h, double* theta_d, double* phi_d) {
  const double u = (i + 0.5) / MerlTable::kThetaHalfBins;
  *theta_h = u * u * (0.5 * M_PI);
  *theta_d = (j + 0.5) / MerlTable::kThetaDiffBins * (0.5 * M_PI);
  *phi_d = (k + 0.5) / MerlTable::kPhiDiffBins * M_PI;
}

MerlTable SampleMerlTable(const Brdf& brdf, ValueCheck* check) {
  MerlTable table;
  table.f.resize(MerlTable::kBinCount);
  std::mutex mutex;
  // One task per (theta_h, theta_d) row of 180 phi_d bins, evaluated as a batch.
  const int rows = MerlTable::kThetaHalfBins * MerlTable::kThetaDiffBins;
  ParallelFor(rows, 8, [&](int64_t begin, int64_t end) {
    ValueCheck local;
    local.clamp = check->clamp;
    std::vector<Vec3> w_i(MerlTable::kPhiDiffBins), w_o(MerlTable::kPhiDiffBins);
    std::vector<Rgb> f(MerlTable::kPhiDiffBins);
    for (int64_t row = begin; row < end; ++row) {
      const int i = static_cast<int>(row / MerlTable::kThetaDiffBins);
      const int j = static_cast<int>(row % MerlTable::kThetaDiffBins);
      for (int k = 0; k < MerlTable::kPhiDiffBins; ++k) {
        double theta_h, theta_d, phi_d;
        MerlBinCenter(i, j, k, &theta_h, &theta_d, &phi_d);
        MerlPairAt(theta_h, theta_d, phi_d, &w_i[k], &w_o[k]);
      }
      brdf.EvalBatch(w_i, w_o, f);
      for (int k = 0; k < MerlTable::kPhiDiffBins; ++k) {
        const bool below = w_i[k].z <= 0 || w_o[k].z <= 0;
        table.f[MerlTable::Index(i, j, k)] = below ? Rgb() : local.Apply(f[k]);
      }
    }
    std::lock_guard<std::mutex> lock(mutex);
    check->Merge(local);
  });
  return table;
}

}  // namespace zbrdf
