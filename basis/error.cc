#include "basis/error.h"

namespace zbrdf {

void ThrowAssertion(const char* condition, const char* file, int line,
                    const std::string& message) {
  throw InternalError(std::string("internal error (please report): ") + message + " [" +
                      condition + " failed at " + file + ":" + std::to_string(line) + "]");
}

}  // namespace zbrdf
