// A BRDF from a file of any format zbrdf reads (docs/formats.md), told apart by its extension:
//
//   NAME.exr     a zbrdf SH file, D-BRDF file or tabulated BRDF (fit-prior.exr), told apart by
//                its zbrdf.format header
//   NAME.binary  a MERL table
//   NAME.json    a network file ("format": "nbrdf-mlp-v1") or a fit report holding a material
//                spec (fit-<model>.json as zbrdf fit writes it)
//   NAME.bsdf    an RGL file (rgb or spectral)
//   NAME.brdf    a BRDF Explorer file written by zbrdf export
#pragma once

#include <memory>
#include <string>

#include "brdf/brdf.h"

namespace zbrdf {

struct BrdfFile {
  std::shared_ptr<const Brdf> brdf;
  // "dbrdf-file", "tabulated-file", "sh-file", "fit-json", "merl-file", "network-file", "rgl-file",
  // "brdf-explorer-file".
  std::string kind;
  std::string path;         // the file read
  std::string description;  // one line for people: what was read from where
};

// Throws InputError naming the file: an unknown extension, a file that cannot be read or is
// malformed, an OpenEXR file that holds no BRDF (zonal coefficients say how to convert them), a
// fit report that says nothing was fitted.
BrdfFile ReadBrdfFile(const std::string& path);

// The zbrdf.format attribute of an OpenEXR file's first part ("" if it has none). Throws
// InputError naming the file if it is not OpenEXR.
std::string ExrFormatOf(const std::string& path);

}  // namespace zbrdf
