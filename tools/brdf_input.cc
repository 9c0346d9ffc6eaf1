#include "tools/brdf_input.h"

#include <ImfHeader.h>
#include <ImfMultiPartInputFile.h>
#include <ImfStringAttribute.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "basis/error.h"
#include "brdf/brdf_explorer.h"
#include "brdf/dbrdf_file.h"
#include "brdf/material_spec.h"
#include "brdf/merl_table.h"
#include "brdf/nbrdf.h"
#include "brdf/rgl_bsdf.h"
#include "brdf/sh_brdf.h"
#include "brdf/sh_file.h"

namespace zbrdf {
namespace {

namespace fs = std::filesystem;

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string Stem(const std::string& path) { return fs::path(path).stem().string(); }

// The zbrdf.format attribute of an OpenEXR file's first part, "" if it has none.
std::string ExrFormat(const std::string& path) {
  try {
    Imf::MultiPartInputFile file(path.c_str());
    const auto* format = file.header(0).findTypedAttribute<Imf::StringAttribute>("zbrdf.format");
    return format ? format->value() : "";
  } catch (const std::exception& e) {
    throw InputError("cannot read " + path + " as OpenEXR: " + e.what());
  }
}

// A fit-<model>.json: a material spec, as a JSON string or in a "spec", "material_spec" or
// "material" field.
std::string SpecFromFitJson(const nlohmann::json& j) {
  if (j.is_string()) return j.get<std::string>();
  if (j.is_object()) {
    for (const char* key : {"spec", "material_spec", "material"}) {
      if (j.contains(key) && j[key].is_string()) return j[key].get<std::string>();
    }
  }
  return "";
}

BrdfInput FromExr(const std::string& path) {
  BrdfInput in;
  in.source = path;
  const std::string format = ExrFormat(path);
  if (format == "zbrdf-dbrdf-v1") {
    in.brdf = ReadDBrdfFile(path);
    in.kind = "dbrdf-file";
    in.description = "D-BRDF fit " + path;
  } else if (format == "zbrdf-sh-v1") {
    in.brdf = std::make_shared<ShBrdf>(ReadShFile(path), path);
    in.kind = "sh-file";
    in.description = "SH conversion " + path;
  } else if (format == "zbrdf-zonal-v1") {
    throw InputError(
        path +
        " holds zonal coefficients, not a BRDF: convert it first (zbrdf convert "
        "writes sh-<target>.exr; zbrdf fit writes fit-dbrdf.exr) and give that file or the "
        "session folder");
  } else {
    throw InputError(path + " is not a zbrdf BRDF file (its zbrdf.format is '" + format +
                     "'; expected zbrdf-dbrdf-v1 or zbrdf-sh-v1)");
  }
  return in;
}

BrdfInput FromJson(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw InputError("cannot open " + path + "; check the path");
  const nlohmann::json j = nlohmann::json::parse(file, nullptr, false);
  if (j.is_discarded()) throw InputError(path + " is not valid JSON");
  BrdfInput in;
  in.source = path;
  if (j.is_object() && j.contains("format") && j["format"] == "nbrdf-mlp-v1") {
    in.brdf = NbrdfBrdf::FromFile(path);
    in.kind = "network-file";
    in.description = "measured network " + path;
    return in;
  }
  if (j.is_object() && j.contains("fitted") && j["fitted"].is_boolean() &&
      !j["fitted"].get<bool>()) {
    throw InputError(path + " reports that nothing was fitted (see its conditions)");
  }
  const std::string spec = SpecFromFitJson(j);
  if (spec.empty()) {
    throw InputError(path +
                     " is neither a network file (\"format\": \"nbrdf-mlp-v1\") nor a fit (a "
                     "\"spec\" field holding a material spec)");
  }
  in.brdf = MakeBrdf(spec);
  in.kind = "fit-json";
  in.description = "fit " + path + " (" + in.brdf->Spec() + ")";
  return in;
}

BrdfInput FromFile(const std::string& path) {
  const std::string ext = Lower(fs::path(path).extension().string());
  BrdfInput in;
  if (ext == ".exr") {
    in = FromExr(path);
  } else if (ext == ".json") {
    in = FromJson(path);
  } else if (ext == ".binary") {
    in.brdf = MerlBrdf::FromFile(path);
    in.kind = "merl-file";
    in.description = "MERL table " + path;
  } else if (ext == ".bsdf") {
    in.brdf = RglBrdf::FromFile(path);
    in.kind = "rgl-file";
    in.description = "RGL file " + path;
  } else if (ext == ".brdf") {
    in.brdf = ReadBrdfExplorerFile(path);
    in.kind = "brdf-explorer-file";
    in.description = "BRDF Explorer file " + path + " (" + in.brdf->Spec() + ")";
  } else {
    throw InputError(path +
                     ": unknown kind of file (expected .exr, .json, .binary, .bsdf or .brdf, a "
                     "session folder, or a material spec)");
  }
  in.source = path;
  in.name = Stem(path);
  return in;
}

// A short name for a spec: "merl:blue-acrylic" -> "blue-acrylic", "ggx:alpha=0.2" -> "ggx".
std::string NameOfSpec(const std::string& spec) {
  const size_t colon = spec.find(':');
  if (colon == std::string::npos) return spec;
  const std::string model = Lower(spec.substr(0, colon));
  if (model == "merl") return spec.substr(colon + 1);
  if (model == "file") return Stem(spec.substr(colon + 1));
  return model;
}

}  // namespace

std::vector<std::string> SessionShFiles(const std::string& dir) {
  std::vector<std::string> files;
  if (fs::exists(dir + "/sh.exr")) files.push_back(dir + "/sh.exr");
  std::vector<std::string> targets;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("sh-", 0) == 0 && entry.path().extension() == ".exr") {
      targets.push_back(entry.path().string());
    }
  }
  std::sort(targets.begin(), targets.end());
  files.insert(files.end(), targets.begin(), targets.end());
  return files;
}

