#include "tools/bench_run.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <set>

#include "acquisition/capture_job.h"
#include "acquisition/ground_truth.h"
#include "acquisition/session.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "basis/spherical_harmonics.h"
#include "basis/stopwatch.h"
#include "brdf/material_spec.h"
#include "brdf/sh_brdf.h"
#include "calibration/calibration_data.h"
#include "fitting/fit_error.h"
#include "pictures/material_ball.h"
#include "rig/direction_maps.h"
#include "simulate/virtual_rig.h"
#include "tools/fit_all.h"
#include "tools/fit_session.h"
#include "tools/json_file.h"
#include "tools/sh_conversion.h"

namespace zbrdf {
namespace {

namespace fs = std::filesystem;
nlohmann::json JsonOrNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

// In-zone relative L2 of z_k up to `order` over the truth's cells; functions the capture did not
// take (an adaptive capture's dropped bands) count as zero.
double PaddedCoefficientError(const ZonalData& measured, const GroundTruth& truth, int order) {
  const ExitantGrid& grid = measured.grid;
  double err = 0, norm = 0;
  const size_t n = std::min(truth.value.size(), static_cast<size_t>(ShCount(order)));
  for (size_t k = 0; k < n; ++k) {
    const bool have = k < measured.functions.size() &&
                      measured.functions[k].value[0].size() == static_cast<size_t>(grid.cells());
    for (size_t ci = 0; ci < truth.cells.size(); ++ci) {
      const int cell = truth.cells[ci];
      const double omega = grid.CellSolidAngle(cell / grid.n_phi);
      for (int ch = 0; ch < 3; ++ch) {
        const double t = truth.value[k][ch][ci];
        const double d = (have ? measured.functions[k].value[ch][cell] : 0.0) - t;
        err += omega * d * d;
        norm += omega * t * t;
      }
    }
  }
  return norm > 0 ? std::sqrt(err / norm) : 0.0;
}

BallOptions BenchBall(int size) {
  BallOptions o;
  o.size = size;
  o.spp = 4;  // antialiasing only: a directional light needs no sampling
  o.light_direction = Normalize(Vec3(0.35, 0.55, 0.76));
  o.seed = 7;
  return o;
}

// One material on its own virtual rig: every strategy, in order.
class MaterialBench {
 public:
  MaterialBench(const Rig& rig, const BenchOptions& options, const std::string& spec,
                FitContext* fits)
      : rig_(rig), options_(options), fits_(fits) {
    material_ = MakeBrdf(spec);
    VirtualRig::Options vr;
    vr.seed = options.seed;
    vr.noise = true;
    virtual_rig_ = std::make_unique<VirtualRig>(rig, material_, vr);
    calibration_ = LoadRigCalibration(rig, "", DefaultCacheDir());
  }

  const Brdf& material() const { return *material_; }

  // Captures and processes one strategy into `dir` (replaced if it exists).
  CaptureJobResult Capture(const BenchStrategy& s, const AdaptiveOptions& adaptive,
                           const std::string& dir, double* capture_time_s) {
    fs::remove_all(dir);
    fs::create_directories(fs::path(dir).parent_path());
    CaptureJobOptions job;
    job.out_dir = dir;
    job.order = s.order;
    job.exposures = s.exposures;
    job.processing.write_hdr_images = false;
    job.interrupt = options_.interrupt;
    job.adaptive = adaptive;
    job.adaptive.enabled = s.adaptive;
    job.session_extra = {{"material", material_->Spec()}, {"seed", options_.seed},
                         {"preset", options_.preset},     {"noise", true},
                         {"kind", "simulated"},           {"bench_strategy", s.name}};
    VirtualRig& vr = *virtual_rig_;
    const int64_t start_us = vr.clock().NowUs();
    CaptureJobResult result =
        RunCaptureJob(rig_, calibration_, vr.camera(), vr.projector(), vr.clock(), job);
    *capture_time_s = (vr.clock().NowUs() - start_us) * 1e-6;
    if (!options_.keep_frames) fs::remove_all(SessionPath(dir, kFramesFolder));
    return result;
  }

