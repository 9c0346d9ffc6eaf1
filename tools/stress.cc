#include "tools/stress.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <random>
#include <typeinfo>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfMultiPartInputFile.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfStdIO.h>

#include "acquisition/hdr.h"
#include "acquisition/session.h"
#include "acquisition/zonal.h"
#include "basis/atomic_file.h"
#include "basis/conditioning.h"
#include "basis/conversion.h"
#include "basis/data_path.h"
#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/spherical_harmonics.h"
#include "basis/zone.h"
#include "brdf/sh_file.h"
#include "rig/rig.h"
#include "tools/fit_session.h"
#include "tools/sh_conversion.h"
#include "tools/virtual_capture.h"

namespace zbrdf {
namespace {

namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

std::string FormatValue(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3g", v);
  return buffer;
}

void Check(bool ok, const std::string& what) {
  if (!ok) throw StressCheckFailed(what);
}

// ---------------------------------------------------------------------------------------------
// basis: the conditioning report (basis/conditioning.h) runs the whole chain: ZB quadrature,
// target Gram blocks, the truncated-SVD conversion and a band-limited round trip.

struct BasisCase {
  double zone_min_deg, zone_max_deg;
  int order;
  TargetKind target;
  double tau;
  // Relative L2 round-trip error in the zone without noise. The factored Apply keeps rounding
  // along the singular vectors (conversion.h), so the round trip reproduces a band-limited
  // function to ~1e-11 even where cond(Gram) is beyond 1e16 (measured 2e-12 .. 2e-11 at order
  // 30); the bound leaves three orders of margin and is still far below any capture's 1e-3.
  double max_roundtrip_in_zone;
  bool expect_truncation;
};

std::string RunBasisCase(const BasisCase& c) {
  ConditioningOptions o;
  const Zone zone = Zone::FromDegrees(c.zone_min_deg, c.zone_max_deg);
  o.theta_min_rad = zone.theta_min_rad();
  o.theta_max_rad = zone.theta_max_rad();
  o.zb_order = o.target_order = c.order;
  o.target = c.target;
  o.tau = c.tau;
  const ConditioningReport r = AnalyzeConditioning(o);
  const std::vector<std::pair<const char*, double>> values = {
      {"zb_orthonormality_max_error", r.zb_orthonormality_max_error},
      {"shannon_number", r.shannon_number},
      {"noise_gain", r.noise_gain},
      {"largest_singular_value", r.largest_singular_value},
      {"smallest_kept_singular_value", r.smallest_kept_singular_value},
      {"roundtrip_error_in_zone", r.roundtrip_error_in_zone},
      {"noisy_roundtrip_error_in_zone", r.noisy_roundtrip_error_in_zone}};
  for (const auto& [name, v] : values)
    Check(std::isfinite(v), std::string(name) + std::string(" is ") + FormatValue(v));
  if (r.has_outside) {
    Check(std::isfinite(r.roundtrip_error_outside_zone), "roundtrip_error_outside_zone is not finite");
    Check(std::isfinite(r.noisy_roundtrip_error_outside_zone),
          "noisy_roundtrip_error_outside_zone is not finite");
  }
  for (double v : r.gram_condition_per_m)
    Check(std::isfinite(v) && v >= 1, std::string("a Gram condition is ") + FormatValue(v));
  // The ZB is orthonormal by construction; the product rule integrates it exactly, so what is
  // left is rounding: 4e-14 at order 30 (docs/design.md section 3); 1e-10 leaves margin.
  // On a sliver of a zone the directions' cos(theta) = x carries an absolute rounding of eps,
  // i.e. eps / (b - a) in the virtual-sphere coordinate t, amplified by dZ/dt <= ~L^2:
  // 100 eps / (b - a) bounds it (1.5e-6 for 0-0.01 deg, measured 1.5e-7; negligible for zones
  // wider than a degree).
  const double width = zone.cos_upper() - zone.cos_lower();
  const double orthonormality_tol = 1e-10 + 100 * std::numeric_limits<double>::epsilon() / width;
  Check(r.zb_orthonormality_max_error < orthonormality_tol,
        std::string("ZB orthonormality error ") + FormatValue(r.zb_orthonormality_max_error) +
            " >= " + FormatValue(orthonormality_tol));
  // Truncation at tau bounds the noise gain: 1 / sigma_kept <= 1 / (tau sigma_max).
  if (c.tau > 0) {
    Check(r.noise_gain * c.tau * r.largest_singular_value <= 1 + 1e-12,
          std::string("noise gain ") + FormatValue(r.noise_gain) + " exceeds 1 / (tau sigma_max)");
  }
  Check(r.roundtrip_error_in_zone <= c.max_roundtrip_in_zone,
        std::string("round trip in zone ") + FormatValue(r.roundtrip_error_in_zone) +
            std::string(" > ") + FormatValue(c.max_roundtrip_in_zone));
  if (c.expect_truncation) {
    Check(r.truncated_components > 0, "nothing was truncated on an ill-conditioned zone");
    Check(!r.warnings.empty(), "no warning about the truncation / extrapolation");
  }
  return std::string("noise gain ") + FormatValue(r.noise_gain) + std::string(", truncated ") +
         std::to_string(r.truncated_components) + std::string(" of ") +
         std::to_string(r.target_size) + ", round trip in zone " +
         FormatValue(r.roundtrip_error_in_zone) +
         (r.has_outside ? std::string(", outside ") + FormatValue(r.roundtrip_error_outside_zone)
                        : "") +
         std::string(", ") + std::to_string(r.warnings.size()) + " warning(s)";
}

// ZonalToTarget applied to moments with a NaN: the conversion has no data check of its own (its
// callers validate, sh_conversion.h), so this case checks that ConvertToSh refuses such data.
std::string RunConvertNanMoments() {
  ZonalTensor t;
  const Zone zone = Zone::FromDegrees(10, 50);
  t.theta_min_rad = zone.theta_min_rad();
  t.theta_max_rad = zone.theta_max_rad();
  t.order = 2;
  const int n = ShCount(2);
  for (int ch = 0; ch < 3; ++ch) {
    t.z[ch] = Eigen::MatrixXd::Identity(n, n) * 0.1;
    t.variance[ch] = Eigen::MatrixXd::Constant(n, n, 1e-8);
  }
  t.z[1](2, 3) = kNaN;
  const ShConversionResult r = ConvertToSh(t, {});
  return std::string("converted data holding a NaN (noise gain ") +
         FormatValue(r.diagnostics.noise_gain) + ")";
}

// ---------------------------------------------------------------------------------------------
// hdr: a 16 x 16 mono camera with the thesis sensor's 12-bit range.

RigCalibration SmallCameraCalibration() {
  RigCalibration c;
  c.source = "stress: 16x16 mono";
  c.camera_width = c.camera_height = 16;
  c.layout = PixelLayout::kMono;
  c.gain_e_per_dn = 2.5;
  c.read_noise_e = 3;
  c.black_dn = 64;
  c.saturation_dn = 4095;
  return c;
}

std::vector<Frame> Bracket(uint16_t value) {
  std::vector<Frame> frames;
  for (double t_us : {1000.0, 4000.0, 16000.0}) {
    Frame f;
    f.width = f.height = 16;
    f.layout = PixelLayout::kMono;
    f.bit_depth = 12;
    f.data.assign(256, value);
    f.exposure_us = t_us;
    frames.push_back(std::move(f));
  }
  return frames;
}

void CheckHdrFinite(const HdrImage& hdr) {
  for (size_t p = 0; p < hdr.rate.size(); ++p) {
    Check(std::isfinite(hdr.rate[p]) && std::isfinite(hdr.variance[p]) && hdr.variance[p] >= 0,
          std::string("pixel ") + std::to_string(p) + std::string(": rate ") +
              FormatValue(hdr.rate[p]) + ", variance " + FormatValue(hdr.variance[p]));
  }
}

std::string RunHdrAllBlack() {
  // Every sample at 0 DN, below the black level (64 DN): dark frames with a negative offset.
  const RigCalibration c = SmallCameraCalibration();
  const HdrImage hdr = MergeExposures(Bracket(0), c, "stress all-black bracket");
  CheckHdrFinite(hdr);
  Check(hdr.saturated_pixels == 0, "black pixels marked saturated");
  // The weighted mean of (0 - black) g / t over the exposures: negative, between the longest
  // exposure's -64 * 2.5 / 0.016 = -1e4 e-/s and the shortest's -1.6e5 e-/s.
  const double rate = hdr.rate[0];
  Check(rate <= -1e4 * (1 - 1e-5) && rate >= -1.6e5 * (1 + 1e-5),
        std::string("rate ") + FormatValue(rate) + " outside [-1.6e5, -1e4] e-/s");
  return std::string("256 valid pixels, rate ") + FormatValue(rate) +
         " e-/s (black offset), finite variances";
}

std::string RunHdrAllSaturated() {
  const RigCalibration c = SmallCameraCalibration();
  const HdrImage hdr = MergeExposures(Bracket(4095), c, "stress all-saturated bracket");
  CheckHdrFinite(hdr);
  Check(hdr.saturated_pixels == 256, std::string("saturated pixels ") + std::to_string(hdr.saturated_pixels) + " != 256");
  for (size_t p = 0; p < hdr.rate.size(); ++p) {
    Check(!hdr.valid[p] && hdr.rate[p] == 0 && hdr.variance[p] == 0, "a saturated pixel holds a value");
  }
  return "256 pixels marked invalid (rate, variance = 0), none NaN";
}

std::string RunHdrMismatchedSize() {
  std::vector<Frame> frames = Bracket(1000);
  frames[1].width = 8;
  frames[1].data.resize(128);
  MergeExposures(frames, SmallCameraCalibration(), "stress mismatched bracket");
  return "merged frames of different sizes";
}

std::string RunHdrOutOfRange() {
  std::vector<Frame> frames = Bracket(1000);
  frames[2].data[17] = 5000;  // above 4095
  MergeExposures(frames, SmallCameraCalibration(), "stress out-of-range bracket");
  return "merged a 12-bit frame holding 5000";
}

std::string RunHdrBadExposure() {
  std::vector<Frame> frames = Bracket(1000);
  frames[0].exposure_us = kInf;
  MergeExposures(frames, SmallCameraCalibration(), "stress bracket with an infinite exposure");
  return "merged a frame with an infinite exposure time";
}

// ---------------------------------------------------------------------------------------------
// zonal: zonal.exr with a non-finite value, written through the library (which must refuse)
// or damaged on disk (which the reader must refuse).

ZonalData SmallZonalData() {
  ZonalData d;
  const Zone zone = Zone::FromDegrees(10, 50);
  d.theta_min_rad = zone.theta_min_rad();
  d.theta_max_rad = zone.theta_max_rad();
  d.order = 2;
  d.grid = MakeExitantGrid(zone, 2.0, 4.0);
  const int cells = d.grid.cells();
  d.functions.resize(ShCount(2));
  for (size_t k = 0; k < d.functions.size(); ++k) {
    GridImage& f = d.functions[k];
    for (int ch = 0; ch < 3; ++ch) {
      f.value[ch].resize(cells);
      for (int c = 0; c < cells; ++c) f.value[ch][c] = static_cast<float>(0.1 / (1 + k) + 1e-3 * (c % 7));
      f.variance[ch].assign(cells, 1e-8f);
      f.weight[ch].assign(cells, 1e-3f);
    }
    f.filled.assign(cells, 0);
  }
  ProjectExitant(&d);
  return d;
}

// Copies an EXR file of scanline parts, replacing value `index` of `channel` in part `part`.
void CopyExrWithValue(const std::string& from, const std::string& to, const std::string& part,
                      const std::string& channel, size_t index, float value) {
  Imf::MultiPartInputFile in(from.c_str());
  std::vector<Imf::Header> headers;
  for (int i = 0; i < in.parts(); ++i) headers.push_back(in.header(i));
  Imf::StdOSStream stream;  // encoded in memory, written through basis/atomic_file.h
  {
    Imf::MultiPartOutputFile out(stream, headers.data(), static_cast<int>(headers.size()));
    for (int i = 0; i < in.parts(); ++i) {
      const Imath::Box2i w = headers[i].dataWindow();
      const int width = w.max.x - w.min.x + 1, height = w.max.y - w.min.y + 1;
      std::vector<std::vector<float>> storage;
      storage.reserve(256);
      Imf::FrameBuffer fb;
      std::vector<std::string> names;
      for (auto c = headers[i].channels().begin(); c != headers[i].channels().end(); ++c) {
        storage.emplace_back(static_cast<size_t>(width) * height);
        names.push_back(c.name());
        char* base = reinterpret_cast<char*>(storage.back().data()) -
                     (static_cast<ptrdiff_t>(w.min.y) * width + w.min.x) * sizeof(float);
        fb.insert(c.name(), Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * width));
      }
      Imf::InputPart ip(in, i);
      ip.setFrameBuffer(fb);
      ip.readPixels(w.min.y, w.max.y);
      if (headers[i].hasName() && headers[i].name() == part) {
        const auto it = std::find(names.begin(), names.end(), channel);
        Check(it != names.end(), "no channel " + channel + " in part " + part);
        storage[it - names.begin()].at(index) = value;
      }
      Imf::OutputPart op(out, i);
      op.setFrameBuffer(fb);
      op.writePixels(height);
    }
  }
  WriteFileAtomically(to, stream.str());
}

std::string RunZonalWriteNan(const std::string& dir) {
  ZonalData d = SmallZonalData();
  d.tensor[1](3, 2) = kNaN;
  WriteZonalExr(SessionPath(dir, kZonalFile), d);
  return "wrote zonal data holding a NaN";
}

std::string RunZonalWriteOverflow(const std::string& dir) {
  // 1e39 is finite in double but Inf once stored in float.
  ZonalData d = SmallZonalData();
  d.functions[4].value[0][10] = std::numeric_limits<float>::max();
  d.tensor[0](0, 0) = 1e39;
  WriteZonalExr(SessionPath(dir, kZonalFile), d);
  return "wrote zonal data beyond float range";
}

std::string RunZonalRead(const std::string& dir, const std::string& part, const std::string& channel,
                         float value) {
  const std::string good = dir + "/good.exr", bad = SessionPath(dir, kZonalFile);
  WriteZonalExr(good, SmallZonalData());
  ReadZonalExr(good);  // the undamaged file reads
  CopyExrWithValue(good, bad, part, channel, 5, value);
  ReadZonalExr(bad);
  return std::string("read back a zonal.exr holding ") + FormatValue(value) + " in " + part + "/" +
         channel;
}

std::string CheckOutputsFinite(const std::string& dir) {
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.path().extension() != ".exr") continue;
    const int64_t bad = CountNonFiniteExr(entry.path().string());
    Check(bad == 0, entry.path().filename().string() + std::string(" holds ") + std::to_string(bad) + " NaN/Inf values");
    ++files;
  }
  return std::to_string(files) + " EXR files finite";
}

