// Integers from JSON files a user may have edited or damaged (session.json, the journal).
//
// nlohmann's get<int>() converts a floating-point value with a static_cast, which is undefined
// behaviour when the value is out of range (found by fuzz/session_fuzz: "order": 1e102). This
// reads integers and integral floating-point values and throws InputError for anything else.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "basis/error.h"

namespace zbrdf {

template <typename Int>
Int JsonInteger(const nlohmann::json& j, const std::string& what) {
  constexpr Int lo = std::numeric_limits<Int>::min(), hi = std::numeric_limits<Int>::max();
  if (j.is_number_unsigned()) {
    const uint64_t v = j.get<uint64_t>();
    if (v <= static_cast<uint64_t>(hi)) return static_cast<Int>(v);
  } else if (j.is_number_integer()) {
    const int64_t v = j.get<int64_t>();
    const bool fits = (v >= 0) ? static_cast<uint64_t>(v) <= static_cast<uint64_t>(hi)
                               : (lo < 0 && v >= static_cast<int64_t>(lo));
    if (fits) return static_cast<Int>(v);
  } else if (j.is_number_float()) {
    const double v = j.get<double>();
    // hi + 1.0 is a power of two, exact in double; the casts below are in range.
    if (std::isfinite(v) && v == std::floor(v) && v >= static_cast<double>(lo) &&
        v < static_cast<double>(hi) + 1.0) {
      return static_cast<Int>(v);
    }
  }
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on string&& + literal chains.
  std::string message = what;
  message += " must be an integer in [";
  message += std::to_string(lo);
  message += ", ";
  message += std::to_string(hi);
  message += "], got ";
  message += j.dump();
  throw InputError(message);
}

// j.at(key) as an integer; InputError naming `where` and the key if it is missing (or j is not
// an object).
template <typename Int>
Int JsonIntegerAt(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) {
    throw InputError(where + " field '" + key + "' is missing");
  }
  return JsonInteger<Int>(j.at(key), where + " field '" + key + "'");
}

}  // namespace zbrdf
