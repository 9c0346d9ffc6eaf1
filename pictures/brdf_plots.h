// Pictures of a BRDF for people (`zbrdf plot`, `zbrdf report`): polar plots of slices in the
// plane of incidence, and the energy of zonal or SH coefficients per band l. Drawn with OpenCV.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "brdf/brdf.h"

namespace zbrdf {

struct ZonalData;
struct ShBrdfData;

// f_r in the plane of incidence: w_i at elevation theta_i in the x-z plane on the +x side
// (phi_i = 0), w_o over theta_o in [-90, 90] deg in the same plane (negative: the -x side, where
// the mirror direction of w_i lies at theta_o = -theta_i).
struct IncidenceSlice {
  double theta_i_deg = 0;
  std::vector<double> theta_o_deg;
  std::vector<Rgb> f;  // 1/sr
};
std::vector<IncidenceSlice> IncidencePlaneSlices(const Brdf& brdf,
                                                 const std::vector<double>& theta_i_deg,
                                                 int samples = 361);

// One polar panel per slice, side by side: R, G, B curves of f_r (radius linear in f_r and
// scaled to each panel's maximum, or log10 over four decades below it), the incident direction
// and the mirror direction marked. Returns an 8-bit BGR image.
cv::Mat DrawIncidenceSlices(const std::vector<IncidenceSlice>& slices, const std::string& title,
                            bool log_scale);

// Coefficient energy per band: sum of squared coefficients whose w_i function has degree l
// (summed over all w_r functions), per RGB channel, and the same by the degree of the w_r
// function.
struct BandEnergy {
  std::string label;                            // "zonal", "sh"
  std::vector<std::array<double, 3>> by_l_in;   // index l
  std::vector<std::array<double, 3>> by_l_out;  // index l
};
BandEnergy ZonalBandEnergy(const ZonalData& data);
BandEnergy ShBandEnergy(const ShBrdfData& data);
// Bar chart, log10 scale, one group of R, G, B bars per l, for each BandEnergy.
cv::Mat DrawBandEnergy(const std::vector<BandEnergy>& energies, const std::string& title);

nlohmann::json SlicesJson(const std::vector<IncidenceSlice>& slices);
nlohmann::json BandEnergyJson(const BandEnergy& energy);

}  // namespace zbrdf