  nlohmann::json Run(const BenchStrategy& s, const std::string& dir, int truth_order) {
    const auto wall_start = WallClock::now();
    double capture_time_s = 0;
    const CaptureJobResult result = Capture(s, options_.adaptive_options, dir, &capture_time_s);
    nlohmann::json row = {{"material", material_->Spec()},
                          {"strategy", s.name},
                          {"adaptive", s.adaptive},
                          {"order", s.order}};
    if (!result.complete) {
      row["interrupted"] = true;
      return row;
    }
    const ZonalData& zonal = result.zonal;
    row["order_captured"] = zonal.order;
    row["exposures"] = result.plan.exposures_us.size();
    const int frames = result.capture.frames_captured + result.capture.frames_reused;
    const int per_lobe = static_cast<int>(result.plan.exposures_us.size()) * result.plan.repeats;
    row["patterns"] = per_lobe > 0 ? frames / per_lobe : 0;
    row["frames"] = frames;
    row["capture_time_s"] = capture_time_s;
    row["processing_s"] = result.processing.hdr_seconds + result.processing.zonal_seconds;
    row["saturated_pixel_lobes"] = result.processing.saturated_pixels;
    if (!result.adaptive.is_null()) {
      row["adaptive_reason"] = result.adaptive.value("reason", std::string());
      row["adaptive_predicted_error"] = result.adaptive.value("predicted_error", 0.0);
      row["adaptive_isotropic"] = result.adaptive.value("isotropic", false);
      row["adaptive_bands"] = result.adaptive["bands"];
      row["adaptive_skipped_lobes"] =
          result.adaptive.value("skipped_lobes", nlohmann::json::array()).size();
    }
    // Ground truth once per material, at the largest order of the bench, on the shared grid.
    {
      std::lock_guard<std::mutex> lock(truth_mutex_);
      if (truth_.value.empty()) {
        ZonalData layout;
        layout.theta_min_rad = zonal.theta_min_rad;
        layout.theta_max_rad = zonal.theta_max_rad;
        layout.grid = zonal.grid;
        layout.order = truth_order;
        GroundTruthOptions truth_options;
        truth_options.samples = options_.truth_samples;
        truth_ = TrueZonalCoefficientsCached(*material_, layout, truth_options,
                                             DefaultCacheDir() + "/truth");
      }
    }
    row["coefficient_error"] = JsonOrNull(PaddedCoefficientError(zonal, truth_, s.order));
    // Against the truth up to the bench's largest order: comparable across strategies (a low
    // order is charged for the bands it leaves out).
    row["coefficient_error_common"] =
        JsonOrNull(PaddedCoefficientError(zonal, truth_, truth_order));
    // SH conversion and its errors.
    const ZonalTensor tensor = ToZonalTensor(zonal);
    auto t = WallClock::now();
    const ShConversionResult sh = ConvertToSh(tensor, ShConversionOptions());
    row["sh_s"] = SecondsSince(t);
    if (!material_->IsDelta()) {
      const ShBrdf sh_brdf(sh.data);
      const CosineWeightedFn sh_fn = [&sh_brdf](const Vec3& w_o, std::span<const Vec3> w_i,
                                                std::span<Rgb> out) {
        sh_brdf.CosineWeightedBatch(w_o, w_i, out);
      };
      const BrdfComparison c = CompareBrdfs(sh_fn, CosineWeightedOf(*material_), zonal.zone());
      row["sh_error_cosine_l2"] = JsonOrNull(c.cosine_l2);
      row["sh_error_in_zone"] = JsonOrNull(c.in_zone);
    }
    // The D-BRDF fit, unless an adaptive capture found nothing above band 1.
    const bool skip_fit = s.adaptive && zonal.order <= 1;
    row["dbrdf_skipped"] = skip_fit;
    if (options_.fit && !skip_fit) {
      FitSessionOptions fit;
      fit.model = "dbrdf";
      fit.write_outputs = false;
      t = WallClock::now();
      const FitSessionOutcome outcome = FitSession(dir, fit, fits_);
      row["fit_s"] = SecondsSince(t);
      row["dbrdf_error_cosine_l2"] =
          outcome.report.value("error_cosine_l2", nlohmann::json(nullptr));
      row["dbrdf_fitted"] = outcome.report.value("fitted", false);
      const BallImage ball = RenderBall(*outcome.model, nullptr, BenchBall(options_.ball_size));
      row["ball_rmse"] = JsonOrNull(BallRmse(TruthBall(), ball) / TruthBallRms());
    }
    // What a renderer gets: the whole-hemisphere reconstruction `zbrdf fit` recommends by
    // default (the prior fit: --model auto keeps it unless another model is clearly better,
    // fitting/model_selection.h), leave-one-out for the bundled prior's own MERL materials. Its
    // cosine-weighted L2 over the hemisphere and its ball are the renderable error.
    if (options_.renderable && !material_->IsDelta()) {
      FitSessionOptions fit;
      fit.model = "prior";
      fit.write_outputs = false;
      if (material_->Spec().rfind("merl:", 0) == 0) {
        fit.prior.exclude = {MaterialShortName(material_->Spec())};
      }
      t = WallClock::now();
      const FitSessionOutcome outcome = FitSession(dir, fit, fits_);
      row["renderable_fit_s"] = SecondsSince(t);
      row["renderable_error_cosine_l2"] =
          outcome.report.value("error_cosine_l2", nlohmann::json(nullptr));
      const nlohmann::json ngan = outcome.report.value("error_ngan", nlohmann::json::object());
      row["renderable_error_ngan"] = ngan.value("hemisphere", nlohmann::json(nullptr));
      const BallImage ball = RenderBall(*outcome.model, nullptr, BenchBall(options_.ball_size));
      row["renderable_ball_rmse"] = JsonOrNull(BallRmse(TruthBall(), ball) / TruthBallRms());
    }
    row["wall_s"] = SecondsSince(wall_start);
    return row;
  }

