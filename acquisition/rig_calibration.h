// What capture and processing need to know about a rig: where each camera and projector pixel
// looks, how bright the projector is and how it responds, and how the camera turns light into
// numbers.
//
// NominalCalibration() derives all of it from the rig description (ray-traced direction maps,
// the nominal radiometry of rig/rig.h, which the simulator renders with); calibration/
// measures it on a real (or injected-fault) rig and saves it to a calibration folder that
// sessions reference. Processing never needs to know which of the two it has.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "basis/vec3.h"
#include "drivers/camera.h"
#include "rig/direction_maps.h"
#include "rig/rig.h"

namespace zbrdf {

struct RigCalibration {
  std::string source;  // "nominal: <rig name>" or the calibration folder it was read from

  // Camera: per pixel (row-major), the exitant direction at the sample, the solid angle of its
  // footprint, and the electrons per second it collects per unit sample radiance (W m^-2 sr^-1),
  // all losses included (etendue, beam splitter, mirrors, quantum efficiency, throughput,
  // flat field); 0 where the pixel sees nothing of the sample.
  int camera_width = 0, camera_height = 0;
  PixelLayout layout = PixelLayout::kBayerRGGB;
  std::vector<float> camera_direction;  // 3 per pixel, unit
  std::vector<float> camera_solid_angle_sr;
  std::vector<float> camera_response;   // e-/s per W m^-2 sr^-1
  // Multiplies each channel's result (gray-card white balance and absolute scale); 1 nominally.
  std::array<double, 3> channel_scale{1, 1, 1};

  // Sensor noise model (EMVA 1288): DN = black + electrons / gain, var(electrons) = signal +
  // read noise^2; values at or above saturation are unusable.
  double gain_e_per_dn = 1;
  double read_noise_e = 0;
  double black_dn = 0;
  double saturation_dn = 4095;

  // Projector: per pixel the incident direction it lights the sample center from, the solid
  // angle it covers and its relative output (flat field, 1 at the brightest).
  int projector_width = 0, projector_height = 0, projector_bit_depth = 8;
  std::vector<float> projector_direction;  // 3 per pixel, unit; 0 where it lights nothing
  std::vector<float> projector_solid_angle_sr;
  std::vector<float> projector_flat_field;
  // Radiance at the sample (W m^-2 sr^-1) from a full-level pixel with flat field 1, above the
  // black level; the black level as a fraction of it; and the response: normalized output
  // (0..1, black removed) for each level 0 .. 2^bits - 1, non-decreasing.
  double projector_peak_radiance = 1;
  double projector_black_fraction = 0;
  std::vector<double> projector_response;

  bool CameraValid(int pixel) const { return camera_response[pixel] > 0; }
  Vec3 CameraDirection(int pixel) const {
    return {camera_direction[3 * pixel], camera_direction[3 * pixel + 1],
            camera_direction[3 * pixel + 2]};
  }
  bool ProjectorValid(int pixel) const { return projector_solid_angle_sr[pixel] > 0; }
  Vec3 ProjectorDirection(int pixel) const {
    return {projector_direction[3 * pixel], projector_direction[3 * pixel + 1],
            projector_direction[3 * pixel + 2]};
  }
  // The lowest level whose normalized output is >= r (r in [0, 1]); the response's inverse.
  int LevelFor(double normalized_output) const;

  // Theta range (radians) seen by both devices, from their valid pixels.
  void CoveredThetaRange(double* theta_min_rad, double* theta_max_rad) const;
  // Typical angular size (radians) of a projector pixel lighting the sample from near theta:
  // the median sqrt(solid angle) of the pixels within 2 deg of it.
  double ProjectorPixelSizeRad(double theta_rad) const;
};

// From the rig description and its ray-traced maps.
RigCalibration NominalCalibration(const Rig& rig, const RigMaps& maps);

}  // namespace zbrdf
