// The isotropic zonal projection of BRDFs with specular peaks narrower than a degree.
//
// PairQuadrature (fit_quadrature.h) integrates over (theta_i, theta_r, Delta) with a fixed rule
// of about 2 L + 32 nodes in each polar angle. A peak much narrower than that spacing (chrome,
// clear coats: f_r falls 100x within 1 deg of the mirror direction) is seen only by the pairs
// whose nodes happen to lie within it, so its projection is off by tens of percent (measured
// on the fast thesis zone at order 8: DC coefficient of merl:chrome +51%, merl:aluminium +23%
// against a fine half-vector reference and against the simulated capture, which agree to 0.5%).
//
// This projector splits the integrand with a smooth window of the half-vector angle, 1 up to
// window_inner_deg and 0 beyond window_outer_deg (a smoothstep in between):
//   - g (1 - window) goes to the pair rule, where it is as smooth as the pair rule needs;
//   - g window is integrated around each exitant node w_r over half vectors h (w_i = w_r
//     reflected about h, dw_i = 4 (w_r.h) dw_h; Walter et al. 2007, eq. 14) with Gauss-Legendre
//     in theta_h on pieces [0, 0.25, 1, 3, window_outer] deg and the trapezoid rule in phi_h, the
//     rule of fitting/fit_error.h that resolves peaks.
// With z_(l,m),(l',m) = 2 pi integral dx_r Theta_l'm(x_r) integral_Z dw_i Theta_lm(theta_i)
// cos(m Delta) g (fit_data.h) the two parts add. The windows sum to 1, so a smooth g gets the
// pair rule's result plus the h rule's error on the window's support.
#pragma once

#include <array>
#include <functional>
#include <memory>

#include <Eigen/Dense>

#include "basis/zone.h"
#include "brdf/brdf.h"
#include "fitting/fit_quadrature.h"

namespace zbrdf {

struct PeakProjectionOptions {
  double window_inner_deg = 3.0, window_outer_deg = 8.0;
  int half_theta_per_piece = 8;  // Gauss nodes per theta_h piece of the h rule
  int half_phi = 192;            // trapezoid points in phi_h
  PairQuadratureOptions pair;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

class PeakProjector {
 public:
  // Throws InputError for an order outside [0, 30] or bad options.
  PeakProjector(const Zone& zone, int order, const PeakProjectionOptions& options = {});
  ~PeakProjector();

  const Zone& zone() const { return zone_; }
  int order() const { return order_; }
  const PairQuadrature& pair_quadrature() const { return *pair_; }

  // A linear model of g / cos(theta_i) = sum_k weight_k v[column_k]: fills at most 8 (column,
  // weight) entries for the pair and returns how many (0: the model is 0 there).
  using Stencil = std::function<int(const Vec3& w_i, const Vec3& w_r, int* columns,
                                    double* weights)>;
  // The matrix (IsotropicLayout(order).size() x columns) that maps the model's values v to its
  // isotropic zonal coefficients. Thread-safe stencil required (called from both cores).
  Eigen::MatrixXd Matrix(const Stencil& stencil, int columns) const;

  // Isotropic coefficients of f_r cos(theta_i) per channel.
  std::array<Eigen::VectorXd, 3> ProjectBrdf(const Brdf& brdf) const;

 private:
  struct HalfNode {
    int r;              // exitant node (index into the pair rule's theta nodes)
    Vec3 w_i;           // incident direction (w_r in the x-z plane)
    double weight;      // rule weight x window
    double theta_h;
  };
  double Window(double theta_h) const;

  Zone zone_;
  int order_;
  PeakProjectionOptions options_;
  std::unique_ptr<PairQuadrature> pair_;
  std::vector<HalfNode> half_nodes_;  // sorted by r
  std::vector<int> half_begin_;       // half_nodes_ of exitant node r: [begin[r], begin[r + 1])
};

}  // namespace zbrdf
