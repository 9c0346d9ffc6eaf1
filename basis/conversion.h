// Conversion of zonal-basis (ZB) coefficients to a target basis by the moment form.
//
// The ZB coefficients of a function f are its moments z_j = integral_Z f Z_j dw. For f in the
// span of the target functions, f = sum_i y_i T_i, they are z = M y with M = B^T,
// B_ij = integral_Z T_i Z_j dw (gram.h). We recover y = M^+ z by a truncated SVD of M,
// block by block in |m| (docs/design.md section 3, item 3). Never the normal equations, and never
// the thesis's dual-basis formula y = G^-1 B z, which is biased (item 2).
//
// Apply() uses the factored form y = V (Sigma^-1 (U^T z)) block by block: rounding errors then
// stay along the singular vectors they belong to, and the result reproduces the moments
// (M y = z) to rounding error. Multiplying by the explicit matrix C instead mixes the 1/sigma
// scale of the smallest singular values into every component and loses up to 4 digits in the
// zone at order 10 on [9, 57] deg.
//
// tau: singular values below tau * (largest singular value) are dropped. A small tau recovers
// band-limited data to rounding error inside the zone; noisy data need a larger tau, traded
// against bias. The noise gain ||C||_2 = 1 / (smallest kept singular value) says how much
// white noise in z is amplified in y.
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "basis/target_basis.h"
#include "basis/zonal_basis.h"

namespace zbrdf {

inline constexpr double kDefaultTau = 1e-13;

struct ConversionDiagnostics {
  double tau = 0;
  double noise_gain = 0;          // ||C||_2
  int truncated_components = 0;   // singular values dropped (each +-m block counted)
  int underdetermined_components = 0;  // target functions beyond the ZB's reach (no data)
  double largest_singular_value = 0;
  double smallest_kept_singular_value = 0;
  std::vector<double> singular_values;  // all, descending, with multiplicity
};

class ZonalToTarget {
 public:
  // Throws InputError if tau is not in [0, 1).
  ZonalToTarget(const ZonalBasis& zb, const TargetBasis& target, double tau = kDefaultTau);

  const ZonalBasis& zonal_basis() const { return zb_; }
  const TargetBasis& target() const { return target_; }
  // C: target.size() x zb.size(); y = C z. For inspection and export; Apply() is more accurate.
  const Eigen::MatrixXd& matrix() const { return conversion_; }
  // M = B^T: zb.size() x target.size(); the ZB moments of sum_i y_i T_i are M y.
  const Eigen::MatrixXd& moment_matrix() const { return moments_; }
  const ConversionDiagnostics& diagnostics() const { return diagnostics_; }

  // y = C z for a vector z of ZB coefficients; ApplyToColumns does so for each column.
  Eigen::VectorXd Apply(const Eigen::VectorXd& z) const;
  Eigen::MatrixXd ApplyToColumns(const Eigen::MatrixXd& z) const;

 private:
  // One |m| block's truncated SVD of M_m = U diag(sigma) V^T, with 1/sigma (0 if dropped).
  struct Block {
    int abs_m = 0;
    std::vector<int> target_degrees;
    Eigen::MatrixXd u, v;
    Eigen::VectorXd inverse_sigma;
  };
  ZonalBasis zb_;
  TargetBasis target_;
  std::vector<Block> blocks_;
  Eigen::MatrixXd conversion_, moments_;
  ConversionDiagnostics diagnostics_;
};

// Tensor-product conversion of BRDF coefficients z_kj (k: ZB in w_i, rows; j: ZB in w_r,
// columns) to target coefficients Y = C_i Z C_r^T.
Eigen::MatrixXd ConvertTensor(const ZonalToTarget& incident, const ZonalToTarget& exitant,
                              const Eigen::MatrixXd& z);

}  // namespace zbrdf