// The SH conversion at order 30 of a narrow zone's noisy data: the automatic tau must truncate
// most singular directions (their noise gain reaches 1e13) and everything written stays finite.
std::string RunConvertOrder30Narrow(const std::string& dir, uint64_t seed) {
  ZonalTensor t;
  const Zone zone = Zone::FromDegrees(40, 45);
  t.theta_min_rad = zone.theta_min_rad();
  t.theta_max_rad = zone.theta_max_rad();
  t.order = 30;
  const int n = ShCount(30);
  // A smooth diagonal-heavy tensor with 1e-3 relative white noise (fixed seed).
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int ch = 0; ch < 3; ++ch) {
    t.z[ch].resize(n, n);
    for (int k = 0; k < n; ++k) {
      for (int j = 0; j < n; ++j) {
        const double noise = 1e-3 * uniform(rng);
        t.z[ch](k, j) = (k == j ? 0.5 / (1 + k) : 0.0) + noise * 0.5;
      }
    }
    t.variance[ch] = Eigen::MatrixXd::Constant(n, n, (0.5e-3 * 0.5e-3) / 3);
  }
  // Coarse exitant tables: the conversion is what is stressed, and 90 x 90 tables of 961
  // functions take half a minute to fill.
  ShConversionOptions options;
  options.exitant_theta = options.exitant_phi = 10;
  const ShConversionResult r = ConvertToSh(t, options);
  Check(CountNonFiniteJson(r.ToJson()) == 0, "the conversion report holds NaN/Inf");
  Check(r.kept_directions < r.singular_directions, "the automatic tau truncated nothing");
  Check(!r.warnings.empty(), "no warning about the narrow zone's extrapolation");
  // tau is never below 1e-4 (sh_conversion.h), so the noise gain is at most 1e4 / sigma_1.
  Check(r.tau >= 1e-4, "automatic tau " + FormatValue(r.tau) + " < 1e-4");
  WriteShFile(dir + "/sh-sh.exr", r.data);
  const int64_t bad = CountNonFiniteExr(dir + "/sh-sh.exr");
  Check(bad == 0, "sh-sh.exr holds " + std::to_string(bad) + " NaN/Inf values");
  return "tau " + FormatValue(r.tau) + ", " + std::to_string(r.kept_directions) + " of " +
         std::to_string(r.singular_directions) + " directions kept, noise gain " +
         FormatValue(r.diagnostics.noise_gain) + ", " + std::to_string(r.warnings.size()) +
         " warning(s); sh-sh.exr finite";
}