std::vector<std::string> SessionBrdfFiles(const std::string& dir) {
  std::vector<std::string> files;
  if (fs::exists(dir + "/fit-dbrdf.exr")) files.push_back(dir + "/fit-dbrdf.exr");
  std::vector<std::string> fits;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    // fit-dbrdf.json is the D-BRDF fit's report; the model itself is fit-dbrdf.exr.
    if (name.rfind("fit-", 0) == 0 && entry.path().extension() == ".json" &&
        name != "fit-dbrdf.json") {
      fits.push_back(entry.path().string());
    }
  }
  std::sort(fits.begin(), fits.end());
  files.insert(files.end(), fits.begin(), fits.end());
  const std::vector<std::string> sh = SessionShFiles(dir);
  files.insert(files.end(), sh.begin(), sh.end());
  return files;
}

BrdfInput ResolveBrdfInput(const std::string& input) {
  if (input.empty()) throw InputError("INPUT is empty: give a session folder, a file or a spec");
  std::error_code error;
  if (fs::is_directory(input, error)) {
    const std::vector<std::string> files = SessionBrdfFiles(input);
    if (files.empty()) {
      std::string hint;
      std::ifstream session(input + "/session.json");
      const nlohmann::json j = session ? nlohmann::json::parse(session, nullptr, false) : nullptr;
      if (j.is_object() && j.contains("material") && j["material"].is_string()) {
        hint = "; this simulated session's true material is " + j["material"].get<std::string>() +
               ", which can be given as INPUT itself";
      }
      throw InputError("session " + input +
                       " has no BRDF yet: none of fit-dbrdf.exr, fit-<model>.json, sh.exr or "
                       "sh-<target>.exr. Run "
                       "zbrdf fit (D-BRDF and analytic fits) or zbrdf convert (SH) on it first" +
                       hint);
    }
    // The first file that holds a model; a fit report without one (nothing was fitted) is
    // skipped.
    BrdfInput in;
    std::string skipped;
    for (const std::string& file : files) {
      try {
        in = FromFile(file);
        break;
      } catch (const InputError& e) {
        if (fs::path(file).extension() != ".json") throw;
        skipped += std::string(skipped.empty() ? "" : "; ") + e.what();
      }
    }
    if (!in.brdf) {
      throw InputError("session " + input + " has fit reports but no fitted model (" + skipped +
                       "); check zbrdf fit's conditions, or run zbrdf convert for SH");
    }
    in.kind = "session";
    in.session_dir = input;
    in.name = fs::path(input).filename().string();
    if (in.name.empty()) in.name = fs::path(input).parent_path().filename().string();
    in.description = "session " + input + ": " + in.description;
    return in;
  }
  if (fs::is_regular_file(input, error)) return FromFile(input);
  // "file:PATH", the Spec() of file-backed BRDFs, also for the kinds MakeBrdf does not read.
  if (input.rfind("file:", 0) == 0 && fs::is_regular_file(input.substr(5), error)) {
    return FromFile(input.substr(5));
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
  in.name = NameOfSpec(input);
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
