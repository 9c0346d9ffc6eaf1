// The INPUT argument of `zbrdf export`, `eval`, `preview`, `plot` and `compare`: anything that
// names a BRDF, resolved in one place.
//
//   a session folder     its D-BRDF fit, else its analytic fit, else its SH conversion
//                        (acquisition/session_brdf.h)
//   a file               any format brdf/brdf_file.h reads: .exr (SH or D-BRDF), .binary
//                        (MERL), .json (network or fit), .bsdf (RGL), .brdf (BRDF Explorer)
//   anything else        a material spec (lambert:0.18, ggx:alpha=0.2, merl:blue-acrylic, ...)
// An existing path wins over a spec of the same spelling.
#pragma once

#include <memory>
#include <string>

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

// The INPUT paragraph for --help.
std::string BrdfInputHelp();

}  // namespace zbrdf
