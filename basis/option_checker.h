// Validation of the public *Options structs, in the spirit of Ceres's Options::IsValid(): every
// struct has `void Validate() const`, called where the options enter a library function, which
// checks every field, names each bad one with the values it accepts and the value it has, and
// throws one InputError listing them all:
//
//   HdrOptions: iterations must be in [1, 100] (got 0); safe_saturation_fraction must be in
//   (0, 1] (got 1.5)
//
// Options nested in other options report their problems under the field's name
// ("processing.hdr.iterations must be ...").
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "basis/error.h"

namespace zbrdf {

// Thrown by Validate(): an InputError whose problems() are the individual messages.
class InvalidOptions : public InputError {
 public:
  InvalidOptions(const std::string& options_name, std::vector<std::string> problems);
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  std::vector<std::string> problems_;
};

class OptionChecker {
 public:
  explicit OptionChecker(std::string options_name) : name_(std::move(options_name)) {}

  // "<field> must be in [lo, hi] (got v)" unless lo <= v <= hi; NaN is never in range.
  OptionChecker& InRange(const std::string& field, double value, double lo, double hi);
  // "<field> must be >= lo (got v)".
  OptionChecker& AtLeast(const std::string& field, double value, double lo);
  // "<field> must be > lo (got v)".
  OptionChecker& Above(const std::string& field, double value, double lo);
  // "<field> must be in (lo, hi] (got v)".
  OptionChecker& InRangeAbove(const std::string& field, double value, double lo, double hi);
  // "<field> must be in [lo, hi) (got v)".
  OptionChecker& InRangeBelow(const std::string& field, double value, double lo, double hi);
  // "<field> must be > 0 and finite (got v)".
  OptionChecker& Positive(const std::string& field, double value);
  // "<fields> must satisfy 0 <= theta_min < theta_max <= 90 deg (got a, b deg)": a zone
  // (basis/zone.h) from its bounds in radians.
  OptionChecker& ValidZone(const std::string& fields, double theta_min_rad, double theta_max_rad);
  // "<field> <problem>" unless ok: for rules the checks above do not express.
  OptionChecker& Require(bool ok, const std::string& field, const std::string& problem);
  // The problems of nested options, each under "<field>.".
  template <typename Options>
  OptionChecker& Nested(const std::string& field, const Options& options) {
    try {
      options.Validate();
    } catch (const InvalidOptions& e) {
      for (const std::string& p : e.problems()) problems_.push_back(field + "." + p);
    }
    return *this;
  }

  // Throws InvalidOptions listing every problem recorded; does nothing if there is none.
  void ThrowIfInvalid() const;

 private:
  std::string name_;
  std::vector<std::string> problems_;
};

// "%g" of a value, for messages.
std::string FormatOptionValue(double value);

}  // namespace zbrdf
