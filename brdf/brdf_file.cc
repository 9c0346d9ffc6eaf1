#include "brdf/brdf_file.h"

#include <ImfHeader.h>
#include <ImfMultiPartInputFile.h>
#include <ImfStringAttribute.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "basis/error.h"
#include "basis/strings.h"
#include "brdf/brdf_explorer.h"
#include "brdf/dbrdf_file.h"
#include "brdf/material_spec.h"
#include "brdf/merl_table.h"
#include "brdf/nbrdf.h"
#include "brdf/rgl_bsdf.h"
#include "brdf/exr_header.h"
#include "brdf/sh_brdf.h"
#include "brdf/sh_file.h"
#include "brdf/tabulated_file.h"

namespace zbrdf {
namespace {

namespace fs = std::filesystem;

}  // namespace

std::string ExrFormatOf(const std::string& path) {
  CheckExrHeaderSizes(path, path);
  try {
    Imf::MultiPartInputFile file(path.c_str());
    const auto* format = file.header(0).findTypedAttribute<Imf::StringAttribute>("zbrdf.format");
    return format ? format->value() : "";
  } catch (const std::exception& e) {
    throw InputError("cannot read " + path + " as OpenEXR: " + e.what());
  }
}

namespace {

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

BrdfFile FromExr(const std::string& path) {
  BrdfFile in;
  const std::string format = ExrFormatOf(path);
  if (format == "zbrdf-dbrdf-v1") {
    in.brdf = ReadDBrdfFile(path);
    in.kind = "dbrdf-file";
    in.description = "D-BRDF fit " + path;
  } else if (format == "zbrdf-tabulated-v1") {
    in.brdf = ReadTabulatedFile(path);
    in.kind = "tabulated-file";
    in.description = "tabulated BRDF " + path;
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
                     "'; expected zbrdf-dbrdf-v1, zbrdf-tabulated-v1 or zbrdf-sh-v1)");
  }
  return in;
}

BrdfFile FromJson(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw InputError("cannot open " + path + "; check the path");
  const nlohmann::json j = nlohmann::json::parse(file, nullptr, false);
  if (j.is_discarded()) throw InputError(path + " is not valid JSON");
  BrdfFile in;
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

}  // namespace

BrdfFile ReadBrdfFile(const std::string& path) {
  const std::string ext = AsciiLower(fs::path(path).extension().string());
  BrdfFile in;
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
  in.path = path;
  return in;
}

}  // namespace zbrdf