// A session whose zonal data are all zero, variances included (a black sample with a perfect
// sensor): convert and fit it; the truth lambert:0 makes every relative error 0 / 0.
std::string RunAllZeroSession(const std::string& dir) {
  const std::string session = dir + "/session";
  fs::create_directories(session);
  ZonalData d = SmallZonalData();
  for (GridImage& f : d.functions) {
    for (int ch = 0; ch < 3; ++ch) {
      std::fill(f.value[ch].begin(), f.value[ch].end(), 0.0f);
      std::fill(f.variance[ch].begin(), f.variance[ch].end(), 0.0f);
    }
  }
  for (int ch = 0; ch < 3; ++ch) {
    d.tensor[ch].setZero();
    d.tensor_variance[ch].setZero();
  }
  SessionFolder::Create(session, {{"material", "lambert:0"},
                                  {"kind", "simulated"},
                                  {"rig", {{"name", "stress"}}},
                                  {"seed", 1},
                                  {"calibration", "nominal"}});
  WriteZonalExr(SessionPath(session, kZonalFile), d);
  const ZonalTensor data = ToZonalTensor(ReadZonalExr(SessionPath(session, kZonalFile)));
  std::string detail;
  try {
    const ShConversionResult sh = ConvertToSh(data, {});
    Check(CountNonFiniteJson(sh.ToJson()) == 0, "the conversion report holds NaN/Inf");
    WriteShFile(session + "/sh-sh.exr", sh.data);
    detail = "convert: tau " + FormatValue(sh.tau);
  } catch (const Error& e) {
    if (dynamic_cast<const InternalError*>(&e)) throw;
    detail = std::string("convert refused: ") + e.what();
  }
  for (const std::string model : {"dbrdf", "ggx"}) {
    FitSessionOptions fit;
    fit.model = model;
    const FitSessionOutcome f = FitSession(session, fit);
    Check(CountNonFiniteJson(f.report) == 0, "the " + model + " fit report holds NaN/Inf");
    detail += "; " + model + " fitted";
  }
  return detail + "; " + CheckOutputsFinite(session);
}

