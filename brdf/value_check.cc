#include "brdf/value_check.h"

#include <cmath>

#include "basis/error.h"

namespace zbrdf {

double ValueCheck::Apply(double v) {
  ++values;
  if (!std::isfinite(v)) {
    ++nan;
    return 0.0;
  }
  if (v < 0) {
    ++negative;
    return 0.0;
  }
  return v;
}

Rgb ValueCheck::Apply(const Rgb& v) { return {Apply(v.r), Apply(v.g), Apply(v.b)}; }

void ValueCheck::Merge(const ValueCheck& other) {
  values += other.values;
  nan += other.nan;
  negative += other.negative;
}

void ValueCheck::Finish(const std::string& what) const {
  if (clamp || (nan == 0 && negative == 0)) return;
  throw InputError(what + ": the BRDF gave " + std::to_string(nan) + " NaN or infinite and " +
                   std::to_string(negative) + " negative values among " + std::to_string(values) +
                   " channel values; nothing was written. Check the input (a damaged fit or "
                   "table?), or pass --clamp-invalid to write them as 0 (the counts are reported)");
}

std::string ValueCheck::Summary() const {
  if (nan == 0 && negative == 0) return "no invalid values";
  return std::string(clamp ? "clamped " : "found ") + std::to_string(nan) + " NaN and " +
         std::to_string(negative) + " negative values of " + std::to_string(values) +
         (clamp ? " to 0" : "");
}

}  // namespace zbrdf
