// Fast zonal projection of BRDF models: what a fit compares with the measured tensor.
//
// A model's coefficients are z_kj = integral_Z integral_Z Z_k(w_i) Z_j(w_r) g(w_i, w_r) dw_i dw_r
// with g = f_r cos(theta_i) (fit_data.h). We integrate in (theta_i, theta_r, Delta), Delta =
// phi_i - phi_r, the variables in which every model here is smooth except for its half-vector
// lobe:
//   - theta_i, theta_r: the psi rule of the zone (quadrature.h), n nodes each;
//   - Delta in [0, pi] (the half [pi, 2 pi] is the mirror image: models are bilaterally
//     symmetric, and anisotropic terms are handled by their phase, below). For fixed
//     (theta_i, theta_r) the half-vector angle theta_h decreases monotonically from
//     (theta_i + theta_r) / 2 at Delta = 0 to |theta_i - theta_r| / 2 at Delta = pi, and
//       cos(Delta) = ((c_i + c_r)^2 / cos^2(theta_h) - 2 - 2 c_i c_r) / (2 s_i s_r)
//     (from |w_i + w_r|^2 = 2 + 2 w_i.w_r = (c_i + c_r)^2 / cos^2 theta_h), so Delta is split
//     exactly where theta_h crosses a multiple of the half-vector step (1 deg): each piece lies in
//     one cell of a D-BRDF table, where the table is linear, and gets Gauss-Legendre nodes.
//     Pieces are further split until L |dDelta| <= 1 and 2L |d gamma| <= 1 (gamma: the half
//     vector's azimuth relative to w_r), so the azimuthal harmonics are integrated to ~1e-7.
//
// Isotropic models (fit_data.h): the tensor is block diagonal and
//   G_m(l, l') = 2 pi sum_{i, r} wx_i wx_r Theta_lm(x_i) Theta_l'm(x_r) H_m(i, r),
//   H_m(i, r) = integral_0^2pi g cos(m Delta) dDelta = 2 integral_0^pi g cos(m Delta) dDelta.
// D-BRDF tables (dbrdf.h) are linear in their values p_jk: f_spec = c p(h) F / d with
// F = F0 (1 - W) + W, W = (1 - k.h)^5, d = k1.n + k2.n - (k1.n)(k2.n), so the model's tensor is
//   z = c (F0 N + R) p + kd D
// with N and R the projections of each table node's hat function times (1 - W) cos(theta_i) / d
// and W cos(theta_i) / d, and D that of cos(theta_i) / pi. ProjectDBrdfTable() computes N, R, D
// once; a fit then costs matrix-vector products.
//
// Anisotropic tables (phi_samples > 1): the phi hat function of node k has the Fourier series
// sum_n c_n e^{i n (phi_h - phi_k)}, c_n = sinc^2(n pi / K) / K, and phi_h = phi_r + gamma
// (theta_i, theta_r, Delta). Writing A_m(phi) = sum_s alpha_ms e^{i s phi}, the azimuthal integral
// picks n = -(s + s'), and
//   z_(l,m),(l',m') = 2 pi sum_{s, s'} alpha_ms alpha_m's' c_n e^{-i n phi_k}
//                     integral integral Theta_l|m| Theta_l'|m'| T_ss'
//   T_ss'(theta_i, theta_r) = 2 integral_0^pi g cos(s Delta - (s + s') gamma) dDelta
// (gamma is odd under Delta -> -Delta, g even). Only |n| <= 2L contributes.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Dense>

#include "basis/quadrature.h"
#include "basis/vec3.h"
#include "basis/zonal_basis.h"
#include "basis/zone.h"
#include "brdf/brdf.h"
#include "brdf/dbrdf.h"
#include "fitting/fit_data.h"

namespace zbrdf {

struct PairQuadratureOptions {
  int theta_nodes = 0;       // psi-rule nodes per direction; 0: 2 * order + 32
  int theta_h_cells = 90;    // Delta is split where theta_h crosses multiples of 90 deg / this
  int gauss_nodes = 4;       // per Delta piece

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

class PairQuadrature {
 public:
  // Throws InputError for an order outside [0, 30] or bad options.
  PairQuadrature(const Zone& zone, int order, const PairQuadratureOptions& options = {});