// ---------------------------------------------------------------------------------------------
// capture: a simulated session of an extreme material, then convert and fit.

struct CaptureCase {
  std::string material;
  double shortest_exposure_us = 0;  // 0: metered
  bool fit_ggx = true;
  bool write_hdr_images = false;  // hdr/*.exr too (checked for NaN like the other outputs)
};

std::string RunStressCapture(const CaptureCase& c, const StressOptions& options,
                             const std::string& dir) {
  VirtualCaptureArgs args;
  const std::string rig_path =
      options.rig_path.empty() ? DataPath("rig/rigs/thesis.yaml") : options.rig_path;
  Rig rig = ApplyPreset(LoadRig(rig_path), Preset::kFast);
  // What is stressed is the numbers' range, not the picture's noise: a few samples per pixel
  // (the fast preset has 1024) keep each capture to a few seconds.
  if (options.samples_per_pixel > 0) rig.simulation.samples_per_pixel = options.samples_per_pixel;
  args.rig = rig;
  args.preset_name = "fast";
  args.material_spec = c.material;
  args.seed = options.seed;
  args.job.out_dir = dir + "/session";
  args.job.order = 2;
  args.job.exposures = 2;
  args.job.shortest_exposure_us = c.shortest_exposure_us;
  args.job.processing.write_hdr_images = c.write_hdr_images;
  const auto start = std::chrono::steady_clock::now();
  const auto seconds = [&start] {
    return FormatValue(
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()) +
           " s";
  };
  const VirtualCaptureOutcome outcome = RunVirtualCapture(args);
  Check(outcome.result.complete, "the capture did not complete");
  const std::string session = args.job.out_dir;
  std::string detail = "captured at " + seconds() + ", saturated pixel-lobes " +
                       std::to_string(outcome.result.processing.saturated_pixels);

  // The SH conversion (automatic tau), written like `zbrdf convert` does.
  const ZonalData zonal = ReadZonalExr(SessionPath(session, kZonalFile));
  const ZonalTensor data = ToZonalTensor(zonal);
  double max_abs = 0;
  for (int ch = 0; ch < 3; ++ch) max_abs = std::max(max_abs, data.z[ch].cwiseAbs().maxCoeff());
  detail += std::string(", max |z| ") + FormatValue(max_abs);
  const ShConversionResult sh = ConvertToSh(data, {});
  Check(CountNonFiniteJson(sh.ToJson()) == 0, "the conversion report holds NaN/Inf");
  WriteShFile(session + "/sh-sh.exr", sh.data);
  detail += std::string("; convert: tau ") + FormatValue(sh.tau) + std::string(", ") +
            std::to_string(sh.kept_directions) + "/" + std::to_string(sh.singular_directions) +
            " kept";

  // The fits; a refusal with a clear error is an acceptable answer for data that carry no
  // signal, and is reported as the case's outcome.
  // Shared by the capture cases (same zone and order): the fitters' precomputation is most of a
  // fit's time.
  static FitContext context;
  for (const std::string model : {"dbrdf", "ggx"}) {
    if (model == "ggx" && !c.fit_ggx) continue;
    FitSessionOptions fit;
    fit.model = model;
    const FitSessionOutcome f = FitSession(session, fit, &context);
    Check(CountNonFiniteJson(f.report) == 0, "the " + model + " fit report holds NaN/Inf");
    detail += "; " + model + " fitted at " + seconds();
  }
  return detail + "; " + CheckOutputsFinite(session);
}

