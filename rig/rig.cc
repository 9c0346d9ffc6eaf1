#include "rig/rig.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <set>
#include <sstream>

#include "basis/data_path.h"
#include "basis/error.h"
#include "basis/hash.h"
#include "basis/strings.h"

namespace zbrdf {

double ProjectorParams::Response(double u) const {
  u = std::clamp(u, 0.0, 1.0);
  if (response_table.size() >= 2) {
    const double x = u * (response_table.size() - 1);
    const size_t i = std::min(static_cast<size_t>(x), response_table.size() - 2);
    const double f = x - i;
    return (1 - f) * response_table[i] + f * response_table[i + 1];
  }
  return std::pow(u, gamma);
}

double ProjectorParams::FlatField(double px, double py) const {
  const double dx = px - 0.5 * lens.width, dy = py - 0.5 * lens.height;
  const double corner2 = 0.25 * (static_cast<double>(lens.width) * lens.width +
                                 static_cast<double>(lens.height) * lens.height);
  return 1.0 - flat_field_falloff * (dx * dx + dy * dy) / corner2;
}

namespace {

// Shortest text that reads back as exactly v (std::to_chars round-trip guarantee).
std::string Num(double v) {
  char buf[64];
  const auto result = std::to_chars(buf, buf + sizeof(buf), v);
  return std::string(buf, result.ptr);
}

// Reads fields from a YAML tree, collecting every problem instead of stopping at the first.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  void Error(const std::string& path, const std::string& what) {
    errors_.push_back("rig file " + file_ + ": " + path + " " + what);
  }
  const std::vector<std::string>& errors() const { return errors_; }

  // Flags keys of `node` (a map at `path`) that are not in `known`.
  void CheckKeys(const YAML::Node& node, const std::string& path,
                 const std::vector<std::string>& known) {
    if (!node || !node.IsMap()) return;
    for (const auto& item : node) {
      if (!item.first.IsScalar()) {  // a list or map used as a key ("? [a, b]" or "{a: 1}: 2")
        Error(path.empty() ? "the top level" : path,
              "has a key that is a list or map; keys must be field names");
        continue;
      }
      const std::string key = item.first.as<std::string>();
      if (std::find(known.begin(), known.end(), key) == known.end()) {
        std::string list;
        for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
        Error(Join(path, key), "is not a known field (known in " + (path.empty() ? "the top level" : path) +
                                   ": " + list + ")");
      }
    }
  }

  YAML::Node Map(const YAML::Node& parent, const std::string& path, const std::string& key,
                 bool required) {
    const YAML::Node node = parent[key];
    if (!node) {
      if (required) Error(Join(path, key), "is missing");
      return YAML::Node();
    }
    if (!node.IsMap()) {
      Error(Join(path, key), "must be a map of fields");
      return YAML::Node();
    }
    return node;
  }

  // A finite number satisfying `check` (which returns "" or the requirement text).
  double Number(const YAML::Node& parent, const std::string& path, const std::string& key,
                std::optional<double> fallback,
                const std::function<std::string(double)>& check = nullptr) {
    const std::string full = Join(path, key);
    const YAML::Node node = parent ? parent[key] : YAML::Node();
    if (!node) {
      if (!fallback) {
        Error(full, "is missing");
        return 0;
      }
      return *fallback;
    }
    double value = 0;
    try {
      if (!node.IsScalar()) throw YAML::Exception(YAML::Mark(), "");
      value = node.as<double>();
    } catch (const YAML::Exception&) {
      Error(full, "must be a number (got '" + Dump(node) + "')");
      return fallback.value_or(0);
    }
    if (!std::isfinite(value)) {
      Error(full, "must be finite (got " + Dump(node) + ")");
      return fallback.value_or(0);
    }
    if (check) {
      const std::string requirement = check(value);
      if (!requirement.empty()) Error(full, "must be " + requirement + " (got " + Dump(node) + ")");
    }
    return value;
  }