  struct Node {
    double delta;    // phi_i - phi_r in [0, pi]
    double weight;   // Delta weight, doubled for the mirror half
    double theta_h;  // half-vector polar angle
    double k_dot_h;  // w_i . h = |w_i + w_r| / 2
    double cos_delta, sin_delta;  // of delta, kept: every projection needs them
  };
  // A run of nodes of one (theta_i, theta_r) pair within one theta_h cell.
  struct Segment {
    int pair;        // ti * theta_nodes() + tr
    int cell;        // theta_h in [cell, cell + 1] * step
    int64_t begin, end;
  };

  const Zone& zone() const { return zone_; }
  int order() const { return order_; }
  int theta_nodes() const { return n_; }
  int theta_h_cells() const { return cells_; }
  double theta_h_step() const { return 0.5 * M_PI / cells_; }
  const CosThetaRule& theta_rule() const { return rule_; }
  int64_t size() const { return static_cast<int64_t>(nodes_.size()); }
  const std::vector<Node>& nodes() const { return nodes_; }
  // Segments in pair order (all segments of pair 0, then pair 1, ...).
  const std::vector<Segment>& segments() const { return segments_; }
  // Segment indices of each cell: cell_segments()[c].
  const std::vector<std::vector<int>>& cell_segments() const { return cell_segments_; }
  // Segments of pair p: [PairSegmentBegin(p), PairSegmentBegin(p + 1)).
  int PairSegmentBegin(int pair) const { return pair_segments_[pair]; }
  // Theta parts of the ZB at theta node t: ThetaPart(t)[LegendreIndex(l, m)] (zonal_basis.h).
  const double* ThetaPart(int t) const { return &theta_part_[static_cast<size_t>(t) * part_size_]; }

  // The directions of a node of pair p: w_r = (sin theta_r, 0, cos theta_r), w_i at azimuth
  // delta.
  void Directions(int pair, const Node& node, Vec3* w_i, Vec3* w_r) const;

  // Isotropic coefficients (IsotropicLayout) of an isotropic g given at every node (size()).
  Eigen::VectorXd ProjectIsotropic(std::span<const double> g) const;
  // The same for several functions at once (the channels of a BRDF): one pass over the nodes,
  // each function's coefficients equal to what ProjectIsotropic gives it.
  std::vector<Eigen::VectorXd> ProjectIsotropicAll(std::span<const std::span<const double>> g) const;
  // g = f_r cos(theta_i) of a BRDF (one channel per output), evaluated at the nodes in parallel.
  std::array<Eigen::VectorXd, 3> ProjectIsotropicBrdf(const Brdf& brdf) const;

 private:
  Zone zone_;
  int order_, n_, cells_;
  CosThetaRule rule_;
  std::vector<Node> nodes_;
  std::vector<Segment> segments_;
  std::vector<int> pair_segments_;
  std::vector<std::vector<int>> cell_segments_;
  int part_size_ = 0;
  std::vector<double> theta_part_;
};

// The D-BRDF's linear pieces for a table of theta_samples x phi_samples nodes (dbrdf.h layout,
// column j * phi_samples + k): z = c (F0 normal + grazing) p + kd diffuse.
struct DBrdfProjection {
  bool isotropic = true;  // isotropic layout (phi_samples == 1), else full ShCount^2 (row-major
                          // k * n + j) coefficients
  Eigen::MatrixXd normal, grazing;  // coefficients x table nodes
  Eigen::VectorXd diffuse;          // coefficients of cos(theta_i) / pi
};
// (theta_samples - 1) must divide the quadrature's theta_h_cells. Throws InputError otherwise.
DBrdfProjection ProjectDBrdfTable(const PairQuadrature& quadrature, int theta_samples,
                                  int phi_samples);

// The zonal tensor (all channels, full ShCount x ShCount) of a D-BRDF whose table matches the
// projection's size.
std::array<Eigen::MatrixXd, 3> DBrdfTensor(const DBrdfProjection& projection,
                                           const DBrdfParams& params, int order);

}  // namespace zbrdf