// ---------------------------------------------------------------------------------------------

std::vector<StressCase> MakeCases() {
  std::vector<StressCase> cases;
  const auto basis = [&](const std::string& name, const std::string& what, const BasisCase& c) {
    cases.push_back(
        {name, "basis", what,
         "finite report; ZB orthonormality < 1e-10 + 100 eps/(b-a); round trip in zone <= " +
             FormatValue(c.max_roundtrip_in_zone) + "; noise gain <= 1/(tau sigma_max)" +
             (c.expect_truncation ? "; truncates and warns" : ""),
         StressExpect::kSuccess,
         [c](const StressOptions&, const std::string&) { return RunBasisCase(c); }});
  };
  basis("basis-order30-narrow", "zone 40-45 deg, order 30, all SH: cond(Gram) far beyond 1/eps",
        {40, 45, 30, TargetKind::kSh, kDefaultTau, 1e-8, true});
  basis("basis-order30-pole", "zone 0-30 deg (touches the pole), order 30, all SH",
        {0, 30, 30, TargetKind::kSh, kDefaultTau, 1e-8, true});
  basis("basis-order30-horizon", "zone 60-90 deg (touches the horizon), order 30, SH l+m even",
        {60, 90, 30, TargetKind::kShEven, kDefaultTau, 1e-8, true});
  basis("basis-order30-hemisphere", "zone 0-90 deg, order 30, HSH (the ZB is the HSH basis)",
        {0, 90, 30, TargetKind::kHsh, kDefaultTau, 1e-12, false});
  basis("basis-order30-tau0", "zone 40-45 deg, order 30, all SH, tau = 0 (no truncation)",
        {40, 45, 30, TargetKind::kSh, 0.0, 1e-8, false});
  basis("basis-sliver", "zone 0-0.01 deg (b - a = 1.5e-8), order 10, all SH",
        {0, 0.01, 10, TargetKind::kSh, kDefaultTau, 1e-6, true});
  cases.push_back({"basis-empty-zone", "basis", "zone 45-45 deg (no width)",
                   "InputError naming the zone", StressExpect::kInputError,
                   [](const StressOptions&, const std::string&) {
                     ZonalBasis zb(Zone::FromDegrees(45, 45), 4);
                     return std::string("made a basis on an empty zone");
                   }});
  cases.push_back({"basis-tau-nan", "basis", "conversion with tau = NaN",
                   "InputError naming tau", StressExpect::kInputError,
                   [](const StressOptions&, const std::string&) {
                     const ZonalBasis zb(Zone::FromDegrees(10, 50), 4);
                     ZonalToTarget conversion(zb, TargetBasis(TargetKind::kSh, 4), kNaN);
                     return std::string("accepted tau = NaN");
                   }});
  cases.push_back({"basis-convert-nan", "basis", "SH conversion of a zonal tensor holding a NaN",
                   "NumericalError or InputError naming the entry", StressExpect::kSuccessOrError,
                   [](const StressOptions&, const std::string&) -> std::string {
                     RunConvertNanMoments();
                     throw StressCheckFailed("ConvertToSh accepted a NaN coefficient");
                   }});

  cases.push_back({"convert-order30-narrow", "basis",
                   "zbrdf convert of noisy order-30 data on zone 40-45 deg (automatic tau)",
                   "truncates (tau >= 1e-4), warns; report and sh-sh.exr finite",
                   StressExpect::kSuccess, [](const StressOptions& o, const std::string& dir) {
                     return RunConvertOrder30Narrow(dir, o.seed);
                   }});

  cases.push_back({"hdr-all-black", "hdr", "3 exposures, every sample 0 DN (below the black level)",
                   "all pixels valid and finite; rate within the exposures' black offsets "
                   "[-1.6e5, -1e4] e-/s",
                   StressExpect::kSuccess,
                   [](const StressOptions&, const std::string&) { return RunHdrAllBlack(); }});
  cases.push_back({"hdr-all-saturated", "hdr", "3 exposures, every sample at 4095 DN",
                   "every pixel invalid with rate = variance = 0 (no NaN)", StressExpect::kSuccess,
                   [](const StressOptions&, const std::string&) { return RunHdrAllSaturated(); }});
  cases.push_back({"hdr-mismatched-size", "hdr", "a bracket with one 8x16 frame among 16x16",
                   "InputError naming the frame sizes", StressExpect::kInputError,
                   [](const StressOptions&, const std::string&) { return RunHdrMismatchedSize(); }});
  cases.push_back({"hdr-out-of-range", "hdr", "a 12-bit frame holding 5000",
                   "InputError naming the bit depth", StressExpect::kInputError,
                   [](const StressOptions&, const std::string&) { return RunHdrOutOfRange(); }});
  cases.push_back({"hdr-infinite-exposure", "hdr", "a frame with exposure time Inf",
                   "InputError naming the exposure", StressExpect::kInputError,
                   [](const StressOptions&, const std::string&) { return RunHdrBadExposure(); }});

  cases.push_back({"zonal-write-nan", "zonal", "WriteZonalExr of a tensor holding a NaN",
                   "NumericalError naming the entry; no file written", StressExpect::kNumericalError,
                   [](const StressOptions&, const std::string& dir) -> std::string {
                     try {
                       return RunZonalWriteNan(dir);
                     } catch (const NumericalError&) {
                       Check(!fs::exists(SessionPath(dir, kZonalFile)), "a file was written anyway");
                       throw;
                     }
                   }});
  cases.push_back({"zonal-write-overflow", "zonal",
                   "WriteZonalExr of values beyond float range (1e39)",
                   "NumericalError naming the entry", StressExpect::kNumericalError,
                   [](const StressOptions&, const std::string& dir) { return RunZonalWriteOverflow(dir); }});
  cases.push_back({"zonal-read-nan-grid", "zonal", "zonal.exr with a NaN grid value read back",
                   "InputError naming the file and the channel", StressExpect::kInputError,
                   [](const StressOptions&, const std::string& dir) {
                     return RunZonalRead(dir, "grid", "Z1_0.G", std::numeric_limits<float>::quiet_NaN());
                   }});
  cases.push_back({"zonal-read-inf-tensor", "zonal", "zonal.exr with +Inf in the tensor read back",
                   "InputError naming the file and the entry", StressExpect::kInputError,
                   [](const StressOptions&, const std::string& dir) {
                     return RunZonalRead(dir, "tensor", "z.R", std::numeric_limits<float>::infinity());
                   }});
  cases.push_back({"zonal-read-nan-variance", "zonal",
                   "zonal.exr with a NaN tensor variance read back",
                   "InputError naming the file and the entry", StressExpect::kInputError,
                   [](const StressOptions&, const std::string& dir) {
                     return RunZonalRead(dir, "tensor", "var.B", std::numeric_limits<float>::quiet_NaN());
                   }});
  cases.push_back({"zonal-read-negative-variance", "zonal",
                   "zonal.exr with a negative grid variance read back",
                   "InputError naming the file and the entry", StressExpect::kInputError,
                   [](const StressOptions&, const std::string& dir) {
                     return RunZonalRead(dir, "grid", "Z2_-1.var.R", -1.0f);
                   }});

  cases.push_back({"zonal-all-zero-fit", "zonal",
                   "a session of all-zero coefficients and variances (truth lambert:0): convert, "
                   "D-BRDF and GGX fits",
                   "outputs and reports finite (0/0 errors reported as null), or a clear error",
                   StressExpect::kSuccessOrError,
                   [](const StressOptions&, const std::string& dir) { return RunAllZeroSession(dir); }});

  const std::string capture_tolerance =
      "capture, convert, D-BRDF and GGX fits complete; every EXR output and JSON report finite";
  const std::string dbrdf_tolerance =
      "capture, convert and D-BRDF fit complete; every EXR output and JSON report finite";
  const auto capture = [&](const std::string& name, const std::string& what, const CaptureCase& c,
                           StressExpect expect, const std::string& tolerance) {
    cases.push_back({name, "capture", what, tolerance, expect,
                     [c](const StressOptions& o, const std::string& dir) {
                       return RunStressCapture(c, o, dir);
                     }});
  };
  // GGX fits take seconds each: they run where the model is most strained (a mirror: alpha -> 0)
  // and where they are cheap (diffuse); the D-BRDF fit runs everywhere.
  capture("capture-chrome", "merl:chrome (sharp specular peak, ~500/sr), order 2",
          {"merl:chrome", 0, false}, StressExpect::kSuccess, dbrdf_tolerance);
  capture("capture-mirror", "mirror:0.9 (a delta: f_r is a distribution), order 2",
          {"mirror:0.9"}, StressExpect::kSuccess, capture_tolerance);
  capture("capture-diffuse", "lambert:0.95 (pure diffuse, bright), order 2", {"lambert:0.95"},
          StressExpect::kSuccess, capture_tolerance);
  capture("capture-retro", "retro:kd=0.05,kr=0.8,n=30 (light returns toward its source), order 2",
          {"retro:kd=0.05,kr=0.8,n=30", 0, false}, StressExpect::kSuccess, dbrdf_tolerance);
  capture("capture-black-metered", "lambert:0 with metered exposure", {"lambert:0"},
          StressExpect::kDeviceError, "DeviceError: metering finds no exposure (check the lens cap)");
  capture("capture-black-fixed", "lambert:0 at a fixed 20 ms exposure (frames of pure noise), HDR images written",
          {"lambert:0", 20000, false, true}, StressExpect::kSuccessOrError,
          "D-BRDF fit: outputs finite, or a clear error saying the data carry no signal");
  capture("capture-all-saturated",
          "lambert:0.95 at a fixed 2 s exposure: every pixel of every frame saturated, HDR images written",
          {"lambert:0.95", 2e6, false, true}, StressExpect::kSuccessOrError,
          "a clear error saying the frames are saturated, or outputs finite");
  return cases;
}