  int Integer(const YAML::Node& parent, const std::string& path, const std::string& key,
              std::optional<int> fallback, int min, int max) {
    const double v = Number(parent, path, key, fallback ? std::optional<double>(*fallback)
                                                         : std::nullopt,
                            [&](double x) -> std::string {
                              if (x != std::floor(x) || x < min || x > max) {
                                return "an integer in [" + std::to_string(min) + ", " +
                                       std::to_string(max) + "]";
                              }
                              return "";
                            });
    // Out of range (an error is recorded): no cast, which would be undefined beyond int.
    return v >= min && v <= max ? static_cast<int>(v) : min;
  }

  std::vector<double> Numbers(const YAML::Node& parent, const std::string& path,
                              const std::string& key, size_t count,
                              std::optional<std::vector<double>> fallback) {
    const std::string full = Join(path, key);
    const YAML::Node node = parent ? parent[key] : YAML::Node();
    if (!node) {
      if (!fallback) Error(full, "is missing");
      return fallback.value_or(std::vector<double>(count, 0.0));
    }
    std::vector<double> out;
    bool ok = node.IsSequence() && (count == 0 || node.size() == count);
    if (ok) {
      for (const auto& item : node) {
        try {
          const double v = item.as<double>();
          if (!std::isfinite(v)) ok = false;
          out.push_back(v);
        } catch (const YAML::Exception&) {
          ok = false;
        }
      }
    }
    if (!ok) {
      Error(full, count ? "must be a list of " + std::to_string(count) + " finite numbers (got '" +
                              Dump(node) + "')"
                        : "must be a list of finite numbers (got '" + Dump(node) + "')");
      return fallback.value_or(std::vector<double>(count, 0.0));
    }
    return out;
  }

  std::string String(const YAML::Node& parent, const std::string& path, const std::string& key,
                     const std::string& fallback) {
    const YAML::Node node = parent ? parent[key] : YAML::Node();
    if (!node) return fallback;
    if (!node.IsScalar()) {
      Error(Join(path, key), "must be a text value");
      return fallback;
    }
    return node.as<std::string>();
  }

  static std::string Join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

 private:
  static std::string Dump(const YAML::Node& node) {
    std::ostringstream s;
    s << node;
    std::string text = s.str();
    for (char& c : text) {
      if (c == '\n') c = ' ';
    }
    return text.size() > 60 ? text.substr(0, 57) + "..." : text;
  }

  std::string file_;
  std::vector<std::string> errors_;
};

std::function<std::string(double)> Positive() {
  return [](double v) { return v > 0 ? "" : std::string("> 0"); };
}
std::function<std::string(double)> NonNegative() {
  return [](double v) { return v >= 0 ? "" : std::string(">= 0"); };
}
std::function<std::string(double)> Fraction() {
  return [](double v) { return v >= 0 && v <= 1 ? "" : std::string("in [0, 1]"); };
}
std::function<std::string(double)> Range(double lo, double hi) {
  return [lo, hi](double v) {
    return v >= lo && v <= hi ? "" : "in [" + Num(lo) + ", " + Num(hi) + "]";
  };
}

const std::vector<std::string> kLensKeys = {"resolution",        "pixel_pitch_um", "focal_length_mm",
                                            "f_number",          "focus_distance_mm",
                                            "position_mm",       "tilt_deg"};

