// Isotropic BRDFs tabulated over the half-vector / difference-vector angles of Rusinkiewicz
// (1998): the representation of whole-hemisphere reconstructions (fitting/prior_fit.h) and of
// the measured materials a prior is built from (brdf/brdf_prior.h).
//
// Coordinates of a pair (w_i, w_o), both in the upper hemisphere: h = normalize(w_i + w_o) gives
// theta_h; d = w_i rotated by -phi_h about z, then by -theta_h about y, gives theta_d and phi_d
// (the MERL convention, brdf/merl_table.h). Isotropy removes phi_h; reciprocity (phi_d -> phi_d +
// pi) and bilateral symmetry (phi_d -> -phi_d) fold phi_d into [0, pi/2], so a table holds only
// that quarter and is reciprocal by construction.
//
// The grid has nodes (not cells): theta_h = (pi/2) u^2 for u uniform on [0, 1] (nodes crowd near
// the specular peak: the second node is at 0.09 deg for 32 nodes), theta_d and phi_d uniform on
// [0, pi/2] and [0, pi/2]. Values between nodes are trilinear in (u, theta_d, phi_d).
// Nodes whose directions fall below the horizon (theta_d + theta_h > pi/2 at phi_d = 0) hold the
// value of the nearest node above it at lower theta_d, so that pairs just above the horizon
// interpolate between values of the material, not towards zero.
#pragma once

#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "brdf/proxy_sampler.h"

namespace zbrdf {

struct HalfDiffAngles {
  double theta_h = 0, theta_d = 0, phi_d = 0;  // radians; phi_d folded into [0, pi/2]
};
// The folded coordinates of a pair (unit vectors; any hemisphere).
HalfDiffAngles HalfDiffOf(const Vec3& w_i, const Vec3& w_o);

class HalfDiffGrid {
 public:
  // Throws InputError unless every count is in [2, 512].
  HalfDiffGrid(int theta_h_nodes = 32, int theta_d_nodes = 32, int phi_d_nodes = 16);

  int theta_h_nodes() const { return nh_; }
  int theta_d_nodes() const { return nd_; }
  int phi_d_nodes() const { return np_; }
  int size() const { return nh_ * nd_ * np_; }
  // Node index, phi_d fastest.
  int Index(int ih, int id, int ip) const { return (ih * nd_ + id) * np_ + ip; }
  double ThetaHalf(int ih) const;
  double ThetaDiff(int id) const;
  double PhiDiff(int ip) const;
  // The directions of a node with phi_h = 0 (w_o is w_i reflected about h); either may lie
  // below the horizon.
  void Directions(int index, Vec3* w_i, Vec3* w_o) const;
  // True when both directions of the node are strictly above the horizon.
  bool NodeAboveHorizon(int index) const;

  // The 8 nodes and weights (summing to 1) whose trilinear blend gives a value at the pair.
  struct Stencil {
    std::array<int, 8> index;
    std::array<double, 8> weight;
  };
  Stencil StencilOf(const HalfDiffAngles& angles) const;

  bool operator==(const HalfDiffGrid& o) const {
    return nh_ == o.nh_ && nd_ == o.nd_ && np_ == o.np_;
  }
  std::string ToString() const;  // "32 x 32 x 16"

 private:
  int nh_, nd_, np_;
};

// Samples a BRDF at the grid's nodes: the mean of the two mirror pairs phi_d and pi - phi_d
// (which makes the table bilaterally symmetric even where the source is not), with nodes below
// the horizon filled as described above. Evaluated on both cores.
std::vector<Rgb> TabulateBrdf(const Brdf& brdf, const HalfDiffGrid& grid);

// Fills nodes below the horizon from their nearest valid neighbour at lower theta_d (in place).
template <typename T>
void FillBelowHorizon(const HalfDiffGrid& grid, std::span<T> values);

class TabulatedBrdf final : public ProxySampledBrdf {
 public:
  // values: f_r in 1/sr per node (grid.size()); sigma: its one-standard-deviation uncertainty
  // per node, or empty. Throws InputError for wrong sizes or negative or non-finite values.
  TabulatedBrdf(HalfDiffGrid grid, std::vector<Rgb> values, std::vector<Rgb> sigma,
                std::string spec);

  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override;
  // The uncertainty interpolated like the values (zero when the table has none).
  Rgb EvalSigma(const Vec3& w_i, const Vec3& w_o) const;
  bool IsReciprocal() const override { return true; }
  // False: a table reconstructed from data carries no such guarantee.
  bool IsEnergyConserving() const override { return false; }
  bool IsIsotropic() const override { return true; }  // the half/difference grid is
  std::string Spec() const override { return spec_; }

  const HalfDiffGrid& grid() const { return grid_; }
  const std::vector<Rgb>& values() const { return values_; }
  const std::vector<Rgb>& sigma() const { return sigma_; }

 private:
  HalfDiffGrid grid_;
  std::vector<Rgb> values_, sigma_;
  std::string spec_;
};

}  // namespace zbrdf