std::string ErrorKind(const std::exception& e) {
  if (dynamic_cast<const InputError*>(&e)) return "input";
  if (dynamic_cast<const DeviceError*>(&e)) return "device";
  if (dynamic_cast<const NumericalError*>(&e)) return "numerical";
  if (dynamic_cast<const InternalError*>(&e)) return "internal";
  return "other";
}

bool ErrorExpected(StressExpect expect, const std::string& kind) {
  switch (expect) {
    case StressExpect::kSuccess: return false;
    case StressExpect::kInputError: return kind == "input";
    case StressExpect::kDeviceError: return kind == "device";
    case StressExpect::kNumericalError: return kind == "numerical";
    case StressExpect::kSuccessOrError: return kind == "input" || kind == "device" || kind == "numerical";
  }
  return false;
}

}  // namespace

std::string StressOutcomeName(StressOutcome outcome) {
  switch (outcome) {
    case StressOutcome::kPass: return "pass";
    case StressOutcome::kExpectedError: return "expected-error";
    case StressOutcome::kFail: return "FAIL";
  }
  return "FAIL";
}

nlohmann::json StressResult::ToJson() const {
  return {{"name", name},   {"group", group},     {"what", what},
          {"tolerance", tolerance}, {"outcome", StressOutcomeName(outcome)},
          {"error_kind", error_kind.empty() ? nlohmann::json(nullptr) : nlohmann::json(error_kind)},
          {"detail", detail}, {"seconds", seconds}};
}