ThinLensParams ReadLens(Reader& r, const YAML::Node& node, const std::string& path) {
  ThinLensParams lens;
  const std::vector<double> res = r.Numbers(node, path, "resolution", 2, std::nullopt);
  // Checked before the conversion to int, which is undefined for values beyond int's range.
  const auto pixels = [](double v) { return v >= 8 && v <= 20000 && v == std::floor(v); };
  if (pixels(res[0]) && pixels(res[1])) {
    lens.width = static_cast<int>(res[0]);
    lens.height = static_cast<int>(res[1]);
  } else {
    r.Error(Reader::Join(path, "resolution"),
            "must be two integers in [8, 20000] (width, height in pixels)");
  }
  lens.pixel_pitch_um = r.Number(node, path, "pixel_pitch_um", std::nullopt, Positive());
  lens.focal_length_mm = r.Number(node, path, "focal_length_mm", std::nullopt, Positive());
  lens.f_number = r.Number(node, path, "f_number", std::nullopt, Range(0.5, 64));
  lens.focus_distance_mm = r.Number(node, path, "focus_distance_mm", std::nullopt, Positive());
  if (lens.focal_length_mm > 0 && lens.focus_distance_mm > 0 &&
      lens.focus_distance_mm <= lens.focal_length_mm) {
    r.Error(Reader::Join(path, "focus_distance_mm"),
            "must exceed focal_length_mm (a thin lens cannot focus closer than its focal length)");
  }
  const std::vector<double> pos = r.Numbers(node, path, "position_mm", 3, std::nullopt);
  lens.position_mm = {pos[0], pos[1], pos[2]};
  const std::vector<double> tilt = r.Numbers(node, path, "tilt_deg", 2, std::vector<double>{0, 0});
  for (int i = 0; i < 2; ++i) {
    lens.tilt_deg[i] = tilt[i];
    if (std::abs(tilt[i]) > 30) r.Error(Reader::Join(path, "tilt_deg"), "must be within +-30 deg");
  }
  return lens;
}

void ReadOffsetTilt(Reader& r, const YAML::Node& node, const std::string& path,
                    const std::string& prefix, Vec3* offset, double tilt[2]) {
  const std::vector<double> o =
      r.Numbers(node, path, prefix + "_offset_mm", 3, std::vector<double>{0, 0, 0});
  *offset = {o[0], o[1], o[2]};
  const std::vector<double> t =
      r.Numbers(node, path, prefix + "_tilt_deg", 2, std::vector<double>{0, 0});
  for (int i = 0; i < 2; ++i) {
    tilt[i] = t[i];
    if (std::abs(t[i]) > 10) {
      r.Error(Reader::Join(path, prefix + "_tilt_deg"), "must be within +-10 deg");
    }
  }
  for (double v : o) {
    if (std::abs(v) > 20) {
      r.Error(Reader::Join(path, prefix + "_offset_mm"), "must be within +-20 mm");
      break;
    }
  }
}

}  // namespace

