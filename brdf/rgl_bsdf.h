// RGL .bsdf material files (Dupuy & Jakob 2018, "An Adaptive Parameterization for Efficient
// Material Acquisition and Rendering", ACM TOG 37(6)), as Mitsuba 3's `measured` plugin and
// pbrt-v4's `measured` material read them. docs/formats.md specifies the fields.
//
// The model: for a parameter direction w_p (the file's theta_i, phi_i) and the other direction
// w_q reflected about a microfacet normal m,
//   f_r(w_q, w_p) cos(theta_q) = R(s) * ndf(m) / (4 sigma(w_p))
// where ndf is a microfacet distribution (integral ndf(m) cos(theta_m) dm = 1), sigma(w) =
// integral max(0, w.m) ndf(m) dm its projected area, and R is tabulated over the unit square s
// of the warp that maps s to the visible normals of w_p (the "vndf" field). All tables are on
// grids in u = (sqrt(theta / (pi/2)), (phi + pi) / (2 pi)); isotropic files use the azimuth of
// m relative to w_p's. We write w_p = w_o (toward the viewer), as Mitsuba's plugin takes it
// (its si.wi), so that it evaluates f_r(w_i = light, w_o = camera) of non-reciprocal inputs
// exactly as we do.
//
// Export picks ndf as: GGX's D for a GGX model, p(h) for a D-BRDF, and otherwise the
// distribution that explains the retro-reflection f_r(w, w) (Dupuy & Jakob section 4: for a
// microfacet BRDF f(w, w) = ndf(w) F / (4 sigma(w)^2), solved by power iteration). R is then
// f_r cos(theta_i) 4 sigma(w_o) / ndf(m) at the nodes, computed with the same interpolated
// tables the readers use, so that the file reproduces f_r exactly at the nodes.
#pragma once

#include <memory>
#include <string>

#include "brdf/bilinear_warp.h"
#include "brdf/brdf.h"
#include "brdf/tensor_file.h"
#include "brdf/value_check.h"

namespace zbrdf {

struct RglExportOptions {
  int theta_nodes = 16;       // elevations of w_o, evenly spaced over [0, 90] deg
  int phi_nodes = 25;         // azimuths of w_o for anisotropic inputs, over [-180, 180] deg
  int ndf_resolution = 128;   // ndf and sigma grids: theta nodes (and phi nodes if anisotropic)
  int vndf_resolution = 128;  // sample-space warp grid per w_o, both axes (isotropic inputs)
  int vndf_resolution_anisotropic = 64;  // the same for anisotropic inputs (25x more slices)
  // luminance and rgb/spectra grids per w_o, both axes. 48 rather than 32 since half of the nodes
  // follow the change of f_r (the highlight): with 32 the body of blue-acrylic lost accuracy
  // (uniform-pair median 0.32% -> 0.49%), with 48 it is back (0.30%) (docs/formats.md).
  int sample_resolution = 48;
  bool clamp_invalid = false;  // write NaN and negative f_r as 0 (counted) instead of failing
  std::string description;     // the file's description field

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct RglExportReport {
  bool isotropic = true;
  std::string ndf_source;  // "ggx D", "dbrdf p(h)" or "retro-reflection (power iteration)"
  ValueCheck values;
  // Spectral variant: nodes whose color lies outside the upsampling basis' gamut, and the
  // largest absolute RGB change that mapping made, relative to the node's largest channel.
  int64_t out_of_gamut = 0;
  double max_gamut_error = 0;
};

// True when f_r(R w_i, R w_o) = f_r(w_i, w_o) for rotations R about the normal, probed on fixed
// pseudo-random pairs and angles (relative agreement 1e-6).
bool LooksIsotropic(const Brdf& brdf);

// The fields of the RGB variant ("rgb": Mitsuba 3's RGB variants) and/or the spectral variant
// ("spectra" and "wavelengths": pbrt-v4, Mitsuba 3's spectral variants) from one tabulation;
// either output may be null. Throws InputError for a delta material (no density to tabulate),
// bad options, or invalid values when not clamping.
void MakeRglTensors(const Brdf& brdf, const RglExportOptions& options, RglExportReport* report,
                    TensorFile* rgb, TensorFile* spectral);
RglExportReport WriteRglFile(const std::string& path, const Brdf& brdf,
                             const RglExportOptions& options, bool spectral = false);

// A .bsdf file (RGB or spectral) as a BRDF, evaluated and sampled as Mitsuba 3 does (luminance
// warp, then the visible-normal warp). Spectral files are reduced to RGB with the observer of
// brdf/spectral.h.
class RglBrdf final : public Brdf {
 public:
  // Throws InputError naming the file and the field that is missing or malformed.
  static std::unique_ptr<RglBrdf> FromFile(const std::string& path);

  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override;
  BrdfSample Sample(const Vec3& w_o, double u_lobe, double u0, double u1) const override;
  double Pdf(const Vec3& w_o, const Vec3& w_i) const override;
  bool IsReciprocal() const override { return false; }
  bool IsEnergyConserving() const override { return false; }
  bool IsIsotropic() const override { return isotropic_; }
  // "file:PATH" (readable by zbrdf's INPUT resolution, not by MakeBrdf).
  std::string Spec() const override { return "file:" + path_; }

  bool isotropic() const { return isotropic_; }
  const std::string& description() const { return description_; }

 private:
  RglBrdf() = default;

  std::string path_, description_;
  bool isotropic_ = true;
  bool jacobian_ = true;
  BilinearWarp2D ndf_, sigma_, vndf_, luminance_, rgb_;
};

}  // namespace zbrdf
