// Location of the data bundled with zbrdf (measured materials, rig files).
#pragma once

#include <string>

namespace zbrdf {

// The folder that holds `data/` and `rig/rigs/`: $ZBRDF_DATA_DIR if set, else the source
// tree zbrdf was built from. Throws InputError if neither exists, saying how to fix it.
std::string DataRoot();

// DataRoot() + "/" + relative.
std::string DataPath(const std::string& relative);

}  // namespace zbrdf