Rig ParseRig(const std::string& yaml_text, const std::string& name_for_errors) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError("rig file " + name_for_errors + ": not valid YAML: " + e.what());
  }
  if (!root || !root.IsMap()) {
    throw InputError("rig file " + name_for_errors +
                     ": must be a YAML map of sections (parabola, dome, camera, projector, ...)");
  }
  Reader r(name_for_errors);
  Rig rig;
  r.CheckKeys(root, "", {"name", "parabola", "dome", "camera", "projector", "beam_splitter",
                         "mirror_reflectance", "sample_diameter_mm", "sensor", "timing",
                         "misalignment", "simulation"});
  rig.name = r.String(root, "", "name", "unnamed rig");

  const YAML::Node parabola = r.Map(root, "", "parabola", true);
  r.CheckKeys(parabola, "parabola", {"vertex_height_mm", "focal_length_mm", "rim_radius_mm"});
  rig.parabola.vertex_height_mm =
      r.Number(parabola, "parabola", "vertex_height_mm", std::nullopt, Positive());
  rig.parabola.focal_length_mm =
      r.Number(parabola, "parabola", "focal_length_mm", std::nullopt, Positive());
  rig.parabola.rim_radius_mm =
      r.Number(parabola, "parabola", "rim_radius_mm", std::nullopt, Positive());

  const YAML::Node dome = r.Map(root, "", "dome", false);
  r.CheckKeys(dome, "dome", {"lower_edge_height_mm", "design_steps"});
  rig.dome.lower_edge_height_mm =
      r.Number(dome, "dome", "lower_edge_height_mm", 0.0, NonNegative());
  rig.dome.design_steps = r.Integer(dome, "dome", "design_steps", 20000, 100, 10000000);

  const YAML::Node camera = r.Map(root, "", "camera", true);
  r.CheckKeys(camera, "camera", kLensKeys);
  if (camera) rig.camera = ReadLens(r, camera, "camera");

  const YAML::Node projector = r.Map(root, "", "projector", true);
  std::vector<std::string> projector_keys = kLensKeys;
  for (const char* k : {"bit_depth", "gamma", "response_table", "black_level",
                        "flat_field_falloff", "peak_radiance_w_m2_sr"}) {
    projector_keys.push_back(k);
  }
  r.CheckKeys(projector, "projector", projector_keys);
  if (projector) {
    rig.projector.lens = ReadLens(r, projector, "projector");
    rig.projector.bit_depth = r.Integer(projector, "projector", "bit_depth", 8, 1, 16);
    rig.projector.gamma = r.Number(projector, "projector", "gamma", 1.0, Range(0.1, 10));
    if (projector["response_table"]) {
      rig.projector.response_table =
          r.Numbers(projector, "projector", "response_table", 0, std::vector<double>{});
      const auto& t = rig.projector.response_table;
      bool monotone = t.size() >= 2 && t.front() >= 0 && t.back() <= 1 + 1e-12;
      for (size_t i = 1; i < t.size(); ++i) monotone = monotone && t[i] >= t[i - 1];
      if (!monotone) {
        r.Error("projector.response_table",
                "must list >= 2 non-decreasing values in [0, 1] (response at evenly spaced "
                "input levels from 0 to 1)");
      }
    }
    rig.projector.black_level = r.Number(projector, "projector", "black_level", 0.0, Range(0, 0.5));
    rig.projector.flat_field_falloff =
        r.Number(projector, "projector", "flat_field_falloff", 0.0, Range(0, 0.9));
    rig.projector.peak_radiance_w_m2_sr =
        r.Number(projector, "projector", "peak_radiance_w_m2_sr", 1.0, Positive());
  }

  const YAML::Node splitter = r.Map(root, "", "beam_splitter", false);
  r.CheckKeys(splitter, "beam_splitter", {"transmission", "reflection"});
  rig.beam_splitter_transmission =
      r.Number(splitter, "beam_splitter", "transmission", 0.5, Fraction());
  rig.beam_splitter_reflection = r.Number(splitter, "beam_splitter", "reflection", 0.5, Fraction());
  if (rig.beam_splitter_transmission + rig.beam_splitter_reflection > 1 + 1e-9) {
    r.Error("beam_splitter", "transmission + reflection must be <= 1");
  }
  rig.mirror_reflectance = r.Number(root, "", "mirror_reflectance", 0.9, Range(0.01, 1));
  rig.sample_diameter_mm = r.Number(root, "", "sample_diameter_mm", 40.0, Positive());

  const YAML::Node sensor = r.Map(root, "", "sensor", false);
  r.CheckKeys(sensor, "sensor", {"gain_e_per_dn", "read_noise_e", "dark_level_dn", "bit_depth",
                                 "saturation_dn", "full_well_e", "quantum_efficiency", "layout"});
  SensorParams& s = rig.sensor;
  s.gain_e_per_dn = r.Number(sensor, "sensor", "gain_e_per_dn", 2.0, Positive());
  s.read_noise_e = r.Number(sensor, "sensor", "read_noise_e", 6.0, NonNegative());
  s.bit_depth = r.Integer(sensor, "sensor", "bit_depth", 12, 8, 16);
  const double max_dn = std::ldexp(1.0, s.bit_depth) - 1;
  s.dark_level_dn = r.Number(sensor, "sensor", "dark_level_dn", 64.0, Range(0, max_dn / 2));
  s.saturation_dn = r.Number(sensor, "sensor", "saturation_dn", max_dn, Range(1, max_dn));
  s.full_well_e = r.Number(sensor, "sensor", "full_well_e", 20000.0, Positive());
  s.quantum_efficiency = r.Number(sensor, "sensor", "quantum_efficiency", 0.5, Range(1e-3, 1));
  try {
    s.layout = ParsePixelLayout(r.String(sensor, "sensor", "layout", "bayer-rggb"));
    if (s.layout == PixelLayout::kRgb) r.Error("sensor.layout", "must be mono or a Bayer mosaic");
  } catch (const InputError& e) {
    r.Error("sensor.layout", std::string("is not valid: ") + e.what());
  }

  const YAML::Node timing = r.Map(root, "", "timing", false);
  r.CheckKeys(timing, "timing", {"frame_rate_hz", "readout_ms", "projector_settle_ms"});
  rig.timing.frame_rate_hz = r.Number(timing, "timing", "frame_rate_hz", 15.0, Range(0.01, 10000));
  rig.timing.readout_ms = r.Number(timing, "timing", "readout_ms", 30.0, NonNegative());
  rig.timing.projector_settle_ms =
      r.Number(timing, "timing", "projector_settle_ms", 50.0, NonNegative());

  const YAML::Node mis = r.Map(root, "", "misalignment", false);
  r.CheckKeys(mis, "misalignment",
              {"camera_offset_mm", "camera_tilt_deg", "projector_offset_mm", "projector_tilt_deg",
               "parabola_offset_mm", "parabola_tilt_deg"});
  ReadOffsetTilt(r, mis, "misalignment", "camera", &rig.misalignment.camera_offset_mm,
                 rig.misalignment.camera_tilt_deg);
  ReadOffsetTilt(r, mis, "misalignment", "projector", &rig.misalignment.projector_offset_mm,
                 rig.misalignment.projector_tilt_deg);
  ReadOffsetTilt(r, mis, "misalignment", "parabola", &rig.misalignment.parabola_offset_mm,
                 rig.misalignment.parabola_tilt_deg);

  const YAML::Node sim = r.Map(root, "", "simulation", false);
  r.CheckKeys(sim, "simulation", {"samples_per_pixel", "aperture_samples", "direction_grid_deg"});
  rig.simulation.samples_per_pixel =
      r.Integer(sim, "simulation", "samples_per_pixel", 512, 1, 65536);
  rig.simulation.aperture_samples = r.Integer(sim, "simulation", "aperture_samples", 16, 1, 1024);
  rig.simulation.direction_grid_deg =
      r.Number(sim, "simulation", "direction_grid_deg", 0.1, Range(0.01, 2));

  // Cross-field geometry checks.
  if (r.errors().empty()) {
    const double rim_height = rig.parabola.vertex_height_mm -
                              rig.parabola.rim_radius_mm * rig.parabola.rim_radius_mm /
                                  (4 * rig.parabola.focal_length_mm);
    if (rim_height <= 0) {
      r.Error("parabola", "reaches below the sample plane: rim height vertex_height_mm - "
                          "rim_radius_mm^2 / (4 focal_length_mm) = " +
                              Num(rim_height) + " mm must be > 0");
    }
    if (rig.camera.position_mm.z <= rig.parabola.vertex_height_mm) {
      r.Error("camera.position_mm", "must be above the parabola vertex (z > " +
                                        Num(rig.parabola.vertex_height_mm) + " mm)");
    }
    if (rig.projector.lens.position_mm.z <= rig.parabola.vertex_height_mm) {
      r.Error("projector.position_mm", "must be above the parabola vertex (z > " +
                                           Num(rig.parabola.vertex_height_mm) + " mm)");
    }
  }

  if (!r.errors().empty()) {
    std::string message;
    for (const auto& e : r.errors()) message += (message.empty() ? "" : "\n") + e;
    throw InputError(message);
  }
  return rig;
}

