// Linear RGB <-> reflectance spectra, for renderers that need spectra (pbrt-v4's measured
// material reads only spectral .bsdf files).
//
// Observer: the CIE 1931 2-degree color matching functions in the multi-lobe analytic fit of
// Wyman, Sloan & Shirley 2013 ("Simple Analytic Approximations to the CIE XYZ Color Matching
// Functions", JCGT 2(2), eq. 2 and table 1), then the XYZ -> linear sRGB matrix (IEC 61966-2-1).
// RGB of a reflectance spectrum S is white-balanced for an equal-energy light:
//   RGB_j(S) = integral S(lambda) rbar_j(lambda) dlambda / integral rbar_j(lambda) dlambda,
// so the flat spectrum S = v has RGB (v, v, v) exactly.
//
// Upsampling uses three smooth basis spectra that sum to 1 at every wavelength (a blue, a green
// and a red band with logistic edges at 495 and 585 nm): S = c_b B_b + c_g B_g + c_r B_r with
// c >= 0 the non-negative least-squares solution of RGB(S) = rgb. A gray stays exactly flat;
// colors inside the basis' gamut come back exactly; a more saturated color is mapped to the
// nearest color of the gamut, and the mapping error is reported, never hidden.
#pragma once

#include <array>
#include <vector>

#include "basis/vec3.h"

namespace zbrdf {

// CIE 1931 x-bar, y-bar, z-bar at a wavelength in nm (the analytic fit above).
Vec3 CieXyz1931(double lambda_nm);
// Linear sRGB (D65 primaries) from XYZ.
Rgb LinearSrgbFromXyz(const Vec3& xyz);

class SpectralBasis {
 public:
  // Wavelength nodes in nm, ascending (e.g. 380, 390, ..., 780). The spectra are piecewise
  // linear between nodes and constant beyond the ends, as pbrt-v4 interpolates them.
  explicit SpectralBasis(std::vector<double> wavelengths_nm);
  // The default nodes: 380 to 780 nm every 10 nm.
  static SpectralBasis Default();

  const std::vector<double>& wavelengths_nm() const { return wavelengths_; }

  // Spectrum values at the nodes for rgb; *gamut_error (if given) is the largest per-channel
  // absolute difference between rgb and the RGB of the returned spectrum.
  std::vector<double> Upsample(const Rgb& rgb, double* gamut_error = nullptr) const;
  // RGB of a spectrum given at the nodes.
  Rgb Project(const std::vector<double>& values) const;
  // RGB of node k's tent function: Project is sum_k values[k] * NodeWeight(k).
  const Rgb& NodeWeight(int k) const { return node_weights_[k]; }

 private:
  std::vector<double> wavelengths_;
  std::vector<Rgb> node_weights_;                      // RGB of each node's tent spectrum
  std::array<std::vector<double>, 3> basis_at_nodes_;  // B_b, B_g, B_r at the nodes
  std::array<Rgb, 3> basis_rgb_;                       // RGB of each basis spectrum
};

}  // namespace zbrdf
