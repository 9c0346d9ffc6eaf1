// What the exporters do with BRDF values a file must not hold: NaN (or infinite) and negative
// f_r. They are counted, and the export fails with the counts, unless the user asked for them
// to be clamped to 0 (--clamp-invalid), in which case the counts go into the export report.
// Never written silently.
#pragma once

#include <cstdint>
#include <string>

#include "basis/vec3.h"

namespace zbrdf {

struct ValueCheck {
  bool clamp = false;
  int64_t values = 0;    // channel values checked
  int64_t nan = 0;       // NaN or infinite channel values
  int64_t negative = 0;  // negative channel values

  // Counts the invalid channels of v and returns v with them replaced by 0 (what is written
  // when clamping; an export that does not clamp fails in Finish() before anything is written).
  Rgb Apply(const Rgb& v);
  double Apply(double v);
  // Adds another check's counts (for per-thread checks).
  void Merge(const ValueCheck& other);
  // Throws InputError naming `what` with the counts when there are invalid values and clamp is
  // off, saying to check the input or pass --clamp-invalid.
  void Finish(const std::string& what) const;
  // "no invalid values" or "clamped 12 NaN and 40 negative values of 1234567 to 0".
  std::string Summary() const;
};

}  // namespace zbrdf
