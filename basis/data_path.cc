#include "basis/data_path.h"

#include <cstdlib>
#include <filesystem>

#include "basis/error.h"

#ifndef ZBRDF_SOURCE_DATA_DIR
#error "ZBRDF_SOURCE_DATA_DIR must be defined by the build"
#endif

namespace zbrdf {

std::string DataRoot() {
  if (const char* env = std::getenv("ZBRDF_DATA_DIR"); env != nullptr && *env != '\0') {
    if (!std::filesystem::is_directory(env)) {
      throw InputError(std::string("ZBRDF_DATA_DIR=") + env +
                       " is not a folder; point it at the zbrdf source tree (it holds data/) "
                       "or unset it");
    }
    return env;
  }
  const std::string built_from = ZBRDF_SOURCE_DATA_DIR;
  if (!std::filesystem::is_directory(built_from + "/data")) {
    throw InputError("zbrdf's data folder " + built_from +
                     "/data is missing; set ZBRDF_DATA_DIR to a zbrdf source tree");
  }
  return built_from;
}

std::string DataPath(const std::string& relative) { return DataRoot() + "/" + relative; }

}  // namespace zbrdf
