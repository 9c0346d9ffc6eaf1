#include "tools/virtual_capture.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "acquisition/session.h"
#include "calibration/calibration_data.h"
#include "simulate/direction_maps.h"
#include "basis/error.h"
#include "fitting/material_spec.h"
#include "simulate/virtual_rig.h"

namespace zbrdf {

VirtualCaptureOutcome RunVirtualCapture(VirtualCaptureArgs args) {
  const auto start = std::chrono::steady_clock::now();
  if (args.job.resume) {
    // The session decides what is being captured.
    const nlohmann::json s = SessionFolder::Open(args.job.out_dir).session();
    const std::string material = s.value("material", std::string());
    if (material.empty()) {
      throw InputError("session " + args.job.out_dir + " was not captured on the virtual rig "
                       "(no material in session.json); resume it with its hardware rig file");
    }
    if (!args.material_spec.empty() && MakeBrdf(args.material_spec)->Spec() != material) {
      throw InputError("session " + args.job.out_dir + " captures " + material + ", not " +
                       args.material_spec + "; leave --material out to resume it");
    }
    args.material_spec = material;
    args.seed = s.value("seed", args.seed);
    args.noise = s.value("noise", args.noise);
    args.faults_yaml = s.value("faults", std::string());
    args.faults_name = "session faults";
    if (args.calibration_folder.empty()) args.calibration_folder = s.value("calibration_folder", std::string());
  }
  if (args.material_spec.empty()) throw InputError("no --material given for the virtual rig");
  if (!args.job.resume && std::filesystem::exists(args.job.out_dir + "/session.json")) {
    throw InputError("folder " + args.job.out_dir +
                     " already holds a session; resume it (--resume) or choose another --out");
  }
  VirtualCaptureOutcome out;
  out.material = MakeBrdf(args.material_spec);
  VirtualRig::Options vr;
  vr.seed = args.seed;
  vr.noise = args.noise;
  vr.progress = args.job.progress;
  const Rig as_built = args.faults_yaml.empty()
                           ? args.rig
                           : ApplyRigOverlayText(args.rig, args.faults_yaml, args.faults_name);
  VirtualRig rig(as_built, out.material, vr);
  out.transport_entries = rig.model().transport_entries();
  const RigCalibration calibration =
      LoadRigCalibration(args.rig, args.calibration_folder, DefaultCacheDir(), args.job.progress);
  out.setup_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  args.job.session_extra = {{"material", out.material->Spec()},
                            {"seed", args.seed},
                            {"preset", args.preset_name},
                            {"noise", args.noise},
                            {"kind", "simulated"}};
  if (!args.faults_yaml.empty()) args.job.session_extra["faults"] = args.faults_yaml;
  if (!args.calibration_folder.empty()) {
    args.job.session_extra["calibration_folder"] =
        std::filesystem::absolute(args.calibration_folder).lexically_normal().string();
  }
  out.result = RunCaptureJob(args.rig, calibration, rig.camera(), rig.projector(), rig.clock(),
                             args.job);
  out.device_time_s = rig.clock().NowUs() * 1e-6;
  return out;
}

Rig SessionRig(const std::string& session_dir) {
  const nlohmann::json s = SessionFolder::Open(session_dir).session();
  if (!s.contains("rig") || !s["rig"].is_string()) {
    throw InputError(session_dir + "/session.json has no rig description; the session is damaged");
  }
  return ParseRig(s["rig"].get<std::string>(), session_dir + "/session.json (rig)");
}

}  // namespace zbrdf

namespace zbrdf {

std::string ReadTextFile(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw InputError(what + " " + path + " cannot be read");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string SessionCalibrationFolder(const std::string& session_dir) {
  return SessionFolder::Open(session_dir).session().value("calibration_folder", std::string());
}

}  // namespace zbrdf
