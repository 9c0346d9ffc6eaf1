// Shared by the tools tests: fixed-seed random numbers and directions, per-test temporary
// folders, running the zbrdf binary.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <string>

#include "tests/brdf/brdf_checks.h"
#include "tests/test_files.h"

namespace zbrdf::testing {

// Rng and RandomUpperDirection come from tests/brdf/brdf_checks.h, TempDir, ReadFile and
// WriteFile from tests/test_files.h.

// The zbrdf binary the tests run: the build's, or $ZBRDF_TEST_BINARY (to run the command-line
// tests against another build, e.g. an earlier version's).
inline std::string ZbrdfBinary() {
  const char* binary = std::getenv("ZBRDF_TEST_BINARY");
  return binary != nullptr ? binary : std::string(ZBRDF_BINARY_DIR) + "/zbrdf";
}

// Runs `zbrdf ARGS` with the shell; returns its exit status. Output goes to the given files.
inline int RunZbrdf(const std::string& args, const std::string& stdout_file = "/dev/null",
                    const std::string& stderr_file = "/dev/null") {
  const std::string command = ZbrdfBinary() + " " + args + " >" + stdout_file + " 2>" + stderr_file;
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace zbrdf::testing
