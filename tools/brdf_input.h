// The INPUT argument of `zbrdf export`, `eval`, `preview`, `plot` and `compare`: anything that
// names a BRDF, resolved in one place.
//
//   a session folder     its D-BRDF fit (fit-dbrdf.exr), else its analytic fit (fit-<model>.json,
//                        the first by name that holds a model), else its SH conversion (sh.exr,
//                        else sh-<target>.exr as zbrdf convert names it)
//   NAME.exr             a zbrdf SH file or D-BRDF file, told apart by the zbrdf.format header
//   NAME.binary          a MERL table                NAME.json   a network file or a fit
//   NAME.bsdf            an RGL file (rgb or spectral)   NAME.brdf  a BRDF Explorer file
//                        written by zbrdf export
//   anything else        a material spec (lambert:0.18, ggx:alpha=0.2, merl:blue-acrylic, ...)
// An existing path wins over a spec of the same spelling.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "brdf/brdf.h"

namespace zbrdf {

struct BrdfInput {
  std::shared_ptr<const Brdf> brdf;
  // "spec", "session", "dbrdf-file", "sh-file", "fit-json", "merl-file", "network-file",
  // "rgl-file", "brdf-explorer-file".
  std::string kind;
  std::string source;       // the file the BRDF was read from, or the spec
  std::string session_dir;  // when INPUT was a session folder
  std::string name;         // a short name for titles and file names ("blue-acrylic")
  std::string description;  // one line for people: what was loaded from where
};

// Throws InputError naming INPUT and what was tried: a session without fit or conversion says
// which files it looked for and which command makes them; a string that is neither an existing
// path nor a valid spec reports the spec's error.
BrdfInput ResolveBrdfInput(const std::string& input);

// The files of a session folder that hold a BRDF, in the order ResolveBrdfInput prefers them
// (only those that exist).
std::vector<std::string> SessionBrdfFiles(const std::string& session_dir);
// Its SH conversions: sh.exr, then sh-<target>.exr by name.
std::vector<std::string> SessionShFiles(const std::string& session_dir);

// The INPUT paragraph for --help.
std::string BrdfInputHelp();

}  // namespace zbrdf
