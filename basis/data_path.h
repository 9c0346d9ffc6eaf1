// Location of the data bundled with zbrdf (measured materials, priors, baselines, rig files).
#pragma once

#include <string>

namespace zbrdf {

// The folder that holds `data/` and `rig/rigs/`, the first of:
//   1. $ZBRDF_DATA_DIR, if set (a source tree, or an install's PREFIX/share/zbrdf);
//   2. <folder of the running executable>/../share/zbrdf, if it holds data/: the layout
//      `cmake --install` makes (PREFIX/bin/zbrdf, PREFIX/share/zbrdf/data), so an installed zbrdf
//      reads its own copy even where the source tree it was built from still exists;
//   3. the source tree zbrdf was built from (a binary in the build tree).
// Throws InputError if none exists, saying how to fix it.
std::string DataRoot();

// DataRoot() + "/" + relative.
std::string DataPath(const std::string& relative);

// The running executable's absolute path (Linux: /proc/self/exe, whatever the current folder
// and argv[0] are), or "" if it cannot be read.
std::string ExecutablePath();

}  // namespace zbrdf
