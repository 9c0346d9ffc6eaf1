#include "calibration/calibration_data.h"

#include <filesystem>
#include <fstream>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "calibration/float_image.h"
#include "rig/direction_maps.h"
#include "rig/optics.h"

namespace zbrdf {

namespace {

constexpr const char* kFormat = "zbrdf-calibration-v1";

nlohmann::json Vec(const Vec3& v) { return {v.x, v.y, v.z}; }
nlohmann::json CalibrationPair(const double v[2]) { return {v[0], v[1]}; }

nlohmann::json MisalignmentJson(const Misalignment& m) {
  return {{"camera_offset_mm", Vec(m.camera_offset_mm)},
          {"camera_tilt_deg", CalibrationPair(m.camera_tilt_deg)},
          {"projector_offset_mm", Vec(m.projector_offset_mm)},
          {"projector_tilt_deg", CalibrationPair(m.projector_tilt_deg)},
          {"parabola_offset_mm", Vec(m.parabola_offset_mm)},
          {"parabola_tilt_deg", CalibrationPair(m.parabola_tilt_deg)}};
}

Misalignment MisalignmentFromJson(const nlohmann::json& j) {
  Misalignment m;
  auto vec = [&](const char* key, Vec3* out) {
    const auto v = j.at(key).get<std::vector<double>>();
    if (v.size() != 3) throw InputError(std::string(key) + " needs 3 values");
    *out = {v[0], v[1], v[2]};
  };
  auto pair = [&](const char* key, double out[2]) {
    const auto v = j.at(key).get<std::vector<double>>();
    if (v.size() != 2) throw InputError(std::string(key) + " needs 2 values");
    out[0] = v[0];
    out[1] = v[1];
  };
  vec("camera_offset_mm", &m.camera_offset_mm);
  pair("camera_tilt_deg", m.camera_tilt_deg);
  vec("projector_offset_mm", &m.projector_offset_mm);
  pair("projector_tilt_deg", m.projector_tilt_deg);
  vec("parabola_offset_mm", &m.parabola_offset_mm);
  pair("parabola_tilt_deg", m.parabola_tilt_deg);
  return m;
}

void WriteField(const std::string& path, const PixelField& field) {
  FloatImage image;
  image.width = field.width;
  image.height = field.height;
  image.channels["Y"] = field.value;
  WriteFloatImage(path, image);
}

PixelField ReadField(const std::string& path) {
  const FloatImage image = ReadFloatImage(path, {"Y"});
  return {image.width, image.height, image.channels.at("Y")};
}

}  // namespace

std::vector<std::string> CalibrationData::Steps() const {
  std::vector<std::string> steps;
  if (misalignment) steps.push_back("geometry");
  if (sensor) steps.push_back("noise");
  if (projector_response || projector_flat) steps.push_back("projector");
  if (scale_rgb) steps.push_back("graycard");
  return steps;
}

CalibrationData NewCalibration(const Rig& design) {
  CalibrationData data;
  data.rig_name = design.name;
  data.rig_hash = std::to_string(RigHash(design));
  return data;
}

void SaveCalibration(const std::string& folder, const CalibrationData& data) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) throw InputError("cannot create calibration folder " + folder + ": " + ec.message());
  nlohmann::json j;
  j["format"] = kFormat;
  j["rig"] = {{"name", data.rig_name}, {"hash", data.rig_hash}};
  j["steps"] = data.Steps();
  if (data.misalignment) j["geometry"] = {{"misalignment", MisalignmentJson(*data.misalignment)}};
  if (data.sensor) {
    j["noise"] = {{"gain_e_per_dn", data.sensor->gain_e_per_dn},
                  {"read_noise_e", data.sensor->read_noise_e},
                  {"black_dn", data.sensor->black_dn},
                  {"saturation_dn", data.sensor->saturation_dn}};
  }
  if (data.projector_response) {
    j["projector"]["response"] = data.projector_response->response;
    j["projector"]["black_fraction"] = data.projector_response->black_fraction;
  }
  if (data.projector_flat) {
    WriteField(folder + "/projector_flat.exr", *data.projector_flat);
    j["projector"]["flat_field"] = "projector_flat.exr";
  }
  if (data.camera_flat) {
    WriteField(folder + "/camera_flat.exr", *data.camera_flat);
    j["camera_flat"] = {{"file", "camera_flat.exr"}, {"source", data.camera_flat_source}};
  }
  if (data.scale_rgb) j["graycard"] = {{"scale_rgb", *data.scale_rgb}};
  j["reports"] = data.reports;
  WriteFileAtomically(folder + "/calibration.json", j.dump(2) + "\n");
}

