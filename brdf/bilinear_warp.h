// The piecewise-bilinear 2-D distribution of the RGL material format (Dupuy & Jakob 2018, "An
// Adaptive Parameterization for Efficient Material Acquisition and Rendering", section 5): a
// function on [0, 1]^2 given by its values on a regular nx x ny grid of nodes (x fastest),
// interpolated bilinearly, optionally depending on extra parameters (e.g. the incident angles)
// through which the grids are interpolated linearly.
//
// As a density (normalized) it is sampled by inversion: first the marginal over y (the rows),
// which is piecewise linear between row nodes, then x given y, piecewise linear between column
// nodes; each step solves the quadratic of a linear density's integral. Invert() is the exact
// inverse map of Sample(). As a plain interpolant (not normalized) Eval() is the bilinear
// interpolation of the values. These are the semantics that Mitsuba 3's and pbrt-v4's readers
// give to the fields of a .bsdf file (ndf and sigma: interpolants; vndf and luminance:
// densities; rgb or spectra: interpolants with an extra parameter, the channel or wavelength).
//
// Parameters: param_values[d] holds the ascending node values of parameter d; the slices are
// laid out with the last parameter fastest (tensor shape [n_0, n_1, ..., ny, nx]). A query
// between nodes blends the neighbouring slices linearly (clamped at the ends); a parameter with
// one node is constant.
#pragma once

#include <array>
#include <span>
#include <vector>

namespace zbrdf {

class BilinearWarp2D {
 public:
  BilinearWarp2D() = default;
  // values: product(param sizes) * ny * nx entries, >= 0 and finite when normalize is set.
  // normalize: treat every slice as a density (scaled to integrate to 1 over [0, 1]^2) and build
  // the CDFs for Sample() and Invert(). A slice that is zero everywhere is taken as uniform.
  // Throws InputError if nx or ny < 2, a parameter has no node or non-ascending nodes, or the
  // size of values does not match.
  BilinearWarp2D(int nx, int ny, std::span<const float> values,
                 std::vector<std::vector<float>> param_values, bool normalize);

  int nx() const { return nx_; }
  int ny() const { return ny_; }

  // The interpolated value (a density if normalized) at pos in [0, 1]^2.
  double Eval(std::array<double, 2> pos, std::span<const double> params = {}) const;
  // Maps u in [0, 1]^2 to a point distributed with the (interpolated) density; returns the point
  // and the density there. Only for normalized warps.
  std::array<double, 3> Sample(std::array<double, 2> u, std::span<const double> params = {}) const;
  // The inverse of Sample: the u that Sample maps to pos, and the density at pos.
  std::array<double, 3> Invert(std::array<double, 2> pos,
                               std::span<const double> params = {}) const;

 private:
  struct Blend {
    // Up to 2^dims slice offsets (in slices) and their weights.
    std::vector<int> slices;
    std::vector<double> weights;
  };
  Blend BlendFor(std::span<const double> params) const;
  // Value at (x, y) node of the blended slice in one of the arrays.
  double Data(const Blend& b, int x, int y) const;
  double Conditional(const Blend& b, int x, int y) const;
  double Marginal(const Blend& b, int y) const;

  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<float>> param_values_;
  std::vector<int> param_strides_;  // in slices; 0 for a one-node parameter
  bool normalized_ = false;
  std::vector<double> data_;         // per slice ny * nx (normalized: integrates to 1 / cells)
  std::vector<double> conditional_;  // per slice ny * nx: running integral along each row
  std::vector<double> marginal_;     // per slice ny: running integral over rows
};

}  // namespace zbrdf
