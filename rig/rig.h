// The rig description: optics, devices, sensor and timing of a zonal-basis BRDF rig.
//
// Read from a YAML (or JSON) file documented in docs/rig-file.md; every field is validated
// where it enters and all problems are reported at once, naming the field and the file
// ("rig file thesis.yaml: camera.pixel_pitch_um must be > 0 (got -3.45)"). The simulator traces
// rays through exactly this description; calibration estimates its misalignment block.
//
// Frames and units: the sample frame has the sample center at the origin and its normal along
// +z; lengths in mm, angles in degrees in the file (radians in code), times in ms or us as the
// field names say. The camera looks down (-z) at the convex parabola; the projector shares the
// camera's optical axis through the beam splitter and is described at its virtual position
// (its image in the splitter), so a perfectly aligned projector has the camera's pose.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "basis/vec3.h"
#include "drivers/camera.h"

namespace zbrdf {

struct ParabolaParams {
  double vertex_height_mm = 135;  // vertex above the sample plane
  double focal_length_mm = 4.5;   // z = vertex - r^2 / (4 f): curvature at the vertex 1/(2f)
  double rim_radius_mm = 18.5;    // radius of the mirror's edge
};

struct DomeParams {
  // The dome is a surface of revolution designed by the Euler integration of docs/design.md
  // section 1 (rig/dome_design.h). A built dome may stop short of the sample plane:
  double lower_edge_height_mm = 0;  // no mirror below this height (0: down to the sample plane)
  int design_steps = 20000;         // Euler steps from the rim ray to the axis
};

// A thin-lens device: the camera, or the projector at its virtual position.
struct ThinLensParams {
  int width = 0, height = 0;        // pixels
  double pixel_pitch_um = 0;
  double focal_length_mm = 0;
  double f_number = 0;
  double focus_distance_mm = 0;     // object-side distance of the plane in focus
  Vec3 position_mm;                 // center of the lens (center of projection)
  double tilt_deg[2] = {0, 0};      // rotations about the world x then y axes
};

// Projector output: radiance = peak * (black + (1 - black) * response(level / max_level)),
// times the flat field 1 - falloff * (r / r_corner)^2 (r: distance from the image center).
struct ProjectorParams {
  ThinLensParams lens;
  int bit_depth = 8;
  double gamma = 1.0;                     // response(u) = u^gamma, unless a table is given
  std::vector<double> response_table;     // response at evenly spaced inputs 0..1 (>= 2 entries)
  double black_level = 0;                 // fraction of peak radiance emitted at level 0
  double flat_field_falloff = 0;          // relative loss at the image corners
  double peak_radiance_w_m2_sr = 1;       // radiance of a full-white pixel leaving the lens

  // Radiance fraction (0..1 of peak) for a normalized input level u in [0, 1].
  double Response(double u) const;
  // Flat-field factor for the pixel (px, py) (pixel centers at half-integers).
  double FlatField(double px, double py) const;
};

// Photons per joule of light at 550 nm, lambda / (h c): with quantum_efficiency, the electrons a
// sensor collects per joule. The radiometry assumes this one wavelength for every channel.
inline constexpr double kPhotonsPerJoule550nm = 2.7673e18;

struct SensorParams {
  double gain_e_per_dn = 2.0;     // electrons per digital number
  double read_noise_e = 6.0;      // RMS, electrons
  double dark_level_dn = 64;      // black level added to every sample
  int bit_depth = 12;
  double saturation_dn = 4095;    // largest value the sensor delivers
  double full_well_e = 20000;     // electrons at which a pixel saturates
  double quantum_efficiency = 0.5;  // electrons per photon (at 550 nm)
  PixelLayout layout = PixelLayout::kBayerRGGB;
};

struct TimingParams {
  double frame_rate_hz = 15;        // sensor's maximum frame rate
  double readout_ms = 30;           // after each exposure
  double projector_settle_ms = 50;  // after a new pattern, before exposing
};

struct Misalignment {
  Vec3 camera_offset_mm, projector_offset_mm, parabola_offset_mm;
  double camera_tilt_deg[2] = {0, 0};
  double projector_tilt_deg[2] = {0, 0};
  double parabola_tilt_deg[2] = {0, 0};
};

// How finely the simulator integrates (not part of the hardware).
struct SimulationParams {
  int samples_per_pixel = 512;       // incident directions per camera pixel
  int aperture_samples = 16;         // pixel-area x thin-lens rays per pixel (maps, frames)
  double direction_grid_deg = 0.1;   // resolution of the direction -> projector pixel map
};

struct Rig {
  std::string name;
  std::string source_path;  // file it was read from ("" if built in code)
  ParabolaParams parabola;
  DomeParams dome;
  ThinLensParams camera;
  ProjectorParams projector;
  double beam_splitter_transmission = 0.5;  // camera path
  double beam_splitter_reflection = 0.5;    // projector path
  double mirror_reflectance = 0.9;          // each of parabola and dome
  double sample_diameter_mm = 40;
  SensorParams sensor;
  TimingParams timing;
  Misalignment misalignment;
  SimulationParams simulation;
};

// Reads and validates a rig file. A name without '/' or '.' that is not a file in the current
// folder is a bundled rig: "thesis" reads rig/rigs/thesis.yaml under DataRoot()
// (basis/data_path.h), so installed and source-tree zbrdf alike take `--rig thesis`. Throws
// InputError listing every problem found, or naming the bundled rigs if there is no such file.
Rig LoadRig(const std::string& path_or_name);
// Parses rig YAML text; `name_for_errors` stands for the file in messages.
Rig ParseRig(const std::string& yaml_text, const std::string& name_for_errors);
// The canonical YAML of a rig (all fields, fixed order), as stored in session.json and used
// for the map cache key. ParseRig(WriteRigYaml(r)) == r.
std::string WriteRigYaml(const Rig& rig);
// The rig as built: `rig` with the fields of an overlay (a "faults" file) replaced, e.g.
//   misalignment: {projector_offset_mm: [1, 0, 0], camera_tilt_deg: [0.5, 0]}
//   projector: {gamma: 2.2, flat_field_falloff: 0.3}
// Maps merge key by key; any other value replaces the rig's. The result is validated like a
// rig file; errors name `name_for_errors`. Used to simulate a rig that differs from its design.
Rig ApplyRigOverlayText(const Rig& rig, const std::string& yaml_text,
                        const std::string& name_for_errors);
// The same from a file. Throws InputError if it cannot be read.
Rig ApplyRigOverlay(const Rig& rig, const std::string& overlay_path);
// 64-bit FNV-1a hash of the canonical YAML: identifies the rig's geometry for caches.
uint64_t RigHash(const Rig& rig);
// RigHash as 16 lowercase hex digits (batch manifests record it).
std::string RigHashHex(const Rig& rig);

enum class Preset { kFast, kFull };
// "fast" or "full"; throws InputError otherwise.
Preset ParsePreset(const std::string& name);
// fast: camera and projector at 1/4 of their resolution (pixel pitch x4, same optics and field
// of view), the camera's pixels binned 4 x 4 (full well and gain x16, read noise x4), a
// coarser direction grid and twice the samples per pixel, for tests and quick looks; full: the
// rig as described.
Rig ApplyPreset(const Rig& rig, Preset preset);

}  // namespace zbrdf
