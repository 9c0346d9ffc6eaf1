// Shared by the tools tests: fixed-seed random numbers and directions, per-test temporary
// folders, running the zbrdf binary.
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "basis/vec3.h"
#include "tests/fitting/brdf_checks.h"

namespace zbrdf::testing {

// Rng and RandomUpperDirection come from tests/fitting/brdf_checks.h.

// A fresh folder under the temp directory, removed by the destructor.
class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_((std::filesystem::temp_directory_path() /
               ("zbrdf_tools_" + std::to_string(::getpid()) + "_" + name))
                  .string()) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code error;
    std::filesystem::remove_all(path_, error);
  }
  const std::string& path() const { return path_; }
  std::string File(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

inline std::string ReadFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

inline void WriteFile(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// Runs `zbrdf ARGS` with the shell; returns its exit status. Output goes to the given files.
inline int RunZbrdf(const std::string& args, const std::string& stdout_file = "/dev/null",
                    const std::string& stderr_file = "/dev/null") {
  const std::string command =
      std::string(ZBRDF_BINARY_DIR) + "/zbrdf " + args + " >" + stdout_file + " 2>" + stderr_file;
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace zbrdf::testing