namespace {

// The rigs shipped with zbrdf: the NAME.yaml files in DataRoot()/rig/rigs, sorted.
std::vector<std::string> BundledRigNames() {
  std::vector<std::string> names;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(DataPath("rig/rigs"), error)) {
    if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::string CommaList(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
  return out.empty() ? "none found" : out;
}

}  // namespace

Rig LoadRig(const std::string& path_or_name) {
  std::string path = path_or_name;
  std::error_code error;
  const bool bare_name = !path.empty() && path.find_first_of("/.") == std::string::npos;
  if (bare_name && !std::filesystem::exists(path, error)) {
    path = DataPath("rig/rigs/" + path + ".yaml");
  }
  std::ifstream in(path);
  if (!in && bare_name) {
    const std::vector<std::string> names = BundledRigNames();
    const std::vector<std::string> close = ClosestNames(path_or_name, names);
    throw InputError("rig '" + path_or_name + "' is neither a file nor a bundled rig" +
                     (close.empty() ? "" : "; did you mean '" + close.front() + "'?") +
                     " Give the path of a rig YAML or the name of a bundled rig (" +
                     CommaList(names) + ", in " + DataPath("rig/rigs") + ")");
  }
  if (!in) {
    throw InputError("rig file " + path +
                     " cannot be read; give the path of a rig YAML such as "
                     "rig/rigs/thesis.yaml, or the name of a bundled rig (" +
                     CommaList(BundledRigNames()) + ")");
  }
  std::stringstream text;
  text << in.rdbuf();
  Rig rig = ParseRig(text.str(), path);
  rig.source_path = path;
  return rig;
}

namespace {

// Merges overlay into base: maps key by key, anything else replaced. `source` names the overlay
// in errors.
void MergeYaml(YAML::Node base, const YAML::Node& overlay, const std::string& source) {
  for (auto it = overlay.begin(); it != overlay.end(); ++it) {
    if (!it->first.IsScalar()) {
      throw InputError("rig overlay " + source +
                       ": a key is a list or map; keys must be rig field names, e.g. "
                       "misalignment: {camera_tilt_deg: [0.5, 0]}");
    }
    const std::string key = it->first.as<std::string>();
    if (it->second.IsMap() && base[key] && base[key].IsMap()) {
      MergeYaml(base[key], it->second, source);
    } else {
      base[key] = it->second;
    }
  }
}

}  // namespace

Rig ApplyRigOverlayText(const Rig& rig, const std::string& yaml_text,
                        const std::string& name_for_errors) {
  YAML::Node overlay;
  try {
    overlay = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError("rig overlay " + name_for_errors + ": not valid YAML: " + e.what());
  }
  if (!overlay || overlay.IsNull()) return rig;
  if (!overlay.IsMap()) {
    throw InputError("rig overlay " + name_for_errors +
                     ": must be a YAML map of rig sections, e.g. misalignment: {...}");
  }
  YAML::Node base = YAML::Load(WriteRigYaml(rig));
  MergeYaml(base, overlay, name_for_errors);
  YAML::Emitter out;
  out << base;
  Rig built = ParseRig(std::string(out.c_str()) + "\n", rig.name + " + " + name_for_errors);
  built.source_path = rig.source_path;
  return built;
}

Rig ApplyRigOverlay(const Rig& rig, const std::string& overlay_path) {
  std::ifstream in(overlay_path);
  if (!in) {
    throw InputError("rig overlay " + overlay_path +
                     " cannot be read; give a YAML file of the rig fields to change");
  }
  std::stringstream text;
  text << in.rdbuf();
  return ApplyRigOverlayText(rig, text.str(), overlay_path);
}

namespace {
void EmitLens(YAML::Emitter& out, const ThinLensParams& lens) {
  out << YAML::Key << "resolution" << YAML::Value << YAML::Flow << YAML::BeginSeq << lens.width
      << lens.height << YAML::EndSeq;
  out << YAML::Key << "pixel_pitch_um" << YAML::Value << Num(lens.pixel_pitch_um);
  out << YAML::Key << "focal_length_mm" << YAML::Value << Num(lens.focal_length_mm);
  out << YAML::Key << "f_number" << YAML::Value << Num(lens.f_number);
  out << YAML::Key << "focus_distance_mm" << YAML::Value << Num(lens.focus_distance_mm);
  out << YAML::Key << "position_mm" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << Num(lens.position_mm.x) << Num(lens.position_mm.y) << Num(lens.position_mm.z)
      << YAML::EndSeq;
  out << YAML::Key << "tilt_deg" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << Num(lens.tilt_deg[0]) << Num(lens.tilt_deg[1]) << YAML::EndSeq;
}
void EmitVec(YAML::Emitter& out, const std::string& key, const Vec3& v) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq << Num(v.x) << Num(v.y)
      << Num(v.z) << YAML::EndSeq;
}
void EmitPair(YAML::Emitter& out, const std::string& key, const double v[2]) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq << Num(v[0]) << Num(v[1])
      << YAML::EndSeq;
}
}  // namespace

