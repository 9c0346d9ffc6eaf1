// The BRDF a session folder holds once `zbrdf fit` or `zbrdf convert` has run on it
// (docs/session-folder.md): the fit `zbrdf fit --model auto` recommended (fit-auto.json), else
// its prior fit (fit-prior.exr), else its D-BRDF fit (fit-dbrdf.exr), else its analytic fit
// (fit-<model>.json, the first by name that holds a model), else its SH conversion (sh.exr, else
// sh-<target>.exr as zbrdf convert names it).
#pragma once

#include <string>
#include <vector>

#include "brdf/brdf_file.h"

namespace zbrdf {

// The files of a session folder that hold a BRDF, in the order ReadSessionBrdf prefers them
// (only those that exist).
std::vector<std::string> SessionBrdfFiles(const std::string& session_dir);
// Its SH conversions: sh.exr, then sh-<target>.exr by name.
std::vector<std::string> SessionShFiles(const std::string& session_dir);

// The first of SessionBrdfFiles that holds a model; a fit report without one (nothing was
// fitted) is skipped. Throws InputError if there is none, naming the files looked for and the
// commands that write them (and, for a simulated session, its true material).
BrdfFile ReadSessionBrdf(const std::string& session_dir);

}  // namespace zbrdf
