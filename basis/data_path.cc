#include "basis/data_path.h"

#include <cstdlib>
#include <filesystem>

#include "basis/error.h"

#ifndef ZBRDF_SOURCE_DATA_DIR
#error "ZBRDF_SOURCE_DATA_DIR must be defined by the build"
#endif

namespace zbrdf {
namespace {

// PREFIX/share/zbrdf of an installed executable PREFIX/bin/zbrdf, or "" when the running
// executable has no such folder beside it (a build tree, a test binary). Linux: /proc/self/exe
// names the executable itself, whatever the current folder and argv[0] are.
std::string InstalledDataRoot() {
  const std::string exe = ExecutablePath();
  if (exe.empty()) return "";
  std::error_code error;
  const std::filesystem::path root =
      std::filesystem::path(exe).parent_path().parent_path() / "share" / "zbrdf";
  return std::filesystem::is_directory(root / "data", error) ? root.string() : "";
}

}  // namespace

std::string ExecutablePath() {
  std::error_code error;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::string() : exe.string();
}

std::string DataRoot() {
  if (const char* env = std::getenv("ZBRDF_DATA_DIR"); env != nullptr && *env != '\0') {
    if (!std::filesystem::is_directory(env)) {
      throw InputError(std::string("ZBRDF_DATA_DIR=") + env +
                       " is not a folder; point it at the zbrdf source tree or an install's "
                       "share/zbrdf (either holds data/), or unset it");
    }
    return env;
  }
  // The executable does not move while it runs: look once.
  static const std::string installed = InstalledDataRoot();
  if (!installed.empty()) return installed;
  const std::string built_from = ZBRDF_SOURCE_DATA_DIR;
  if (!std::filesystem::is_directory(built_from + "/data")) {
    throw InputError("zbrdf's data folder " + built_from +
                     "/data is missing and no PREFIX/share/zbrdf/data lies beside the zbrdf "
                     "executable; install zbrdf (cmake --install) or set ZBRDF_DATA_DIR to a "
                     "zbrdf source tree");
  }
  return built_from;
}

std::string DataPath(const std::string& relative) { return DataRoot() + "/" + relative; }

}  // namespace zbrdf