  const BallImage& TruthBall() {
    std::lock_guard<std::mutex> lock(truth_mutex_);
    if (truth_ball_.image.pixels.empty()) {
      truth_ball_ = RenderBall(*material_, nullptr, BenchBall(options_.ball_size));
      const BallImage black =
          RenderBall(*MakeBrdf("lambert:0"), nullptr, BenchBall(options_.ball_size));
      truth_ball_rms_ = BallRmse(truth_ball_, black);
    }
    return truth_ball_;
  }
  double TruthBallRms() {
    TruthBall();
    return truth_ball_rms_ > 0 ? truth_ball_rms_ : 1.0;
  }

 private:
  const Rig& rig_;
  const BenchOptions& options_;
  FitContext* fits_;
  std::shared_ptr<const Brdf> material_;
  std::unique_ptr<VirtualRig> virtual_rig_;
  RigCalibration calibration_;
  std::mutex truth_mutex_;
  GroundTruth truth_;
  BallImage truth_ball_;
  double truth_ball_rms_ = 0;
};

const char* kCsvColumns[] = {"material",
                             "strategy",
                             "adaptive",
                             "order",
                             "order_captured",
                             "exposures",
                             "patterns",
                             "frames",
                             "capture_time_s",
                             "processing_s",
                             "sh_s",
                             "fit_s",
                             "coefficient_error",
                             "coefficient_error_common",
                             "sh_error_cosine_l2",
                             "sh_error_in_zone",
                             "dbrdf_error_cosine_l2",
                             "ball_rmse",
                             "renderable_error_cosine_l2",
                             "renderable_error_ngan",
                             "renderable_ball_rmse",
                             "adaptive_reason",
                             "failure"};

std::string CsvField(const nlohmann::json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) {
    std::string s = v.get<std::string>(), out = "\"";
    for (char c : s) {
      if (c == '"') out += '"';
      out += c;
    }
    return out + "\"";
  }
  if (v.is_number_float()) {
    char b[32];
    std::snprintf(b, sizeof(b), "%.6g", v.get<double>());
    return b;
  }
  return v.dump();
}

}  // namespace

std::vector<std::string> DefaultBenchMaterials() {
  // Diffuse to mirror-like: matte, fabric, plastics and paints, metallic paints, metals, chrome.
  return {"merl:white-diffuse-bball",
          "merl:pink-felt",
          "merl:blue-fabric",
          "merl:yellow-matte-plastic",
          "merl:red-phenolic",
          "merl:green-acrylic",
          "merl:gold-metallic-paint",
          "merl:blue-acrylic",
          "merl:specular-black-phenolic",
          "merl:nickel",
          "merl:brass",
          "merl:chrome"};
}

std::vector<BenchStrategy> BenchStrategies(const BenchOptions& o) {
  std::vector<BenchStrategy> out;
  for (int order : o.orders) {
    for (int e : o.exposures) {
      out.push_back(
          {"fixed-L" + std::to_string(order) + "-x" + std::to_string(e), false, order, e});
    }
    if (o.adaptive) out.push_back({"adaptive-L" + std::to_string(order), true, order, 3});
  }
  return out;
}

