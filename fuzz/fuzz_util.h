// Helpers shared by the libFuzzer targets (docs/fuzzing.md).
//
// A target feeds its input to one reader. The errors zbrdf throws for bad input (InputError,
// DeviceError, NumericalError) are the expected outcome; anything else escaping the reader (an
// InternalError from ZBRDF_ASSERT, std::bad_alloc, nlohmann::json's out_of_range, ...) reaches
// std::terminate and libFuzzer reports it as a crash, like sanitizer findings and timeouts.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "basis/error.h"

namespace zbrdf::fuzz {

// A folder of this process's own, created on first use, reused for every input and removed when
// the process exits normally: readers that take a path read the input from a file in it. It is
// in memory (/dev/shm, a tmpfs) where the machine has one: writing and reading an input there
// costs ~25 us, against ~400 us in /tmp on a CI machine's ext4 mounted with `discard` (every
// rewrite frees blocks), which was most of the time of some targets (docs/fuzzing.md). Otherwise
// it is in the temporary folder (TMPDIR, else /tmp).
inline std::string ScratchParent() {
  if (::access("/dev/shm", W_OK | X_OK) == 0 && std::filesystem::is_directory("/dev/shm")) {
    return "/dev/shm";
  }
  return std::filesystem::temp_directory_path().string();
}

inline const std::string& ScratchDir() {
  static const std::string dir = [] {
    const std::string d = ScratchParent() + "/zbrdf-fuzz-" + std::to_string(::getpid());
    std::filesystem::create_directories(d);
    // A copy that outlives `dir` (destroyed before atexit handlers registered earlier run).
    static const char* const cleanup = strdup(d.c_str());
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(cleanup, ignored);
    });
    return d;
  }();
  return dir;
}

// Writes `size` bytes to ScratchDir()/name and returns the path.
inline std::string WriteScratchFile(const std::string& name, const uint8_t* data, size_t size) {
  const std::string path = ScratchDir() + "/" + name;
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr || (size > 0 && std::fwrite(data, 1, size, file) != size) ||
      std::fclose(file) != 0) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();  // the machine's problem, not the reader's: stop rather than report nothing
  }
  return path;
}

// Runs `read`, treating zbrdf's input, device and numerical errors as the expected rejection of
// bad input. Everything else propagates (and crashes the fuzzer, which reports the input).
template <typename Read>
void ExpectOnlyInputErrors(Read&& read) {
  try {
    read();
  } catch (const InputError&) {
  } catch (const DeviceError&) {
  } catch (const NumericalError&) {
  }
}

}  // namespace zbrdf::fuzz
