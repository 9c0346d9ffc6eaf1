// zbrdf preview: a material ball under a directional light or an environment map.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "basis/error.h"
#include "tools/brdf_input.h"
#include "tools/cli/command.h"
#include "tools/cli/preview_flags.h"
#include "pictures/image.h"
#include "pictures/material_ball.h"

namespace zbrdf::cli {
namespace {

int RunPreview(const std::vector<std::string>& args) {
  CommandLine cl("preview",
                 "Renders a material ball: a sphere with the BRDF under a directional light\n"
                 "(--light) or an HDR environment map (--envmap; by default the built-in sky with\n"
                 "a small bright sun). Environment light is importance-sampled from the material\n"
                 "(Brdf::Sample; a D-BRDF samples its p(h) table) and from the map, combined by\n"
                 "multiple importance sampling. Writes a tone-mapped PNG and, with --exr, the\n"
                 "linear image. docs/preview.md describes the frame, the sky and the tone curve.");
  cl.Positional("INPUT", "session folder, file or material spec (see below)")
      .Option("out", "FILE.png", "the tone-mapped image to write")
      .Option("exr", "FILE.exr", "also write the linear RGB image")
      .Flag("json", "print what was rendered as JSON");
  AddPreviewFlags(cl, 64, 256);
  cl.Epilog(
      "Examples:\n"
      "  zbrdf preview merl:gold-metallic-paint --out gold.png\n"
      "  zbrdf preview results/blue-acrylic --light dir:40,60 --out ball.png --exr ball.exr\n"
      "  zbrdf preview fit-dbrdf.exr --envmap studio.exr --spp 256 --size 512 --out ball.png\n\n" +
      BrdfInputHelp());
  if (!cl.Parse(args)) return 0;
  if (!cl.Has("out")) throw InputError("--out is required: the PNG to write");
  const auto start = std::chrono::steady_clock::now();
  const BrdfInput input = ResolveBrdfInput(cl.Positional(0));
  const PreviewSetup setup = ReadPreviewFlags(cl);
  const BallImage ball = RenderBall(*input.brdf, setup.environment.get(), setup.ball);
  WritePng(cl.Get("out"), ToneMap(ball.image, setup.exposure_ev));
  if (cl.Has("exr")) WriteExrImage(cl.Get("exr"), ball.image);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (cl.Has("json")) {
    nlohmann::json j = {{"input", input.description}, {"brdf", input.brdf->Spec()},
                        {"lighting", setup.lighting}, {"spp", setup.ball.spp},
                        {"size", setup.ball.size},    {"sampling", cl.Get("sampling")},
                        {"png", cl.Get("out")},       {"seconds", seconds}};
    if (cl.Has("exr")) j["exr"] = cl.Get("exr");
    std::cout << j.dump(2) << "\n";
  } else {
    std::printf("rendered %s under %s, %d x %d, %d spp (%.2f s) -> %s\n", input.description.c_str(),
                setup.lighting.c_str(), setup.ball.size, setup.ball.size, setup.ball.spp, seconds,
                cl.Get("out").c_str());
  }
  return 0;
}

const CommandRegistration kReg({"preview", "render a material ball of a BRDF (PNG, optional EXR)",
                                RunPreview});

}  // namespace
}  // namespace zbrdf::cli