CalibrationData LoadCalibration(const std::string& folder) {
  const std::string path = folder + "/calibration.json";
  std::ifstream in(path);
  if (!in) {
    throw InputError("calibration folder " + folder +
                     " has no calibration.json; create it with zbrdf calibrate");
  }
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object() || j.value("format", "") != kFormat) {
    throw InputError(path + " is not a zbrdf calibration (format " + kFormat +
                     "); re-create it with zbrdf calibrate");
  }
  CalibrationData data;
  try {
    data.rig_name = j.at("rig").at("name").get<std::string>();
    data.rig_hash = j.at("rig").at("hash").get<std::string>();
    if (j.contains("geometry")) data.misalignment = MisalignmentFromJson(j["geometry"].at("misalignment"));
    if (j.contains("noise")) {
      const auto& n = j["noise"];
      SensorCalibration s;
      s.gain_e_per_dn = n.at("gain_e_per_dn").get<double>();
      s.read_noise_e = n.at("read_noise_e").get<double>();
      s.black_dn = n.at("black_dn").get<double>();
      s.saturation_dn = n.at("saturation_dn").get<double>();
      if (!(s.gain_e_per_dn > 0 && s.read_noise_e >= 0 && s.saturation_dn > s.black_dn)) {
        throw InputError("noise parameters out of range");
      }
      data.sensor = s;
    }
    if (j.contains("projector")) {
      const auto& p = j["projector"];
      if (p.contains("response")) {
        ProjectorResponseCalibration r;
        r.response = p["response"].get<std::vector<double>>();
        r.black_fraction = p.value("black_fraction", 0.0);
        for (size_t i = 1; i < r.response.size(); ++i) {
          if (!(r.response[i] >= r.response[i - 1])) throw InputError("projector response is not monotone");
        }
        if (r.response.size() < 2) throw InputError("projector response has fewer than 2 levels");
        data.projector_response = r;
      }
      if (p.contains("flat_field")) {
        data.projector_flat = ReadField(folder + "/" + p["flat_field"].get<std::string>());
      }
    }
    if (j.contains("camera_flat")) {
      data.camera_flat = ReadField(folder + "/" + j["camera_flat"].at("file").get<std::string>());
      data.camera_flat_source = j["camera_flat"].value("source", "");
    }
    if (j.contains("graycard")) {
      const auto s = j["graycard"].at("scale_rgb").get<std::vector<double>>();
      if (s.size() != 3 || !(s[0] > 0 && s[1] > 0 && s[2] > 0)) throw InputError("scale_rgb must be 3 positive values");
      data.scale_rgb = std::array<double, 3>{s[0], s[1], s[2]};
    }
    if (j.contains("reports") && j["reports"].is_object()) data.reports = j["reports"];
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + " is damaged (" + e.what() + "); re-create it with zbrdf calibrate");
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (what.find(folder) != std::string::npos) throw;
    throw InputError(path + ": " + what + "; re-create it with zbrdf calibrate");
  }
  return data;
}

void CheckCalibrationRig(const CalibrationData& data, const Rig& design, const std::string& folder) {
  if (data.rig_hash != std::to_string(RigHash(design))) {
    throw InputError("calibration " + folder + " belongs to rig '" + data.rig_name + "' (hash " +
                     data.rig_hash + "), not to this rig description '" + design.name +
                     "' (hash " + std::to_string(RigHash(design)) +
                     "); use the same --rig and --preset it was made with, or calibrate this rig");
  }
}

Rig CalibratedRig(const Rig& design, const CalibrationData& data) {
  Rig rig = design;
  if (data.misalignment) rig.misalignment = *data.misalignment;
  return rig;
}

RigCalibration ApplyCalibration(const Rig& design, const CalibrationData& data,
                                const std::string& source, const std::string& cache_dir,
                                const ProgressCallback& progress) {
  const Rig rig = CalibratedRig(design, data);
  const OpticalSystem optics(rig);
  RigCalibration c = NominalCalibration(rig, LoadOrBuildRigMaps(optics, cache_dir, progress));
  c.source = source;
  if (data.sensor) {
    c.gain_e_per_dn = data.sensor->gain_e_per_dn;
    c.read_noise_e = data.sensor->read_noise_e;
    c.black_dn = data.sensor->black_dn;
    c.saturation_dn = data.sensor->saturation_dn;
  }
  if (data.projector_response) {
    if (static_cast<int>(data.projector_response->response.size()) != 1 << c.projector_bit_depth) {
      throw InputError(source + ": the projector response has " +
                       std::to_string(data.projector_response->response.size()) +
                       " levels, the rig's projector " + std::to_string(1 << c.projector_bit_depth));
    }
    c.projector_response = data.projector_response->response;
    c.projector_black_fraction = data.projector_response->black_fraction;
  }
  auto check = [&](const PixelField& f, int w, int h, const char* what) {
    if (f.width != w || f.height != h || f.value.size() != static_cast<size_t>(w) * h) {
      throw InputError(source + ": the " + std::string(what) + " flat field is " +
                       std::to_string(f.width) + "x" + std::to_string(f.height) + ", the device " +
                       std::to_string(w) + "x" + std::to_string(h));
    }
  };
  if (data.projector_flat) {
    check(*data.projector_flat, c.projector_width, c.projector_height, "projector");
    c.projector_flat_field = data.projector_flat->value;
  }
  if (data.camera_flat) {
    check(*data.camera_flat, c.camera_width, c.camera_height, "camera");
    for (size_t i = 0; i < c.camera_response.size(); ++i) {
      c.camera_response[i] *= std::max(0.0f, data.camera_flat->value[i]);
    }
  }
  if (data.scale_rgb) c.channel_scale = *data.scale_rgb;
  return c;
}

RigCalibration LoadRigCalibration(const Rig& design, const std::string& folder,
                                  const std::string& cache_dir, const ProgressCallback& progress) {
  if (folder.empty()) {
    const OpticalSystem optics(design);
    return NominalCalibration(design, LoadOrBuildRigMaps(optics, cache_dir, progress));
  }
  const CalibrationData data = LoadCalibration(folder);
  CheckCalibrationRig(data, design, folder);
  return ApplyCalibration(design, data, "calibration: " + folder, cache_dir, progress);
}

}  // namespace zbrdf