nlohmann::json CompareFixedAdaptive(const nlohmann::json& rows, int fixed_exposures,
                                    double tolerance) {
  std::map<std::pair<std::string, int>, const nlohmann::json*> fixed, adaptive;
  for (const nlohmann::json& r : rows) {
    if (!r.contains("capture_time_s") || !r["coefficient_error"].is_number()) continue;
    const auto key = std::make_pair(r["material"].get<std::string>(), r["order"].get<int>());
    if (r.value("adaptive", false)) {
      adaptive[key] = &r;
    } else if (r.value("exposures", 0) == fixed_exposures) {
      fixed[key] = &r;
    }
  }
  nlohmann::json pairs = nlohmann::json::array();
  double saving_sum = 0;
  int same = 0, renderable_pairs = 0, same_renderable = 0;
  for (const auto& [key, f] : fixed) {
    const auto it = adaptive.find(key);
    if (it == adaptive.end()) continue;
    const nlohmann::json& a = *it->second;
    const double tf = (*f)["capture_time_s"].get<double>(), ta = a["capture_time_s"].get<double>();
    const double ef = (*f)["coefficient_error"].get<double>(),
                 ea = a["coefficient_error"].get<double>();
    const bool same_error = ea <= ef * (1 + tolerance);
    const double saving = tf > 0 ? 1 - ta / tf : 0.0;
    saving_sum += saving;
    same += same_error;
    nlohmann::json p = {{"material", key.first},
                        {"order", key.second},
                        {"fixed_time_s", tf},
                        {"adaptive_time_s", ta},
                        {"saving", saving},
                        {"fixed_error", ef},
                        {"adaptive_error", ea},
                        {"same_error", same_error},
                        {"adaptive_order", a.value("order_captured", 0)}};
    for (const char* k : {"sh_error_in_zone", "dbrdf_error_cosine_l2", "ball_rmse",
                          "renderable_error_cosine_l2", "renderable_ball_rmse"}) {
      p[std::string("fixed_") + k] = f->value(k, nlohmann::json(nullptr));
      p[std::string("adaptive_") + k] = a.value(k, nlohmann::json(nullptr));
    }
    // Judged by what the user renders: the recommended fit's hemisphere error and its ball, both
    // at most (1 + tolerance) times the fixed capture's.
    bool have_renderable = true, same_render = true;
    for (const char* k : {"renderable_error_cosine_l2", "renderable_ball_rmse"}) {
      const nlohmann::json rf = f->value(k, nlohmann::json(nullptr)), ra = a.value(k, nlohmann::json(nullptr));
      if (!rf.is_number() || !ra.is_number()) {
        have_renderable = false;
        continue;
      }
      same_render = same_render && ra.get<double>() <= rf.get<double>() * (1 + tolerance);
    }
    if (have_renderable) {
      ++renderable_pairs;
      same_renderable += same_render;
      p["same_renderable_error"] = same_render;
    }
    pairs.push_back(p);
  }
  const double mean = pairs.empty() ? 0.0 : saving_sum / pairs.size();
  return {{"pairs", pairs},
          {"fixed_exposures", fixed_exposures},
          {"tolerance", tolerance},
          {"mean_saving", mean},
          {"same_error_pairs", same},
          {"target_saving", 0.4},
          {"target_met", !pairs.empty() && mean >= 0.4 && same == static_cast<int>(pairs.size())},
          {"renderable_pairs", renderable_pairs},
          {"same_renderable_error_pairs", same_renderable},
          {"target_met_renderable",
           renderable_pairs > 0 && mean >= 0.4 && same_renderable == renderable_pairs}};
}

