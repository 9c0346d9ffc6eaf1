// zbrdf preview: a material ball under a directional light or an environment map; with
// --turntable or --environment-sequence, an animation (frames, APNG) rendered with MIS, SIR or
// SMC (pictures/relight.h).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "acquisition/session.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "pictures/animated_png.h"
#include "pictures/image.h"
#include "pictures/material_ball.h"
#include "pictures/relight.h"
#include "tools/brdf_input.h"
#include "tools/cli/command.h"
#include "tools/cli/preview_flags.h"
#include "tools/terminal_progress.h"

namespace zbrdf::cli {
namespace {

namespace fs = std::filesystem;

// The numbered environment maps of --environment-sequence, in name order.
std::vector<std::string> SequenceFiles(const std::string& dir) {
  if (!fs::is_directory(dir)) {
    throw InputError("--environment-sequence " + dir +
                     ": not a folder; give a folder of numbered .exr or .hdr maps");
  }
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (entry.is_regular_file() && (ext == ".exr" || ext == ".hdr")) {
      files.push_back(entry.path().string());
    }
  }
  if (files.empty()) {
    throw InputError("--environment-sequence " + dir +
                     ": no .exr or .hdr files; name the frames e.g. env-0001.exr, env-0002.exr");
  }
  std::sort(files.begin(), files.end());
  return files;
}

int RunPreview(const std::vector<std::string>& args) {
  CommandLine cl("preview",
                 "Renders a material ball: a sphere with the BRDF under a directional light\n"
                 "(--light) or an HDR environment (--environment; by default the built-in sky with\n"
                 "a small bright sun). Environment light is importance-sampled: --sampler mis\n"
                 "combines material and environment samples (MIS); sir resamples candidates from\n"
                 "both by environment x BRDF (bidirectional importance sampling); smc carries\n"
                 "those samples from frame to frame, on a turntable turned with the light\n"
                 "(sequential Monte Carlo: the lowest error per second of an animation;\n"
                 "smc-bridges is the seed paper's variant, for comparison). --turntable N and\n"
                 "--environment-sequence DIR render an animation: numbered PNG frames and\n"
                 "animation.png (an animated PNG browsers play). docs/preview.md describes the\n"
                 "frame, the samplers, the sky and the tone curve.");
  cl.Positional("INPUT", "session folder, file or material spec (see below)")
      .Option("out", "FILE.png|DIR",
              "the tone-mapped image to write; for an animation the folder (default "
              "SESSION/turntable for a session's turntable)")
      .Option("exr", "FILE.exr|DIR", "also write the linear RGB image (a folder for an animation)")
      .Option("sampler", "S", "mis, sir, smc or smc-bridges (see above)", "mis")
      .Option("candidates", "M", "sir, smc: candidates per pixel (default 4 x --spp)")
      .Option("history-weight", "H",
              "smc: the carried particles' weight against the M fresh candidates", "1")
      .Option("bridges", "K", "smc-bridges: intermediate distributions between frames", "2")
      .Option("move-candidates", "J", "smc-bridges: proposals per Metropolis-Hastings move", "4")
      .Option("ess-threshold", "F",
              "smc-bridges: resample when the effective sample size < F x --spp", "0.5")
      .Option("turntable", "N", "an animation of N frames, the environment turned once around")
      .Option("environment-sequence", "DIR",
              "an animation whose frames are lit by the numbered .exr / .hdr maps in DIR")
      .Option("fps", "N", "frames per second of animation.png", "15")
      .Flag("json", "print what was rendered as JSON");
  AddPreviewFlags(cl, 64, 256);
  cl.Epilog(
      "Examples:\n"
      "  zbrdf preview merl:gold-metallic-paint --out gold.png\n"
      "  zbrdf preview results/blue-acrylic --light dir:40,60 --out ball.png --exr ball.exr\n"
      "  zbrdf preview fit-dbrdf.exr --environment studio.hdr --spp 256 --size 512 --out ball.png\n"
      "  zbrdf preview results/blue-acrylic --turntable 30 --environment studio --sampler smc "
      "--spp 16\n\n" +
      BrdfInputHelp());
  if (!cl.Parse(args)) return 0;
  const auto start = std::chrono::steady_clock::now();
  const std::string input_text = cl.Positional(0);
  const bool turntable = cl.Has("turntable");
  const bool sequence_dir = cl.Has("environment-sequence");
  const bool animation = turntable || sequence_dir;
  if (turntable && sequence_dir) {
    throw InputError("--turntable and --environment-sequence exclude each other: give one");
  }
  const BallSampler sampler = BallSamplerFromName(cl.Get("sampler"));
  if (sampler != BallSampler::kMis && cl.Get("sampling") != "mis") {
    throw InputError("--sampling " + cl.Get("sampling") + " goes with --sampler mis only; " +
                     "--sampler " + cl.Get("sampler") + " chooses its own samples");
  }
  std::string out;
  if (cl.Has("out")) {
    out = cl.Get("out");
  } else if (turntable && fs::exists(SessionPath(input_text, kSessionFile))) {
    out = SessionPath(input_text, "turntable");
  } else {
    throw InputError(animation ? "--out is required: the folder for the frames"
                               : "--out is required: the PNG to write");
  }
  const BrdfInput input = ResolveBrdfInput(input_text);
  PreviewSetup setup = ReadPreviewFlags(cl);
  if (animation && setup.ball.light_direction) {
    throw InputError("--light gives a still light; an animation needs an environment "
                     "(--environment, the sky by default)");
  }
  RelightOptions relight;
  relight.ball = setup.ball;
  relight.sampler = sampler;
  relight.candidates = cl.Has("candidates") ? cl.GetInt("candidates", 1, 1 << 20) : 0;
  relight.history_weight = cl.GetDouble("history-weight", 1e-3, 1e3);
  relight.bridges = cl.GetInt("bridges", 1, 64);
  relight.move_candidates = cl.GetInt("move-candidates", 2, 1024);
  relight.ess_threshold = cl.GetDouble("ess-threshold", 0, 1);

  if (!animation) {
    BallImage ball;
    if (sampler == BallSampler::kMis || setup.ball.light_direction) {
      ball = RenderBall(*input.brdf, setup.environment.get(), setup.ball);
    } else {
      BallSequence sequence(*input.brdf, relight);
      ball = sequence.Render(*setup.environment);
    }
    WritePng(out, ToneMap(ball.image, setup.exposure_ev));
    if (cl.Has("exr")) WriteExrImage(cl.Get("exr"), ball.image);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (cl.Has("json")) {
      nlohmann::json j = {{"input", input.description}, {"brdf", input.brdf->Spec()},
                          {"lighting", setup.lighting}, {"spp", setup.ball.spp},
                          {"size", setup.ball.size},    {"sampling", cl.Get("sampling")},
                          {"sampler", cl.Get("sampler")}, {"png", out},
                          {"seconds", seconds}};
      if (cl.Has("exr")) j["exr"] = cl.Get("exr");
      std::cout << j.dump(2) << "\n";
    } else {
      std::printf("rendered %s under %s, %d x %d, %d spp (%.2f s) -> %s\n",
                  input.description.c_str(), setup.lighting.c_str(), setup.ball.size,
                  setup.ball.size, setup.ball.spp, seconds, out.c_str());
    }
    return 0;
  }

  // An animation: the frames' environments, cheap rotated copies or the sequence's files.
  const int fps = cl.GetInt("fps", 1, 120);
  std::vector<std::string> files;
  int frames = 0;
  if (turntable) {
    frames = cl.GetInt("turntable", 1, 100000);
  } else {
    files = SequenceFiles(cl.Get("environment-sequence"));
    frames = static_cast<int>(files.size());
  }
  fs::create_directories(out);
  const std::string exr_dir = cl.Has("exr") ? cl.Get("exr") : "";
  if (!exr_dir.empty()) fs::create_directories(exr_dir);
  BallSequence sequence(*input.brdf, relight);
  TerminalProgress progress(cl.Has("json"));
  std::vector<cv::Mat> pngs;
  nlohmann::json frame_rows = nlohmann::json::array();
  const double rotation_step = 2.0 * M_PI / frames;
  for (int t = 0; t < frames; ++t) {
    const auto frame_start = std::chrono::steady_clock::now();
    const Environment env = turntable ? setup.environment->Rotated(rotation_step * t)
                                      : LoadEnvironment(files[t]);
    RelightStats stats;
    const BallImage ball = sequence.Render(env, &stats);
    char name[32];
    std::snprintf(name, sizeof(name), "frame-%04d", t);
    pngs.push_back(ToneMap(ball.image, setup.exposure_ev));
    WritePng(out + "/" + name + ".png", pngs.back());
    if (!exr_dir.empty()) WriteExrImage(exr_dir + "/" + name + ".exr", ball.image);
    const double frame_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - frame_start).count();
    nlohmann::json row = {{"frame", t},
                          {"seconds", frame_s},
                          {"brdf_evaluations", stats.brdf_evaluations},
                          {"sir_starts", stats.sir_starts}};
    if (turntable) row["rotation_deg"] = rotation_step * t * 180 / M_PI;
    if (!turntable) row["environment"] = files[t];
    if (sampler == BallSampler::kSmc || sampler == BallSampler::kSmcBridges) {
      row["resamplings"] = stats.resamplings;
      row["mean_ess_fraction"] = stats.mean_ess_fraction;
    }
    if (sampler == BallSampler::kSmc) row["particles_carried"] = stats.carried;
    if (sampler == BallSampler::kSmcBridges) {
      row["moves_accepted"] = stats.moves_accepted;
      row["moves_proposed"] = stats.moves_proposed;
    }
    frame_rows.push_back(row);
    progress.Update({"render", t + 1, frames, "frames"});
  }
  WriteAnimatedPng(out + "/animation.png", pngs, fps);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json summary = {{"input", input.description},
                            {"brdf", input.brdf->Spec()},
                            {"lighting", setup.lighting},
                            {"kind", turntable ? "turntable" : "environment-sequence"},
                            {"frames", frames},
                            {"fps", fps},
                            {"sampler", cl.Get("sampler")},
                            {"spp", setup.ball.spp},
                            {"size", setup.ball.size},
                            {"seconds", seconds},
                            {"animation", out + "/animation.png"},
                            {"frame_files", out + "/frame-NNNN.png"},
                            {"per_frame", frame_rows}};
  if (!exr_dir.empty()) summary["exr_files"] = exr_dir + "/frame-NNNN.exr";
  WriteFileAtomically(out + "/animation.json", summary.dump(2));
  if (cl.Has("json")) {
    summary.erase("per_frame");
    std::cout << summary.dump(2) << "\n";
  } else {
    std::printf("rendered %d frames of %s under %s (%s), %d x %d, %d spp, %.1f s (%.2f s/frame)"
                " -> %s/animation.png\n",
                frames, input.description.c_str(), setup.lighting.c_str(),
                cl.Get("sampler").c_str(), setup.ball.size, setup.ball.size, setup.ball.spp,
                seconds, seconds / frames, out.c_str());
  }
  return 0;
}

const CommandRegistration kPreviewCommand(
    {"preview",
     "render a material ball of a BRDF (PNG, optional EXR), or a "
     "turntable / environment-sequence animation",
     RunPreview});

}  // namespace
}  // namespace zbrdf::cli
