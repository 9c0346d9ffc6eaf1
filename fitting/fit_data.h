// The measured zonal data a fit works from, and its reduction for isotropic materials.
//
// ZonalTensor is the fitting layer's view of a session's coefficients (acquisition's ZonalData
// lies a layer above): per RGB channel the tensor z_kj = integral_Z integral_Z Z_k(w_i) Z_j(w_r)
// f_r(w_i, w_r) cos(theta_i) dw_i dw_r (rows k: ZB in w_i, columns j: ZB in w_r, ShIndex order)
// and the variance of each coefficient (independent noise assumed).
//
// Isotropy. For a BRDF that depends on the azimuths only through |phi_i - phi_r| (isotropic and
// bilaterally symmetric, as every MERL material), write Z_lm = Theta_lm(theta) A_m(phi) with A_m
// = 1, sqrt(2) cos(m phi) or sqrt(2) sin(|m| phi). The double azimuthal integral of
// f A_m(phi_i) A_m'(phi_r) vanishes unless m' = m, and for m' = m it is
//   2 pi integral_0^2pi f(theta_i, theta_r, Delta) cos(|m| Delta) dDelta,   Delta = phi_i - phi_r,
// the same for +m and -m. So the tensor of such a BRDF is block diagonal: one block
// G_m(l, l') = z_(l,m),(l',m) per |m| = 0..L (degrees l, l' >= |m|), shared by +m and -m; every
// other entry is 0. IsotropicCoefficients() pools +m and -m by inverse-variance weighting;
// AnalyzeIsotropy() tests whether the other entries are noise.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "basis/zone.h"

namespace zbrdf {

struct ZonalTensor {
  double theta_min_rad = 0, theta_max_rad = 0;
  int order = 0;
  std::array<Eigen::MatrixXd, 3> z, variance;  // ShCount(order) x ShCount(order) each

  Zone zone() const { return Zone(theta_min_rad, theta_max_rad); }
  int size() const;  // ShCount(order)
  // Empty if well formed, else what is wrong (sizes, negative or non-finite variances,
  // non-finite coefficients), naming the channel and entry.
  std::string Problems() const;
};

// Layout of the isotropic (block-diagonal) coefficients: blocks |m| = 0..order, block m of size
// (order + 1 - m)^2, row-major (l - m) * (order + 1 - m) + (l' - m). l: degree in w_i, l': in w_r.
class IsotropicLayout {
 public:
  explicit IsotropicLayout(int order);
  int order() const { return order_; }
  int size() const { return size_; }
  int BlockOffset(int abs_m) const { return offset_[abs_m]; }
  int BlockWidth(int abs_m) const { return order_ + 1 - abs_m; }
  int Index(int abs_m, int l, int l_prime) const {
    return offset_[abs_m] + (l - abs_m) * BlockWidth(abs_m) + (l_prime - abs_m);
  }
  // Expands isotropic coefficients to the full ShCount x ShCount tensor (zeros elsewhere).
  Eigen::MatrixXd Expand(const Eigen::VectorXd& isotropic) const;

 private:
  int order_, size_;
  std::vector<int> offset_;
};

// The measured isotropic coefficients per channel with their variances: entries shared by +m and
// -m are the inverse-variance weighted mean of the two (variance: the harmonic combination).
// Entries whose variances are both zero are averaged plainly with variance 0.
struct IsotropicData {
  IsotropicLayout layout{0};
  std::array<Eigen::VectorXd, 3> z, variance;
};
IsotropicData IsotropicCoefficients(const ZonalTensor& data);

// How far the data are from isotropy. off_block_* are the entries an isotropic BRDF leaves zero
// and the differences between the +m and -m copies of an isotropic entry.
struct IsotropyReport {
  double chi2_per_dof = 0;      // sum (value^2 / variance) / count over those entries
  int dof = 0;
  // Their energy beyond the expected noise, relative to the tensor's energy:
  // max(0, sum value^2 - sum variance) / sum z^2, all channels.
  double anisotropic_energy_fraction = 0;
  bool isotropic = true;        // the decision (see kAnisotropyThreshold)
};
// Data count as anisotropic when the off-block energy exceeds this fraction of the tensor's energy
// beyond noise. Simulated isotropic materials on the thesis rig show 0.1-0.5% (the rig's
// discretization breaks the rotational symmetry slightly); anisotropic ones (alpha_x / alpha_y
// = 2) several percent.
inline constexpr double kAnisotropyThreshold = 0.02;
IsotropyReport AnalyzeIsotropy(const ZonalTensor& data);

}  // namespace zbrdf