void WriteBenchPlot(const nlohmann::json& rows, const std::string& path, const std::string& key,
                    const std::string& caption) {
  std::vector<std::string> materials;
  for (const nlohmann::json& r : rows) {
    const std::string m = r.value("material", std::string());
    if (std::find(materials.begin(), materials.end(), m) == materials.end()) materials.push_back(m);
  }
  const int cols = std::max<int>(1, std::min<int>(4, materials.size()));
  const int rows_n = std::max<int>(1, (static_cast<int>(materials.size()) + cols - 1) / cols);
  const int pw = 380, ph = 280, left = 58, bottom = 40, top = 26, right = 12;
  cv::Mat image(rows_n * ph + 48, cols * pw, CV_8UC3, cv::Scalar(255, 255, 255));
  auto text = [&](const std::string& s, cv::Point at, double scale = 0.4,
                  cv::Scalar c = cv::Scalar(40, 40, 40)) {
    cv::putText(image, s, at, cv::FONT_HERSHEY_SIMPLEX, scale, c, 1, cv::LINE_AA);
  };
  text(caption, cv::Point(8, rows_n * ph + 18), 0.42);
  text(
      "against capture time on the rig; blue: fixed x3 (thesis), green: fixed, other brackets, "
      "red: adaptive; labels: order; grey: Pareto front",
      cv::Point(8, rows_n * ph + 38), 0.42);
  for (size_t mi = 0; mi < materials.size(); ++mi) {
    const int ox = static_cast<int>(mi % cols) * pw, oy = static_cast<int>(mi / cols) * ph;
    struct Point {
      double t, e;
      int kind;
      int order;
    };
    std::vector<Point> pts;
    for (const nlohmann::json& r : rows) {
      if (r.value("material", std::string()) != materials[mi] || !r.contains("capture_time_s") ||
          !r.value(key, nlohmann::json(nullptr)).is_number()) {
        continue;
      }
      const int kind = r.value("adaptive", false) ? 2 : r.value("exposures", 0) == 3 ? 0 : 1;
      pts.push_back({r["capture_time_s"].get<double>(), r[key].get<double>(),
                     kind, r.value("order", 0)});
    }
    text(materials[mi], cv::Point(ox + left, oy + 18), 0.45);
    if (pts.empty()) continue;
    double t0 = 1e300, t1 = 0, e0 = 1e300, e1 = 0;
    for (const Point& p : pts) {
      t0 = std::min(t0, p.t), t1 = std::max(t1, p.t), e0 = std::min(e0, p.e),
      e1 = std::max(e1, p.e);
    }
    const double lt0 = std::log10(t0 / 1.2), lt1 = std::log10(t1 * 1.2);
    const double le0 = std::log10(e0 / 1.2), le1 = std::log10(e1 * 1.2);
    const int x0 = ox + left, x1 = ox + pw - right, y0 = oy + top, y1 = oy + ph - bottom;
    auto X = [&](double t) {
      return x0 + static_cast<int>((std::log10(t) - lt0) / (lt1 - lt0 + 1e-12) * (x1 - x0));
    };
    auto Y = [&](double e) {
      return y1 - static_cast<int>((std::log10(e) - le0) / (le1 - le0 + 1e-12) * (y1 - y0));
    };
    cv::rectangle(image, cv::Point(x0, y0), cv::Point(x1, y1), cv::Scalar(200, 200, 200));
    char b[64];
    std::snprintf(b, sizeof(b), "%.3g s", t0);
    text(b, cv::Point(x0, y1 + 14));
    std::snprintf(b, sizeof(b), "%.3g s", t1);
    text(b, cv::Point(x1 - 50, y1 + 14));
    text("capture time (log)", cv::Point(x0 + 90, y1 + 30));
    std::snprintf(b, sizeof(b), "%.3g", e1);
    text(b, cv::Point(ox + 4, y0 + 8));
    std::snprintf(b, sizeof(b), "%.3g", e0);
    text(b, cv::Point(ox + 4, y1));
    // Pareto front: the points no faster point beats in error.
    std::vector<Point> sorted = pts;
    std::sort(sorted.begin(), sorted.end(), [](const Point& a, const Point& c) {
      return a.t < c.t || (a.t == c.t && a.e < c.e);
    });
    std::vector<cv::Point> front;
    double best = 1e300;
    for (const Point& p : sorted) {
      if (p.e < best) {
        best = p.e;
        front.emplace_back(X(p.t), Y(p.e));
      }
    }
    if (front.size() > 1)
      cv::polylines(image, front, false, cv::Scalar(150, 150, 150), 1, cv::LINE_AA);
    const cv::Scalar colors[3] = {cv::Scalar(200, 90, 30), cv::Scalar(40, 160, 40),
                                  cv::Scalar(40, 40, 220)};
    for (const Point& p : pts) {
      cv::circle(image, cv::Point(X(p.t), Y(p.e)), 4, colors[p.kind], cv::FILLED, cv::LINE_AA);
      text(std::to_string(p.order), cv::Point(X(p.t) + 5, Y(p.e) - 4), 0.35, colors[p.kind]);
    }
  }
  WritePng(path, image);  // pictures/image.h: through basis/atomic_file.h
}