std::string WriteRigYaml(const Rig& rig) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << rig.name;
  out << YAML::Key << "parabola" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "vertex_height_mm" << YAML::Value << Num(rig.parabola.vertex_height_mm);
  out << YAML::Key << "focal_length_mm" << YAML::Value << Num(rig.parabola.focal_length_mm);
  out << YAML::Key << "rim_radius_mm" << YAML::Value << Num(rig.parabola.rim_radius_mm);
  out << YAML::EndMap;
  out << YAML::Key << "dome" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "lower_edge_height_mm" << YAML::Value << Num(rig.dome.lower_edge_height_mm);
  out << YAML::Key << "design_steps" << YAML::Value << rig.dome.design_steps;
  out << YAML::EndMap;
  out << YAML::Key << "camera" << YAML::Value << YAML::BeginMap;
  EmitLens(out, rig.camera);
  out << YAML::EndMap;
  out << YAML::Key << "projector" << YAML::Value << YAML::BeginMap;
  EmitLens(out, rig.projector.lens);
  out << YAML::Key << "bit_depth" << YAML::Value << rig.projector.bit_depth;
  out << YAML::Key << "gamma" << YAML::Value << Num(rig.projector.gamma);
  if (!rig.projector.response_table.empty()) {
    out << YAML::Key << "response_table" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (double v : rig.projector.response_table) out << Num(v);
    out << YAML::EndSeq;
  }
  out << YAML::Key << "black_level" << YAML::Value << Num(rig.projector.black_level);
  out << YAML::Key << "flat_field_falloff" << YAML::Value << Num(rig.projector.flat_field_falloff);
  out << YAML::Key << "peak_radiance_w_m2_sr" << YAML::Value
      << Num(rig.projector.peak_radiance_w_m2_sr);
  out << YAML::EndMap;
  out << YAML::Key << "beam_splitter" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "transmission" << YAML::Value << Num(rig.beam_splitter_transmission);
  out << YAML::Key << "reflection" << YAML::Value << Num(rig.beam_splitter_reflection);
  out << YAML::EndMap;
  out << YAML::Key << "mirror_reflectance" << YAML::Value << Num(rig.mirror_reflectance);
  out << YAML::Key << "sample_diameter_mm" << YAML::Value << Num(rig.sample_diameter_mm);
  const SensorParams& s = rig.sensor;
  out << YAML::Key << "sensor" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "gain_e_per_dn" << YAML::Value << Num(s.gain_e_per_dn);
  out << YAML::Key << "read_noise_e" << YAML::Value << Num(s.read_noise_e);
  out << YAML::Key << "dark_level_dn" << YAML::Value << Num(s.dark_level_dn);
  out << YAML::Key << "bit_depth" << YAML::Value << s.bit_depth;
  out << YAML::Key << "saturation_dn" << YAML::Value << Num(s.saturation_dn);
  out << YAML::Key << "full_well_e" << YAML::Value << Num(s.full_well_e);
  out << YAML::Key << "quantum_efficiency" << YAML::Value << Num(s.quantum_efficiency);
  out << YAML::Key << "layout" << YAML::Value << PixelLayoutName(s.layout);
  out << YAML::EndMap;
  out << YAML::Key << "timing" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "frame_rate_hz" << YAML::Value << Num(rig.timing.frame_rate_hz);
  out << YAML::Key << "readout_ms" << YAML::Value << Num(rig.timing.readout_ms);
  out << YAML::Key << "projector_settle_ms" << YAML::Value << Num(rig.timing.projector_settle_ms);
  out << YAML::EndMap;
  const Misalignment& m = rig.misalignment;
  out << YAML::Key << "misalignment" << YAML::Value << YAML::BeginMap;
  EmitVec(out, "camera_offset_mm", m.camera_offset_mm);
  EmitPair(out, "camera_tilt_deg", m.camera_tilt_deg);
  EmitVec(out, "projector_offset_mm", m.projector_offset_mm);
  EmitPair(out, "projector_tilt_deg", m.projector_tilt_deg);
  EmitVec(out, "parabola_offset_mm", m.parabola_offset_mm);
  EmitPair(out, "parabola_tilt_deg", m.parabola_tilt_deg);
  out << YAML::EndMap;
  out << YAML::Key << "simulation" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "samples_per_pixel" << YAML::Value << rig.simulation.samples_per_pixel;
  out << YAML::Key << "aperture_samples" << YAML::Value << rig.simulation.aperture_samples;
  out << YAML::Key << "direction_grid_deg" << YAML::Value << Num(rig.simulation.direction_grid_deg);
  out << YAML::EndMap;
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

