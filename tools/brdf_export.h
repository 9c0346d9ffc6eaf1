// `zbrdf export`: a BRDF written in a format renderers and viewers load (docs/formats.md), with
// scene snippets that use it.
//
//   merl            MERL .binary (brdf/merl_export.h)
//   rgl             RGL .bsdf: the rgb variant (Mitsuba 3 RGB variants) and/or the spectral
//                   variant (pbrt-v4, Mitsuba 3 spectral variants) (brdf/rgl_bsdf.h)
//   sh              zbrdf SH file (brdf/sh_file.h), from SH data (a converted session or an
//                   sh.exr)
//   dbrdf           zbrdf D-BRDF file (brdf/dbrdf_file.h), from a D-BRDF (a fitted session,
//                   a fit-dbrdf.exr or a dbrdf: spec)
//   brdf-explorer   Disney BRDF Explorer .brdf (brdf/brdf_explorer.h)
// Scene snippets (rgl only): NAME.mitsuba.xml (Mitsuba 3, `measured` BSDF on a sphere) and
// NAME.pbrt (pbrt-v4, Material "measured"), next to the export.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "brdf/rgl_bsdf.h"
#include "tools/brdf_input.h"

namespace zbrdf {

enum class ExportFormat { kMerl, kRgl, kSh, kDBrdf, kBrdfExplorer };

// "merl", "rgl", "sh", "dbrdf", "brdf-explorer" -> format; throws InputError listing them.
ExportFormat ParseExportFormat(const std::string& name);
std::string ExportFormatName(ExportFormat format);

struct ExportOptions {
  ExportFormat format = ExportFormat::kMerl;
  std::string out;             // the file to write
  bool clamp_invalid = false;  // NaN / negative f_r -> 0 (reported) instead of failing
  // rgl: which variants; with both, the spectral file is OUT with ".spectral.bsdf" for ".bsdf".
  enum class RglVariant { kRgb, kSpectral, kBoth } rgl_variant = RglVariant::kBoth;
  RglExportOptions rgl;
  // Scene snippets to write next to an rgl export: "mitsuba", "pbrt".
  std::vector<std::string> scenes = {"mitsuba", "pbrt"};

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct ExportResult {
  std::vector<std::string> files;  // everything written
  nlohmann::json report;           // what was done: format, input, counts, timings
};

// Writes the export; nothing is written when it fails (invalid values without clamping, an
// input the format cannot hold). Throws InputError saying what to do instead.
ExportResult ExportBrdf(const BrdfInput& input, const ExportOptions& options);

// The scene snippets' text. bsdf_file: the .bsdf file name as the scene should reference it.
std::string MitsubaSceneSnippet(const std::string& bsdf_file, const std::string& what);
std::string PbrtSceneSnippet(const std::string& bsdf_file, const std::string& what);

}  // namespace zbrdf