void BenchOptions::Validate() const {
  OptionChecker check("BenchOptions");
  check.Require(!out_dir.empty(), "out_dir", "must name the output folder (--out)")
      .Require(preset == "fast" || preset == "full", "preset",
               "must be fast or full (got '" + preset + "')")
      .Require(!orders.empty(), "orders", "must not be empty (--orders)");
  for (size_t i = 0; i < orders.size(); ++i) {
    check.InRange("orders[" + std::to_string(i) + "]", orders[i], 1, 20);
  }
  for (size_t i = 0; i < exposures.size(); ++i) {
    check.InRange("exposures[" + std::to_string(i) + "]", exposures[i], 1, 10);
  }
  check.Require(!exposures.empty() || adaptive, "exposures",
                "must not be empty unless adaptive: there is no strategy to run (give "
                "--exposures or keep adaptive)")
      .Nested("adaptive_options", adaptive_options)
      .Require(truth_samples >= 16 && (truth_samples & (truth_samples - 1)) == 0,
               "truth_samples",
               "must be a power of two >= 16 (--truth-samples; got " +
                   std::to_string(truth_samples) + ")")
      .InRange("ball_size", ball_size, 8, 8192)
      .InRange("parallel_materials", parallel_materials, 1, 16)
      .ThrowIfInvalid();
}

namespace {

std::vector<std::string> BenchMaterials(const BenchOptions& options) {
  return options.materials.empty() ? DefaultBenchMaterials() : options.materials;
}

// The bench's tables from its rows: bench.json's object (wall_s left to the caller).
nlohmann::json BenchTable(const nlohmann::json& batch_options, const nlohmann::json& floor,
                          const nlohmann::json& rows) {
  return {{"rig", batch_options["rig"]},
          {"preset", batch_options["preset"]},
          {"seed", batch_options["seed"]},
          {"materials", batch_options["materials"]},
          {"orders", batch_options["orders"]},
          {"exposures", batch_options["exposures"]},
          {"adaptive_options", floor.is_object() && floor.contains("adaptive_options")
                                   ? floor["adaptive_options"]
                                   : batch_options["adaptive_options"]},
          {"truth_samples", batch_options["truth_samples"]},
          {"floor", floor},
          {"rows", rows},
          {"summary", CompareFixedAdaptive(rows)},
          {"wall_s", nullptr}};
}

void WriteBenchOutputs(const std::string& out_dir, const nlohmann::json& table, bool renderable) {
  WriteFileAtomically(out_dir + "/bench.json", table.dump(2) + "\n");
  std::string csv;
  for (const char* c : kCsvColumns) csv += std::string(csv.empty() ? "" : ",") + c;
  csv += "\n";
  for (const nlohmann::json& r : table["rows"]) {
    bool first = true;
    for (const char* c : kCsvColumns) {
      if (!first) csv += ',';
      first = false;
      csv += CsvField(r.value(c, nlohmann::json(nullptr)));
    }
    csv += "\n";
  }
  WriteFileAtomically(out_dir + "/bench.csv", csv);
  WriteBenchPlot(table["rows"], out_dir + "/bench.png");
  if (renderable) {
    WriteBenchPlot(table["rows"], out_dir + "/bench-renderable.png", "renderable_error_cosine_l2",
                   "renderable error: the recommended (prior) fit's cosine-weighted L2 over the "
                   "whole hemisphere, leave-one-out");
  }
}

}  // namespace

BatchManifest BenchManifest(const BenchOptions& options) {
  options.Validate();
  const std::vector<std::string> materials = BenchMaterials(options);
  const Rig rig = ApplyPreset(LoadRig(options.rig_path), ParsePreset(options.preset));
  BatchManifest manifest;
  manifest.command = "bench";
  manifest.args = options.command_args;
  manifest.options = {{"rig", rig.name},
                      {"rig_hash", RigHashHex(rig)},
                      {"preset", options.preset},
                      {"seed", options.seed},
                      {"materials", materials},
                      {"orders", options.orders},
                      {"exposures", options.exposures},
                      {"adaptive", options.adaptive},
                      {"adaptive_options", options.adaptive_options.ToJson()},
                      {"measure_floor", options.measure_floor},
                      {"truth_samples", options.truth_samples},
                      {"fit", options.fit},
                      {"renderable", options.renderable},
                      {"ball_size", options.ball_size}};
  AddMaterialItems(materials, "", "", &manifest);
  return manifest;
}

