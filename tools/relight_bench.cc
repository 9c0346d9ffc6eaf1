#include "tools/relight_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/option_checker.h"
#include "brdf/dbrdf.h"
#include "brdf/material_spec.h"
#include "pictures/image.h"
#include "pictures/relight.h"
#include "pictures/relight_plots.h"
#include "tools/brdf_input.h"

namespace zbrdf {
namespace {

double StepRadians(const RelightBenchOptions& options) {
  return options.degrees_per_frame > 0 ? options.degrees_per_frame * M_PI / 180
                                       : 2.0 * M_PI / options.frames;
}

std::shared_ptr<const Brdf> BenchMaterial(const std::string& name) {
  if (name == "glossy-dbrdf") {
    DBrdfParams params;
    params.p_h = HalfVectorTable::Ggx(0.1);
    params.c = Rgb(0.25, 0.2, 0.15);
    params.f0 = 0.9;
    return std::make_shared<DBrdf>(params);
  }
  if (name == "diffuse") return MakeBrdf("lambert:0.5");
  return ResolveBrdfInput(name).brdf;
}

Environment BenchEnvironment(const std::string& name) {
  if (name == "studio") return Environment::Studio();
  if (name == "sky") return Environment::Sky();
  return Environment::FromFile(name);
}

// Relative RMSE over the pixels both images see the ball.
double RelativeRmse(const BallImage& image, const BallImage& reference) {
  double sum = 0, norm = 0;
  for (size_t i = 0; i < image.image.pixels.size(); ++i) {
    if (!image.coverage[i] || !reference.coverage[i]) continue;
    for (int c = 0; c < 3; ++c) {
      const double d = image.image.pixels[i][c] - reference.image.pixels[i][c];
      sum += d * d;
      norm += reference.image.pixels[i][c] * reference.image.pixels[i][c];
    }
  }
  return norm > 0 ? std::sqrt(sum / norm) : 0.0;
}

std::string SafeName(std::string s) {
  for (char& c : s) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  }
  return s;
}

}  // namespace

void RelightBenchOptions::Validate() const {
  OptionChecker check("RelightBenchOptions");
  check.Require(!materials.empty(), "materials", "must name at least one material")
      .InRange("size", size, 8, 1024)
      .InRange("frames", frames, 1, 10000)
      .InRange("degrees_per_frame", degrees_per_frame, 0.0, 360.0)
      .Require(!budgets.empty(), "budgets", "must list at least one budget")
      .AtLeast("reference_spp", reference_spp, 1)
      .AtLeast("bridges", bridges, 1)
      .Require(history_weight > 0, "history_weight", "must be positive")
      .Require(ess_threshold >= 0 && ess_threshold <= 1, "ess_threshold", "must be in [0, 1]")
      .Require(!out_dir.empty(), "out_dir", "must name the folder for the results");
  for (int b : budgets) check.AtLeast("budgets", b, 1);
  check.ThrowIfInvalid();
}

double InterpolateLogLog(std::vector<std::pair<double, double>> curve, double x) {
  std::sort(curve.begin(), curve.end());
  for (size_t k = 0; k + 1 < curve.size(); ++k) {
    const auto [x0, y0] = curve[k];
    const auto [x1, y1] = curve[k + 1];
    if (x < x0 || x > x1 || !(x0 > 0) || !(y0 > 0) || !(y1 > 0)) continue;
    if (x1 == x0) return y0;
    const double t = (std::log(x) - std::log(x0)) / (std::log(x1) - std::log(x0));
    return std::exp(std::log(y0) + t * (std::log(y1) - std::log(y0)));
  }
  if (curve.size() == 1 && curve[0].first == x) return curve[0].second;
  return std::numeric_limits<double>::quiet_NaN();
}

