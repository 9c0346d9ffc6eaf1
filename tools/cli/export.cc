// zbrdf export: a fit, a conversion or any material in a file renderers and viewers load.
#include <algorithm>
#include <cstdio>
#include <iostream>

#include "basis/error.h"
#include "tools/brdf_export.h"
#include "tools/brdf_input.h"
#include "tools/cli/command.h"

namespace zbrdf::cli {
namespace {

int RunExport(const std::vector<std::string>& args) {
  CommandLine cl("export",
                 "Writes a BRDF in a format renderers and viewers load (docs/formats.md):\n"
                 "  merl           MERL .binary table (MERL's reader, BRDF Explorer, Mitsuba 0.6)\n"
                 "  rgl            RGL .bsdf (Dupuy & Jakob 2018): Mitsuba 3's and pbrt-v4's\n"
                 "                 `measured` material, with scene snippets next to it\n"
                 "  sh             zbrdf SH file (from a converted session)\n"
                 "  dbrdf          zbrdf D-BRDF file (from a fitted session or a dbrdf: spec)\n"
                 "  brdf-explorer  Disney BRDF Explorer .brdf (analytic GLSL; D-BRDF with its\n"
                 "                 p(h) table, measured networks with their weights)\n"
                 "NaN or negative f_r values make the export fail with their count; "
                 "--clamp-invalid\nwrites them as 0 instead and reports the count.");
  cl.Positional("INPUT", "session folder, file or material spec (see below)")
      .Option("format", "F", "merl, rgl, sh, dbrdf or brdf-explorer")
      .Option("out", "FILE", "the file to write")
      .Flag("clamp-invalid", "write NaN and negative f_r as 0 (reported) instead of failing")
      .Option("rgl-variant", "V",
              "rgl: rgb (Mitsuba 3 RGB variants), spectral (pbrt-v4) or both; with both the "
              "spectral file is OUT with .spectral.bsdf",
              "both")
      .Option("scene", "S", "rgl: scene snippets next to the export: mitsuba, pbrt, both or none",
              "both")
      .Option("rgl-theta", "N", "rgl: elevation nodes of the view direction", "16")
      .Option("rgl-phi", "N", "rgl: azimuth nodes of the view direction (anisotropic inputs)", "25")
      .Option("rgl-samples", "N", "rgl: sample grid per view direction (N x N)", "48")
      .Flag("json", "print the export report as JSON")
      .Epilog(
          "Examples:\n"
          "  zbrdf export results/blue-acrylic --format rgl --out blue-acrylic.bsdf\n"
          "  zbrdf export merl:gold-metallic-paint --format merl --out gold.binary\n"
          "  zbrdf export ggx:alpha=0.2,F0=0.9 --format brdf-explorer --out ggx.brdf\n\n" +
          BrdfInputHelp());
  if (!cl.Parse(args)) return 0;
  if (!cl.Has("format"))
    throw InputError("--format is required (merl, rgl, sh, dbrdf, brdf-explorer)");
  if (!cl.Has("out")) throw InputError("--out is required: the file to write");
  ExportOptions options;
  options.format = ParseExportFormat(cl.Get("format"));
  options.out = cl.Get("out");
  options.clamp_invalid = cl.Has("clamp-invalid");
  const std::string variant = cl.Get("rgl-variant");
  if (variant == "rgb") {
    options.rgl_variant = ExportOptions::RglVariant::kRgb;
  } else if (variant == "spectral") {
    options.rgl_variant = ExportOptions::RglVariant::kSpectral;
  } else if (variant != "both") {
    throw InputError("--rgl-variant must be rgb, spectral or both (got '" + variant + "')");
  }
  const std::string scene = cl.Get("scene");
  const bool scene_given = std::find(args.begin(), args.end(), "--scene") != args.end() ||
                           std::any_of(args.begin(), args.end(), [](const std::string& a) {
                             return a.rfind("--scene=", 0) == 0;
                           });
  if (scene == "none") {
    options.scenes.clear();
  } else if (scene == "both") {
    options.scenes = {"mitsuba", "pbrt"};
  } else {
    options.scenes = {scene};
  }
  if (options.format != ExportFormat::kRgl) {
    if (scene_given && scene != "none") {
      throw InputError(
          "--scene: scene snippets go with --format rgl (Mitsuba 3 and pbrt-v4 read "
          "measured materials from .bsdf files)");
    }
    options.scenes.clear();
  } else {
    if (options.rgl_variant == ExportOptions::RglVariant::kRgb && !scene_given) {
      options.scenes = {"mitsuba"};
    }
    if (options.rgl_variant == ExportOptions::RglVariant::kSpectral && !scene_given) {
      options.scenes = {"pbrt"};
    }
  }
  options.rgl.theta_nodes = cl.GetInt("rgl-theta", 2, 180);
  options.rgl.phi_nodes = cl.GetInt("rgl-phi", 3, 360);
  options.rgl.sample_resolution = cl.GetInt("rgl-samples", 4, 256);
  const BrdfInput input = ResolveBrdfInput(cl.Positional(0));
  const ExportResult result = ExportBrdf(input, options);
  if (cl.Has("json")) {
    std::cout << result.report.dump(2) << "\n";
    return 0;
  }
  std::printf("exported %s as %s (%.2f s)\n", input.description.c_str(), cl.Get("format").c_str(),
              result.report["seconds"].get<double>());
  for (const std::string& file : result.files) std::printf("  %s\n", file.c_str());
  if (result.report.contains("values")) {
    const auto& v = result.report["values"];
    if (v["nan"].get<int64_t>() > 0 || v["negative"].get<int64_t>() > 0) {
      std::printf("  clamped to 0: %lld NaN and %lld negative values of %lld\n",
                  static_cast<long long>(v["nan"].get<int64_t>()),
                  static_cast<long long>(v["negative"].get<int64_t>()),
                  static_cast<long long>(v["values"].get<int64_t>()));
    }
  }
  if (result.report.contains("spectral")) {
    const auto& s = result.report["spectral"];
    if (s["out_of_gamut_nodes"].get<int64_t>() > 0) {
      std::printf(
          "  spectral variant: %lld nodes outside the upsampling gamut (largest relative "
          "RGB change %.3g)\n",
          static_cast<long long>(s["out_of_gamut_nodes"].get<int64_t>()),
          s["max_relative_gamut_error"].get<double>());
    }
  }
  return 0;
}

const CommandRegistration kExportCommand(
    {"export", "write a BRDF as MERL, RGL .bsdf, SH, D-BRDF or BRDF Explorer file", RunExport});

}  // namespace
}  // namespace zbrdf::cli