nlohmann::json MeasureBenchFloor(const BenchOptions& options, bool* interrupted) {
  if (interrupted) *interrupted = false;
  if (!options.measure_floor || !options.adaptive) return nullptr;
  const BatchManifest manifest = BenchManifest(options);
  const std::string floor_path = options.out_dir + "/floor.json";
  const nlohmann::json stored = ReadJsonOrNull(floor_path);
  if (stored.is_object() && stored.value("batch_options", nlohmann::json()) == manifest.options &&
      stored.contains("floor_profile")) {
    return stored;
  }
  const Rig rig = ApplyPreset(LoadRig(options.rig_path), ParsePreset(options.preset));
  const int max_order = *std::max_element(options.orders.begin(), options.orders.end());
  const auto t = WallClock::now();
  FitContext fits;
  MaterialBench white(rig, options, "target:white", &fits);
  double capture_time_s = 0;
  // A shard measures into its own folder: shards that start together do not share a session.
  const std::string folder = options.shard.IsWhole()
                                 ? options.out_dir + "/floor"
                                 : options.out_dir + "/floor-shard-" + std::to_string(options.shard.index);
  const CaptureJobResult r =
      white.Capture({"floor", false, max_order, 3}, AdaptiveOptions(), folder, &capture_time_s);
  if (!r.complete) {
    if (interrupted) *interrupted = true;
    return nullptr;
  }
  std::vector<AdaptiveBand> bands;
  for (int l = 0; l <= r.zonal.order; ++l) {
    std::vector<const GridImage*> f;
    for (int m = -l; m <= l; ++m) f.push_back(&r.zonal.functions[ShIndex(l, m)]);
    bands.push_back(MeasureBandEnergy(l, f, r.zonal.grid));
  }
  AdaptiveOptions adaptive = options.adaptive_options;
  adaptive.floor_profile = FloorProfile(bands);
  nlohmann::json energies = nlohmann::json::array();
  for (const AdaptiveBand& b : bands) energies.push_back(b.energy);
  const nlohmann::json floor = {{"material", "target:white"},
                                {"order", max_order},
                                {"band_energy", energies},
                                {"floor_profile", adaptive.floor_profile},
                                {"adaptive_options", adaptive.ToJson()},
                                {"capture_time_s", capture_time_s},
                                {"wall_s", SecondsSince(t)},
                                {"batch_options", manifest.options}};
  WriteFileAtomically(floor_path, floor.dump(2) + "\n");
  return floor;
}

BenchSummary ReduceBench(const std::string& out_dir) {
  const BatchManifest manifest = ReadManifest(out_dir, "bench");
  nlohmann::json floor = ReadJsonOrNull(out_dir + "/floor.json");
  if (!floor.is_object() || floor.value("batch_options", nlohmann::json()) != manifest.options) {
    floor = nullptr;
  } else {
    floor.erase("batch_options");
  }
  BenchSummary summary;
  nlohmann::json rows = nlohmann::json::array();
  double item_wall_s = 0;
  for (const BatchItem& item : manifest.items) {
    const nlohmann::json result = ReadItemResult(out_dir, manifest, item);
    if (!result.is_object()) continue;
    item_wall_s += result.value("wall_s", 0.0);
    for (const nlohmann::json& row : result.value("rows", nlohmann::json::array())) {
      summary.failed += row.contains("failure");
      rows.push_back(row);
    }
  }
  summary.table = BenchTable(manifest.options, floor, rows);
  summary.table["item_wall_s_sum"] = item_wall_s;
  WriteBenchOutputs(out_dir, summary.table, manifest.options.value("renderable", true));
  return summary;
}

