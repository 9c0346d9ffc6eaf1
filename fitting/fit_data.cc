#include "fitting/fit_data.h"

#include <cmath>

#include "basis/error.h"
#include "basis/spherical_harmonics.h"

namespace zbrdf {

int ZonalTensor::size() const { return ShCount(order); }

std::string ZonalTensor::Problems() const {
  if (order < 0 || order > 30) return "zonal data: order " + std::to_string(order) + " is out of range";
  if (!(theta_min_rad >= 0 && theta_min_rad < theta_max_rad && theta_max_rad <= 0.5 * M_PI + 1e-12)) {
    return "zonal data: the zone is not a valid range of theta in [0, 90] deg";
  }
  const int n = size();
  for (int ch = 0; ch < 3; ++ch) {
    if (z[ch].rows() != n || z[ch].cols() != n || variance[ch].rows() != n ||
        variance[ch].cols() != n) {
      return std::string("zonal data: channel ") + kRgbChannelNames[ch] + " tensor is not " +
             std::to_string(n) + " x " + std::to_string(n) + " for order " + std::to_string(order);
    }
    for (int k = 0; k < n; ++k) {
      for (int j = 0; j < n; ++j) {
        if (!std::isfinite(z[ch](k, j))) {
          return std::string("zonal data: channel ") + kRgbChannelNames[ch] + " coefficient (" +
                 std::to_string(k) + ", " + std::to_string(j) + ") is not finite";
        }
        const double v = variance[ch](k, j);
        if (!(v >= 0) || std::isnan(v)) {
          return std::string("zonal data: channel ") + kRgbChannelNames[ch] + " variance (" +
                 std::to_string(k) + ", " + std::to_string(j) + ") is negative or NaN";
        }
      }
    }
  }
  return "";
}

IsotropicLayout::IsotropicLayout(int order) : order_(order), size_(0) {
  ZBRDF_ASSERT(order >= 0, "negative order");
  offset_.resize(order + 1);
  for (int m = 0; m <= order; ++m) {
    offset_[m] = size_;
    size_ += (order + 1 - m) * (order + 1 - m);
  }
}

Eigen::MatrixXd IsotropicLayout::Expand(const Eigen::VectorXd& isotropic) const {
  ZBRDF_ASSERT(isotropic.size() == size_, "isotropic vector of the wrong size");
  const int n = ShCount(order_);
  Eigen::MatrixXd full = Eigen::MatrixXd::Zero(n, n);
  for (int m = 0; m <= order_; ++m) {
    for (int l = m; l <= order_; ++l) {
      for (int lp = m; lp <= order_; ++lp) {
        const double v = isotropic[Index(m, l, lp)];
        full(ShIndex(l, m), ShIndex(lp, m)) = v;
        if (m > 0) full(ShIndex(l, -m), ShIndex(lp, -m)) = v;
      }
    }
  }
  return full;
}

namespace {

// Inverse-variance mean of two estimates; plain mean when either variance is 0 (exact data).
void Pool(double a, double va, double b, double vb, double* mean, double* variance) {
  if (va > 0 && vb > 0 && std::isfinite(va) && std::isfinite(vb)) {
    const double wa = 1.0 / va, wb = 1.0 / vb;
    *mean = (wa * a + wb * b) / (wa + wb);
    *variance = 1.0 / (wa + wb);
  } else {
    *mean = 0.5 * (a + b);
    *variance = 0.25 * ((std::isfinite(va) ? va : 0.0) + (std::isfinite(vb) ? vb : 0.0));
  }
}

}  // namespace

IsotropicData IsotropicCoefficients(const ZonalTensor& data) {
  IsotropicData out;
  out.layout = IsotropicLayout(data.order);
  const int order = data.order;
  for (int ch = 0; ch < 3; ++ch) {
    out.z[ch].resize(out.layout.size());
    out.variance[ch].resize(out.layout.size());
    for (int m = 0; m <= order; ++m) {
      for (int l = m; l <= order; ++l) {
        for (int lp = m; lp <= order; ++lp) {
          const int i = out.layout.Index(m, l, lp);
          const int kp = ShIndex(l, m), jp = ShIndex(lp, m);
          if (m == 0) {
            out.z[ch][i] = data.z[ch](kp, jp);
            out.variance[ch][i] = data.variance[ch](kp, jp);
          } else {
            const int kn = ShIndex(l, -m), jn = ShIndex(lp, -m);
            Pool(data.z[ch](kp, jp), data.variance[ch](kp, jp), data.z[ch](kn, jn),
                 data.variance[ch](kn, jn), &out.z[ch][i], &out.variance[ch][i]);
          }
        }
      }
    }
  }
  return out;
}

IsotropyReport AnalyzeIsotropy(const ZonalTensor& data) {
  IsotropyReport report;
  const int n = data.size();
  double chi2 = 0, energy = 0, noise = 0, total = 0;
  int count = 0;
  // A variance floor keeps noise-free (simulated without noise) data from dividing by zero:
  // 1e-6 of the RMS coefficient squared, below float storage precision's effect on ratios.
  for (int ch = 0; ch < 3; ++ch) {
    const double rms2 = data.z[ch].squaredNorm() / (static_cast<double>(n) * n);
    const double floor = 1e-12 * rms2 + 1e-300;
    total += data.z[ch].squaredNorm();
    for (int k = 0; k < n; ++k) {
      int l, m;
      ShDegreeOrder(k, &l, &m);
      for (int j = 0; j < n; ++j) {
        int lp, mp;
        ShDegreeOrder(j, &lp, &mp);
        const double v = data.z[ch](k, j), var = data.variance[ch](k, j);
        if (mp != m) {
          chi2 += v * v / (var + floor);
          energy += v * v;
          noise += var;
          ++count;
        } else if (m > 0) {
          // Difference of the +m and -m copies, counted once (from the +m side).
          const double d = v - data.z[ch](ShIndex(l, -m), ShIndex(lp, -m));
          const double dvar = var + data.variance[ch](ShIndex(l, -m), ShIndex(lp, -m));
          chi2 += d * d / (dvar + floor);
          // Half the squared difference is the energy the isotropic average discards.
          energy += 0.5 * d * d;
          noise += 0.5 * dvar;
          ++count;
        }
      }
    }
  }
  report.dof = count;
  report.chi2_per_dof = count > 0 ? chi2 / count : 0.0;
  report.anisotropic_energy_fraction = total > 0 ? std::max(0.0, energy - noise) / total : 0.0;
  report.isotropic = report.anisotropic_energy_fraction <= kAnisotropyThreshold;
  return report;
}

}  // namespace zbrdf
