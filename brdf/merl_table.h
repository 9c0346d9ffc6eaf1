// Tabulated isotropic BRDFs in the MERL ".binary" format (Matusik, Pfister, Brand & McMillan
// 2003, "A Data-Driven Reflectance Model"), read and evaluated with the conventions of MERL's
// reference reader (BRDFRead.cpp):
//
// - File: three int32 dimensions (90, 90, 180), then 90*90*180 float64 values per channel,
//   planar R, G, B, little-endian. Stored values times the channel scales 1/1500, 1.15/1500,
//   1.66/1500 give f_r in 1/sr. Negative values mark bins that were not measured.
// - Coordinates: the half vector h = normalize(w_i + w_o) gives theta_h and phi_h; the difference
//   vector is w_i rotated by -phi_h about z and then by -theta_h about y (Rusinkiewicz 1998),
//   giving theta_d and phi_d. phi_d is folded into [0, pi) (phi_d < 0 -> phi_d + pi), which
//   makes the table reciprocal.
// - Bins: theta_h on a square-root axis, bin = floor(sqrt(theta_h / (pi/2)) * 90); theta_d
//   linear, floor(theta_d / (pi/2) * 90); phi_d linear, floor(phi_d / pi * 180); each clamped to
//   its range. Lookup is nearest-bin (the value of the bin holding the point, no interpolation),
//   as in the reference reader.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "brdf/proxy_sampler.h"

namespace zbrdf {

struct MerlTable {
  static constexpr int kThetaHalfBins = 90;
  static constexpr int kThetaDiffBins = 90;
  static constexpr int kPhiDiffBins = 180;
  static constexpr size_t kBinCount =
      static_cast<size_t>(kThetaHalfBins) * kThetaDiffBins * kPhiDiffBins;
  // The per-channel factors from stored values to f_r in 1/sr.
  static constexpr double kRedScale = 1.0 / 1500.0;
  static constexpr double kGreenScale = 1.15 / 1500.0;
  static constexpr double kBlueScale = 1.66 / 1500.0;

  // f_r in 1/sr per bin (kBinCount entries, at Index()); a negative channel is unmeasured.
  std::vector<Rgb> f;

  // MERL's memory order: phi_d fastest, then theta_d, then theta_h.
  static size_t Index(int theta_half_bin, int theta_diff_bin, int phi_diff_bin) {
    return (static_cast<size_t>(theta_half_bin) * kThetaDiffBins + theta_diff_bin) * kPhiDiffBins +
           phi_diff_bin;
  }
};

// The bin of the pair (w_i, w_o), both unit vectors; see the header comment.
struct MerlBin {
  int theta_half = 0, theta_diff = 0, phi_diff = 0;
};
MerlBin MerlBinOf(const Vec3& w_i, const Vec3& w_o);

// Reads a MERL .binary file. Throws InputError naming the file and the problem when it cannot be
// opened, its dimensions are not 90 90 180, it is truncated or has trailing bytes, or a value is
// NaN or infinite.
MerlTable ReadMerlBinary(const std::string& path);

// Writes table in the MERL format (values divided by the channel scales). Throws InputError if
// the table does not have kBinCount entries or the file cannot be written.
void WriteMerlBinary(const std::string& path, const MerlTable& table);

// A MERL table as a BRDF. Unmeasured (negative) entries evaluate to 0 per channel. Sampled with
// the HalfVectorProxySampler fitted to the table at construction.
class MerlBrdf final : public ProxySampledBrdf {
 public:
  // spec: what Spec() returns, e.g. "file:gold.binary".
  MerlBrdf(MerlTable table, std::string spec);
  // Reads the file (see ReadMerlBinary); Spec() is "file:" + path.
  static std::unique_ptr<MerlBrdf> FromFile(const std::string& path);

  Rgb Eval(const Vec3& w_i, const Vec3& w_o) const override;
  // True: folding phi_d by pi maps (w_i, w_o) and (w_o, w_i) to the same bin.
  bool IsReciprocal() const override { return true; }
  // False: measured data carry no such guarantee.
  bool IsEnergyConserving() const override { return false; }
  bool IsIsotropic() const override { return true; }  // MERL tables are isotropic
  std::string Spec() const override { return spec_; }

  const MerlTable& table() const { return table_; }
  // Number of negative (unmeasured) values over all bins and channels, counted at load.
  int64_t invalid_entry_count() const { return invalid_entry_count_; }

 private:
  MerlTable table_;
  std::string spec_;
  int64_t invalid_entry_count_ = 0;
};

}  // namespace zbrdf
