// zbrdf compare: two BRDFs side by side, a difference image and error metrics.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "pictures/brdf_compare.h"
#include "tools/brdf_input.h"
#include "tools/cli/command.h"
#include "tools/cli/preview_flags.h"
#include "pictures/image.h"

namespace zbrdf::cli {
namespace {

int RunCompare(const std::vector<std::string>& args) {
  CommandLine cl(
      "compare",
      "Compares two BRDFs: renders both balls with the same light and pixel samples,\n"
      "a difference image, and error metrics: the RMSE of the renders (linear RGB, over "
      "the\nball) and the cosine-weighted L2 distance between the BRDFs over the "
      "hemisphere\n(Ngan et al. 2005). Writes DIR/a.png, DIR/b.png, DIR/difference.png,\n"
      "DIR/side-by-side.png and DIR/metrics.json.");
  cl.Positional("A", "the reference: session folder, file or material spec")
      .Positional("B", "the other BRDF")
      .Option("out", "DIR", "folder for the images and metrics.json (created if missing)")
      .Option("samples", "N", "Monte Carlo samples of the L2 distance", "262144")
      .Flag("json", "print metrics.json to standard output as well");
  AddPreviewFlags(cl, 32, 192);
  cl.Epilog("Example:\n  zbrdf compare merl:blue-acrylic results/blue-acrylic --out compare/\n\n" +
            BrdfInputHelp());
  if (!cl.Parse(args)) return 0;
  if (!cl.Has("out")) throw InputError("--out is required: the folder for the results");
  const std::string dir = cl.Get("out");
  const BrdfInput a = ResolveBrdfInput(cl.Positional(0));
  const BrdfInput b = ResolveBrdfInput(cl.Positional(1));
  const PreviewSetup setup = ReadPreviewFlags(cl);
  const int64_t samples = cl.GetInt("samples", 1024, 1 << 28);
  std::filesystem::create_directories(dir);
  const MaterialComparison c = CompareMaterials(*a.brdf, *b.brdf, setup.environment.get(),
                                                setup.ball, setup.exposure_ev, samples);
  WritePng(dir + "/a.png", ToneMap(c.a.image, setup.exposure_ev));
  WritePng(dir + "/b.png", ToneMap(c.b.image, setup.exposure_ev));
  WritePng(dir + "/difference.png", c.difference);
  WritePng(dir + "/side-by-side.png", c.side_by_side);
  nlohmann::json metrics = c.ToJson();
  metrics["a"] = a.description;
  metrics["b"] = b.description;
  metrics["lighting"] = setup.lighting;
  metrics["spp"] = setup.ball.spp;
  metrics["size"] = setup.ball.size;
  metrics["l2_samples"] = samples;
  WriteFileAtomically(dir + "/metrics.json", metrics.dump(2) + "\n");
  if (cl.Has("json")) {
    std::cout << metrics.dump(2) << "\n";
  } else {
    std::printf("A: %s\nB: %s\n", a.description.c_str(), b.description.c_str());
    std::printf("  render RMSE %.4g (relative %.3g) under %s, %d spp\n", c.rmse, c.relative_rmse,
                setup.lighting.c_str(), setup.ball.spp);
    std::printf("  cosine-weighted L2 %.4g /sr (relative %.3g; R G B %.4g %.4g %.4g)\n",
                c.distance.Mean(), c.distance.RelativeMean(), c.distance.l2.r, c.distance.l2.g,
                c.distance.l2.b);
    std::printf("  -> %s/side-by-side.png, %s/metrics.json\n", dir.c_str(), dir.c_str());
  }
  return 0;
}

const CommandRegistration kCompareCommand({"compare",
                                           "render two BRDFs side by side with error metrics",
                                           RunCompare});

}  // namespace
}  // namespace zbrdf::cli