BenchSummary RunBench(const BenchOptions& options) {
  options.Validate();
  const std::vector<std::string> materials = BenchMaterials(options);
  for (const std::string& m : materials) MakeBrdf(m);  // validates every spec up front
  const std::vector<BenchStrategy> strategies = BenchStrategies(options);
  const Rig rig = ApplyPreset(LoadRig(options.rig_path), ParsePreset(options.preset));
  const BatchManifest manifest = BenchManifest(options);
  PrepareManifest(options.out_dir, manifest, options.shard);
  const int max_order = *std::max_element(options.orders.begin(), options.orders.end());
  const std::vector<size_t> owned = options.shard.ItemsOf(materials.size());
  const long total =
      static_cast<long>(owned.size() * strategies.size()) + (options.measure_floor ? 1 : 0);
  std::atomic<long> done{0};
  Report(options.progress, {"bench", 0, total, "captures"});
  BenchSummary summary;
  FitContext fits;
  const auto bench_start = WallClock::now();

  // The rig's systematic floor, on a Lambertian target (acquisition/adaptive.h).
  BenchOptions run = options;
  bool interrupted = false;
  const nlohmann::json floor = MeasureBenchFloor(options, &interrupted);
  if (interrupted) {
    summary.interrupted = true;
    return summary;
  }
  if (floor.is_object()) {
    run.adaptive_options.floor_profile = floor["floor_profile"].get<std::vector<double>>();
  }
  if (options.measure_floor) Report(options.progress, {"bench", ++done, total, "captures"});

  std::mutex mutex;
  // A whole run keeps the tables current after every material; a shard leaves them to the merge.
  auto write_outputs = [&]() {  // under mutex
    if (!options.shard.IsWhole()) return;
    summary.table = ReduceBench(options.out_dir).table;
    summary.table["wall_s"] = SecondsSince(bench_start);
    WriteFileAtomically(options.out_dir + "/bench.json", summary.table.dump(2) + "\n");
  };
  std::exception_ptr output_error;
  // One material, all strategies; false stops this worker (interrupted, or the outputs could not
  // be written).
  auto bench_material = [&](size_t mi) {
    if (options.interrupt && options.interrupt->load()) return false;
    const BatchItem& item = manifest.items[mi];
    if (ReadItemResult(options.out_dir, manifest, item).is_object()) {
      done += static_cast<long>(strategies.size());
      Report(options.progress, {"bench", done.load(), total, "captures"});
      return true;
    }
    const RunningMarker running(options.out_dir, item);
    const auto material_start = WallClock::now();
    const std::string dir = options.out_dir + "/" + item.id;
    std::unique_ptr<MaterialBench> bench;
    std::string setup_failure;
    try {
      bench = std::make_unique<MaterialBench>(rig, run, materials[mi], &fits);
    } catch (const std::exception& e) {
      setup_failure = e.what();
    }
    nlohmann::json rows = nlohmann::json::array();
    int failed = 0;
    for (size_t si = 0; si < strategies.size(); ++si) {
      if (options.interrupt && options.interrupt->load()) return false;
      nlohmann::json row;
      try {
        if (!bench) throw InputError(setup_failure);
        row = bench->Run(strategies[si], dir + "/" + strategies[si].name, max_order);
        if (row.value("interrupted", false)) return false;
      } catch (const std::exception& e) {
        row = {{"material", materials[mi]},
               {"strategy", strategies[si].name},
               {"adaptive", strategies[si].adaptive},
               {"order", strategies[si].order},
               {"failure", e.what()}};
      }
      failed += row.contains("failure");
      rows.push_back(std::move(row));
      Report(options.progress, {"bench", ++done, total, "captures"});
    }
    std::lock_guard<std::mutex> lock(mutex);
    summary.failed += failed;
    try {
      WriteItemResult(
          options.out_dir, manifest, item,
          {{"material", materials[mi]}, {"rows", rows}, {"wall_s", SecondsSince(material_start)}});
      write_outputs();
    } catch (...) {
      if (!output_error) output_error = std::current_exception();
      return false;
    }
    return true;
  };
  // Materials in flight at once: each capture and fit is itself mostly single-threaded.
  const int in_flight = std::clamp(options.parallel_materials, 1, 16);
  ParallelForEach(static_cast<int64_t>(owned.size()), in_flight,
                  [&](int64_t k) { return bench_material(owned[static_cast<size_t>(k)]); });
  if (output_error) std::rethrow_exception(output_error);
  std::lock_guard<std::mutex> lock(mutex);
  write_outputs();
  summary.interrupted = done.load() < total;
  return summary;
}

}  // namespace zbrdf
