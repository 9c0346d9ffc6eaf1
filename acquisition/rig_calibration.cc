#include "acquisition/rig_calibration.h"

#include <algorithm>
#include <cmath>

#include "basis/error.h"
#include "rig/optics.h"
#include "rig/rig.h"

namespace zbrdf {

int RigCalibration::LevelFor(double normalized_output) const {
  const auto it = std::lower_bound(projector_response.begin(), projector_response.end(),
                                   normalized_output - 1e-12);
  if (it == projector_response.end()) return static_cast<int>(projector_response.size()) - 1;
  return static_cast<int>(it - projector_response.begin());
}

void RigCalibration::CoveredThetaRange(double* theta_min_rad, double* theta_max_rad) const {
  auto range = [](const std::vector<float>& dir, auto valid, int n, double* lo, double* hi) {
    *lo = M_PI;
    *hi = 0;
    for (int i = 0; i < n; ++i) {
      if (!valid(i)) continue;
      const double theta = std::acos(std::clamp<double>(dir[3 * i + 2], -1, 1));
      *lo = std::min(*lo, theta);
      *hi = std::max(*hi, theta);
    }
  };
  double c_lo, c_hi, p_lo, p_hi;
  range(camera_direction, [&](int i) { return CameraValid(i); }, camera_width * camera_height,
        &c_lo, &c_hi);
  range(projector_direction, [&](int i) { return ProjectorValid(i); },
        projector_width * projector_height, &p_lo, &p_hi);
  *theta_min_rad = std::max(c_lo, p_lo);
  *theta_max_rad = std::min(c_hi, p_hi);
}

double RigCalibration::ProjectorPixelSizeRad(double theta_rad) const {
  std::vector<double> sizes;
  for (int i = 0; i < projector_width * projector_height; ++i) {
    if (!ProjectorValid(i)) continue;
    const double theta = std::acos(std::clamp<double>(projector_direction[3 * i + 2], -1, 1));
    if (std::abs(theta - theta_rad) <= 2 * M_PI / 180) sizes.push_back(std::sqrt(projector_solid_angle_sr[i]));
  }
  if (sizes.empty()) return 0;
  std::nth_element(sizes.begin(), sizes.begin() + sizes.size() / 2, sizes.end());
  return sizes[sizes.size() / 2];
}

RigCalibration NominalCalibration(const Rig& rig, const RigMaps& maps) {
  RigCalibration c;
  c.source = "nominal: " + rig.name;
  const OpticalSystem optics(rig);
  c.camera_width = rig.camera.width;
  c.camera_height = rig.camera.height;
  c.layout = rig.sensor.layout;
  c.camera_direction = maps.camera.direction;
  c.camera_solid_angle_sr = maps.camera.solid_angle_sr;
  const int pixels = c.camera_width * c.camera_height;
  c.camera_response.assign(pixels, 0.0f);
  const double transmission =
      rig.beam_splitter_transmission * rig.mirror_reflectance * rig.mirror_reflectance;
  for (int y = 0; y < c.camera_height; ++y) {
    for (int x = 0; x < c.camera_width; ++x) {
      const int i = y * c.camera_width + x;
      if (!maps.camera.Valid(i)) continue;
      c.camera_response[i] = static_cast<float>(
          optics.camera().PixelEtendue(x + 0.5, y + 0.5) * transmission *
          rig.sensor.quantum_efficiency * kPhotonsPerJoule550nm * maps.camera.throughput[i]);
    }
  }
  c.gain_e_per_dn = rig.sensor.gain_e_per_dn;
  c.read_noise_e = rig.sensor.read_noise_e;
  c.black_dn = rig.sensor.dark_level_dn;
  c.saturation_dn = std::min(rig.sensor.saturation_dn, std::ldexp(1.0, rig.sensor.bit_depth) - 1);

  const ProjectorParams& p = rig.projector;
  c.projector_width = p.lens.width;
  c.projector_height = p.lens.height;
  c.projector_bit_depth = p.bit_depth;
  c.projector_direction = maps.projector.direction;
  c.projector_solid_angle_sr = maps.projector.solid_angle_sr;
  c.projector_flat_field.resize(static_cast<size_t>(p.lens.width) * p.lens.height);
  for (int y = 0; y < p.lens.height; ++y) {
    for (int x = 0; x < p.lens.width; ++x) {
      const int i = y * p.lens.width + x;
      // A pixel lights the sample only if its rays reach it; its share is the map's
      // throughput (partly vignetted pixels at the mirrors' rims).
      c.projector_flat_field[i] = static_cast<float>(p.FlatField(x + 0.5, y + 0.5));
      if (!maps.projector.Valid(i)) c.projector_solid_angle_sr[i] = 0;
    }
  }
  const double path = rig.beam_splitter_reflection * rig.mirror_reflectance * rig.mirror_reflectance;
  c.projector_peak_radiance = p.peak_radiance_w_m2_sr * path * (1 - p.black_level);
  c.projector_black_fraction = p.black_level / std::max(1e-12, 1 - p.black_level);
  const int levels = 1 << p.bit_depth;
  c.projector_response.resize(levels);
  for (int level = 0; level < levels; ++level) {
    c.projector_response[level] = p.Response(static_cast<double>(level) / (levels - 1));
  }
  return c;
}

}  // namespace zbrdf