const std::vector<StressCase>& StressCases() {
  static const std::vector<StressCase> cases = MakeCases();
  return cases;
}

const StressCase& FindStressCase(const std::string& name) {
  std::string names;
  for (const StressCase& c : StressCases()) {
    if (c.name == name) return c;
    names += (names.empty() ? "" : ", ") + c.name;
  }
  throw InputError("no stress case named '" + name + "'; the cases are: " + names +
                   " (zbrdf stress --list)");
}

void StressOptions::Validate() const {
  OptionChecker("StressOptions")
      .InRange("samples_per_pixel", samples_per_pixel, 0, 65536)
      .ThrowIfInvalid();
}

StressResult RunStressCase(const StressCase& c, const StressOptions& options) {
  options.Validate();
  StressResult r;
  r.name = c.name;
  r.group = c.group;
  r.what = c.what;
  r.tolerance = c.tolerance;
  const std::string dir = (options.work_dir.empty() ? fs::temp_directory_path().string() + "/zbrdf-stress"
                                                    : options.work_dir) + "/" + c.name;
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir, ec);
  if (ec) throw InputError("cannot make the stress work folder " + dir + ": " + ec.message());
  const auto start = std::chrono::steady_clock::now();
  try {
    r.detail = c.run(options, dir);
    if (c.expect == StressExpect::kSuccess || c.expect == StressExpect::kSuccessOrError) {
      r.outcome = StressOutcome::kPass;
    } else {
      r.outcome = StressOutcome::kFail;
      r.detail = "expected an error, but it succeeded: " + r.detail;
    }
  } catch (const StressCheckFailed& e) {
    r.outcome = StressOutcome::kFail;
    r.detail = e.what();
  } catch (const std::exception& e) {
    r.error_kind = ErrorKind(e);
    r.detail = e.what();
    // A clear error names the thing and what to do: more than a few words.
    const bool clear = r.detail.size() >= 20;
    if (ErrorExpected(c.expect, r.error_kind) && clear) {
      r.outcome = StressOutcome::kExpectedError;
    } else {
      r.outcome = StressOutcome::kFail;
      r.detail = (clear ? "unexpected " : "unclear ") + r.error_kind + " error: " + r.detail;
    }
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

std::vector<StressResult> RunStressCases(const std::vector<const StressCase*>& cases,
                                         const StressOptions& options,
                                         const ProgressCallback& progress) {
  std::vector<StressResult> results;
  for (size_t i = 0; i < cases.size(); ++i) {
    Report(progress, {"stress " + cases[i]->name, static_cast<long>(i), static_cast<long>(cases.size()), "cases"});
    results.push_back(RunStressCase(*cases[i], options));
  }
  Report(progress, {"stress", static_cast<long>(cases.size()), static_cast<long>(cases.size()), "cases"});
  return results;
}

int64_t CountNonFiniteExr(const std::string& path) {
  int64_t bad = 0;
  try {
    Imf::MultiPartInputFile file(path.c_str());
    for (int i = 0; i < file.parts(); ++i) {
      const Imf::Header& h = file.header(i);
      const Imath::Box2i w = h.dataWindow();
      const int width = w.max.x - w.min.x + 1;
      int channels = 0;
      for (auto c = h.channels().begin(); c != h.channels().end(); ++c) ++channels;
      // Every channel at once (a part decompresses whole scanline blocks), a band of rows at a
      // time so that memory stays at ~64 MB for the widest files (SH exitant tables).
      const int rows = std::max(1, std::min(w.max.y - w.min.y + 1,
                                            static_cast<int>((16 << 20) / (static_cast<int64_t>(width) *
                                                                           std::max(1, channels)))));
      std::vector<float> values(static_cast<size_t>(width) * rows * std::max(1, channels));
      Imf::InputPart part(file, i);
      for (int y0 = w.min.y; y0 <= w.max.y; y0 += rows) {
        const int y1 = std::min(w.max.y, y0 + rows - 1);
        Imf::FrameBuffer fb;
        int index = 0;
        for (auto c = h.channels().begin(); c != h.channels().end(); ++c, ++index) {
          float* band = values.data() + static_cast<size_t>(index) * width * rows;
          char* base = reinterpret_cast<char*>(band) -
                       (static_cast<ptrdiff_t>(y0) * width + w.min.x) * sizeof(float);
          fb.insert(c.name(), Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * width));
        }
        part.setFrameBuffer(fb);
        part.readPixels(y0, y1);
        const size_t used = static_cast<size_t>(width) * (y1 - y0 + 1);
        for (int c = 0; c < channels; ++c) {
          const float* band = values.data() + static_cast<size_t>(c) * width * rows;
          for (size_t k = 0; k < used; ++k) bad += !std::isfinite(band[k]);
        }
      }
    }
  } catch (const std::exception& e) {
    throw InputError("cannot read " + path + " to check its values: " + e.what());
  }
  return bad;
}

int64_t CountNonFiniteJson(const nlohmann::json& value) {
  if (value.is_number_float()) return std::isfinite(value.get<double>()) ? 0 : 1;
  int64_t bad = 0;
  if (value.is_structured()) {
    for (const auto& item : value) bad += CountNonFiniteJson(item);
  }
  return bad;
}

}  // namespace zbrdf