nlohmann::json RunRelightBench(const RelightBenchOptions& options) {
  options.Validate();
  std::filesystem::create_directories(options.out_dir);
  const Environment base = BenchEnvironment(options.environment);
  std::vector<Environment> frames;
  for (int t = 0; t < options.frames; ++t) {
    frames.push_back(base.Rotated(StepRadians(options) * t));
  }
  const std::vector<BallSampler> samplers = {BallSampler::kMis, BallSampler::kSir,
                                             BallSampler::kSmc, BallSampler::kSmcBridges};
  const long total_frames = static_cast<long>(options.materials.size()) * options.frames *
                            (2 + static_cast<long>(samplers.size() * options.budgets.size()));
  long done = 0;
  auto tick = [&]() {
    Report(options.progress, {"relight-bench", ++done, total_frames, "frames"});
  };
  nlohmann::json rows = nlohmann::json::array(), summary = nlohmann::json::array(),
                 equal_time = nlohmann::json::array();
  std::ostringstream csv;
  csv << "material,sampler,budget,frame,seconds,relative_rmse\n";
  std::vector<cv::Mat> panels;
  const int middle = options.frames / 2;
  for (const std::string& material : options.materials) {
    const std::shared_ptr<const Brdf> brdf = BenchMaterial(material);
    BallOptions ball;
    ball.size = options.size;
    ball.jitter = false;
    // The reference, and a second one for its own noise.
    std::vector<BallImage> reference;
    double reference_noise = 0;
    for (int t = 0; t < options.frames; ++t) {
      ball.spp = options.reference_spp;
      ball.seed = options.seed + 1000003;
      reference.push_back(RenderBall(*brdf, &frames[t], ball));
      tick();
      if (t == middle) {
        ball.seed = options.seed + 2000003;
        reference_noise = RelativeRmse(RenderBall(*brdf, &frames[t], ball), reference[t]) /
                          std::sqrt(2.0);
      }
      tick();
    }
    std::map<BallSampler, std::vector<std::pair<double, double>>> curves;
    std::map<BallSampler, std::map<int, BallImage>> middle_frames;
    for (BallSampler sampler : samplers) {
      for (int budget : options.budgets) {
        RelightOptions relight;
        relight.ball = ball;
        relight.ball.spp = budget;
        relight.ball.seed = options.seed;
        relight.sampler = sampler;
        relight.history_weight = options.history_weight;
        relight.bridges = options.bridges;
        relight.ess_threshold = options.ess_threshold;
        BallSequence sequence(*brdf, relight);
        double seconds_sum = 0, rmse_sum = 0;
        for (int t = 0; t < options.frames; ++t) {
          const auto start = std::chrono::steady_clock::now();
          BallImage image = sequence.Render(frames[t]);
          const double seconds =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          const double rmse = RelativeRmse(image, reference[t]);
          seconds_sum += seconds;
          rmse_sum += rmse;
          rows.push_back({{"material", material}, {"sampler", BallSamplerName(sampler)},
                          {"budget", budget}, {"frame", t}, {"seconds", seconds},
                          {"relative_rmse", rmse}});
          csv << material << "," << BallSamplerName(sampler) << "," << budget << "," << t << ","
              << seconds << "," << rmse << "\n";
          if (t == middle) middle_frames[sampler][budget] = std::move(image);
          tick();
        }
        const double mean_s = seconds_sum / options.frames, mean_rmse = rmse_sum / options.frames;
        curves[sampler].push_back({mean_s, mean_rmse});
        summary.push_back({{"material", material}, {"sampler", BallSamplerName(sampler)},
                           {"budget", budget}, {"mean_frame_seconds", mean_s},
                           {"mean_relative_rmse", mean_rmse},
                           {"reference_noise", reference_noise}});
      }
    }
    for (size_t k = 0; k < options.budgets.size(); ++k) {
      const double t_sir = curves[BallSampler::kSir][k].first;
      const double mis = InterpolateLogLog(curves[BallSampler::kMis], t_sir);
      const double smc = InterpolateLogLog(curves[BallSampler::kSmc], t_sir);
      const double smc_bridges = InterpolateLogLog(curves[BallSampler::kSmcBridges], t_sir);
      auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
      equal_time.push_back({{"material", material}, {"frame_seconds", t_sir},
                            {"sir_budget", options.budgets[k]},
                            {"sir_relative_rmse", curves[BallSampler::kSir][k].second},
                            {"mis_relative_rmse", number(mis)},
                            {"smc_relative_rmse", number(smc)},
                            {"smc_bridges_relative_rmse", number(smc_bridges)}});
    }
    std::vector<XySeries> series;
    for (BallSampler sampler : samplers) series.push_back({BallSamplerName(sampler), curves[sampler]});
    char turn[64];
    std::snprintf(turn, sizeof(turn), " frames, %.3g deg per frame",
                  StepRadians(options) * 180 / M_PI);
    panels.push_back(DrawLogLogPanel(material + ": turntable of " +
                                         std::to_string(options.frames) + turn,
                                     "seconds per frame", "relative RMSE", series));
    // Frames at the middle of the turntable: each sampler at the budget whose time is closest
    // to SIR's at the largest budget.
    const double t_ref = curves[BallSampler::kSir].back().first;
    std::vector<cv::Mat> tiles{ToneMap(reference[middle].image)};
    std::vector<std::string> labels{"reference"};
    for (BallSampler sampler : samplers) {
      size_t best = 0;
      for (size_t k = 0; k < options.budgets.size(); ++k) {
        if (std::abs(std::log(curves[sampler][k].first / t_ref)) <
            std::abs(std::log(curves[sampler][best].first / t_ref))) {
          best = k;
        }
      }
      tiles.push_back(ToneMap(middle_frames[sampler][options.budgets[best]].image));
      char label[64];
      std::snprintf(label, sizeof(label), "%s %d (%.1f ms)", BallSamplerName(sampler),
                    options.budgets[best], 1e3 * curves[sampler][best].first);
      labels.push_back(label);
    }
    WritePng(options.out_dir + "/frames-" + SafeName(material) + ".png",
             LabeledStrip(tiles, labels));
  }
  cv::Mat plot;
  cv::vconcat(panels, plot);
  WritePng(options.out_dir + "/rmse-vs-time.png", plot);
  WriteFileAtomically(options.out_dir + "/relight-bench.csv", csv.str());
  nlohmann::json result = {
      {"options",
       {{"materials", options.materials}, {"environment", options.environment},
        {"size", options.size}, {"frames", options.frames}, {"budgets", options.budgets},
        {"reference_spp", options.reference_spp}, {"history_weight", options.history_weight},
        {"degrees_per_frame", StepRadians(options) * 180 / M_PI}, {"bridges", options.bridges},
        {"ess_threshold", options.ess_threshold}, {"seed", options.seed}}},
      {"summary", summary},
      {"equal_time", equal_time},
      {"rows", rows}};
  WriteFileAtomically(options.out_dir + "/relight-bench.json", result.dump(2));
  return result;
}

}  // namespace zbrdf