uint64_t RigHash(const Rig& rig) { return Fnv1a64(WriteRigYaml(rig)); }

Preset ParsePreset(const std::string& name) {
  if (name == "fast") return Preset::kFast;
  if (name == "full") return Preset::kFull;
  throw InputError("unknown preset '" + name + "'; use fast or full");
}

std::string RigHashHex(const Rig& rig) {
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(RigHash(rig)));
  return hex;
}

Rig ApplyPreset(const Rig& rig, Preset preset) {
  if (preset == Preset::kFull) return rig;
  Rig out = rig;
  auto shrink = [](ThinLensParams& lens) {
    lens.width = std::max(8, lens.width / 4);
    lens.height = std::max(8, lens.height / 4);
    lens.pixel_pitch_um *= 4;
  };
  shrink(out.camera);
  shrink(out.projector.lens);
  // A fast pixel stands for the 4 x 4 full-resolution pixels it covers, as if binned: it holds
  // their summed charge (full well x16, read noise x4 from 16 independent reads) and reports
  // it on the same 12-bit scale (gain x16). Noise per unit of measured area is then the rig's.
  out.sensor.full_well_e *= 16;
  out.sensor.gain_e_per_dn *= 16;
  out.sensor.read_noise_e *= 4;
  out.simulation.direction_grid_deg = std::max(rig.simulation.direction_grid_deg, 0.25);
  // Sixteen times fewer pixels buy twice the samples per pixel: frames converge to within 1%
  // (relative RMS) also for sharp materials (tests/simulate/imaging_test.cc).
  out.simulation.samples_per_pixel = 2 * rig.simulation.samples_per_pixel;
  out.name = rig.name + " (fast preset)";
  return out;
}

}  // namespace zbrdf
