// Error types shared by every zbrdf library.
//
// Library boundaries throw one of three kinds, so that the CLI (and any caller) can say what
// went wrong and what to do:
//   InputError      user input is wrong: a flag, a rig file, a session folder, a frame file.
//   DeviceError     a camera or projector failed or is missing.
//   NumericalError  a computation cannot give a trustworthy answer (singular system, NaN data).
// Messages name the thing (file, field, device, feature) and say what to do about it.
// Internal invariants use ZBRDF_ASSERT, which stays on in Release builds and throws
// (never aborts), so that a bug cannot destroy data already captured.
#pragma once

#include <stdexcept>
#include <string>

namespace zbrdf {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class InputError : public Error {
 public:
  using Error::Error;
};

class DeviceError : public Error {
 public:
  using Error::Error;
};

class NumericalError : public Error {
 public:
  using Error::Error;
};

// Thrown by ZBRDF_ASSERT: a broken internal invariant, i.e. a bug in zbrdf.
class InternalError : public Error {
 public:
  using Error::Error;
};

[[noreturn]] void ThrowAssertion(const char* condition, const char* file, int line,
                                 const std::string& message);

}  // namespace zbrdf

#define ZBRDF_ASSERT(condition, message)                                    \
  do {                                                                      \
    if (!(condition)) ::zbrdf::ThrowAssertion(#condition, __FILE__, __LINE__, (message)); \
  } while (0)
