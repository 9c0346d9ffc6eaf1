#include "tools/brdf_input.h"

#include <filesystem>

#include "acquisition/session_brdf.h"
#include "basis/error.h"
#include "brdf/brdf_file.h"
#include "brdf/material_spec.h"

namespace zbrdf {
namespace {

namespace fs = std::filesystem;

BrdfInput FromFile(const std::string& path) {
  const BrdfFile file = ReadBrdfFile(path);
  BrdfInput in;
  in.brdf = file.brdf;
  in.kind = file.kind;
  in.description = file.description;
  in.source = path;
  in.name = fs::path(path).stem().string();
  return in;
}

}  // namespace

BrdfInput ResolveBrdfInput(const std::string& input) {
  if (input.empty()) throw InputError("INPUT is empty: give a session folder, a file or a spec");
  std::error_code error;
  if (fs::is_directory(input, error)) {
    const BrdfFile file = ReadSessionBrdf(input);
    BrdfInput in;
    in.brdf = file.brdf;
    in.source = file.path;
    in.kind = "session";
    in.session_dir = input;
    in.name = fs::path(input).filename().string();
    if (in.name.empty()) in.name = fs::path(input).parent_path().filename().string();
    in.description = "session " + input + ": " + file.description;
    return in;
  }
  if (fs::is_regular_file(input, error)) return FromFile(input);
  // "file:PATH", the Spec() of file-backed BRDFs, also for the kinds MakeBrdf does not read.
  if (input.rfind("file:", 0) == 0 && fs::is_regular_file(input.substr(5), error)) {
    return FromFile(input.substr(5));
  }
  if (input.rfind("file:", 0) == 0 && fs::is_directory(input.substr(5), error)) {
    throw InputError("INPUT '" + input + "': " + input.substr(5) +
                     " is a folder; file: takes a MERL .binary or a network .json file (give a "
                     "session folder without file:)");
  }
  BrdfInput in;
  try {
    in.brdf = MakeBrdf(input);
  } catch (const InputError& e) {
    const bool looks_like_path = input.find('/') != std::string::npos ||
                                 fs::path(input).has_extension() ||
                                 input.find(':') == std::string::npos;
    if (looks_like_path) {
      throw InputError("INPUT '" + input +
                       "' is not an existing file or folder, and not a material spec: " + e.what());
    }
    throw;
  }
  in.kind = "spec";
  in.source = input;
  in.name = MaterialShortName(input);
  in.description = "material " + in.brdf->Spec();
  return in;
}

std::string BrdfInputHelp() {
  return "INPUT is any of:\n"
         "  SESSION/       a session folder: its D-BRDF fit (fit-dbrdf.exr), else its analytic "
         "fit\n"
         "                 (fit-<model>.json), else its SH conversion (sh.exr, sh-<target>.exr)\n"
         "  FILE.exr       a zbrdf SH file (sh-<target>.exr) or D-BRDF file (fit-dbrdf.exr)\n"
         "  FILE.binary    a MERL table           FILE.json   a network file or an analytic fit\n"
         "  FILE.bsdf      an RGL file (rgb or spectral)   FILE.brdf   a BRDF Explorer file from\n"
         "                 zbrdf export\n"
         "  SPEC           a material spec, e.g. lambert:0.18, ggx:alpha=0.2,F0=0.04,\n"
         "                 merl:blue-acrylic (zbrdf eval --help lists them all)\n";
}

}  // namespace zbrdf
