// Files written whole or not at all: a crash, Ctrl-C or a full disk leaves the previous file (or
// none), never a truncated one. Everything zbrdf writes to be read back later goes through here:
// session and calibration folders, exports, reports, pictures.
#pragma once

#include <string>

namespace zbrdf {

// Writes bytes to path via a temporary file in the same folder, fsync, rename, then a sync of the
// folder. Throws InputError naming the file if any step fails (the temporary file is removed).
void WriteFileAtomically(const std::string& path, const std::string& bytes);

}  // namespace zbrdf
