#include "basis/option_checker.h"

#include <cmath>
#include <cstdio>

namespace zbrdf {
namespace {

std::string JoinProblems(const std::string& options_name, const std::vector<std::string>& problems) {
  std::string message = options_name + ": ";
  for (size_t i = 0; i < problems.size(); ++i) message += (i ? "; " : "") + problems[i];
  return message;
}

}  // namespace

std::string FormatOptionValue(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", value);
  return text;
}

InvalidOptions::InvalidOptions(const std::string& options_name, std::vector<std::string> problems)
    : InputError(JoinProblems(options_name, problems)), problems_(std::move(problems)) {}

OptionChecker& OptionChecker::InRange(const std::string& field, double value, double lo,
                                      double hi) {
  if (!(value >= lo && value <= hi)) {
    problems_.push_back(field + " must be in [" + FormatOptionValue(lo) + ", " +
                        FormatOptionValue(hi) + "] (got " + FormatOptionValue(value) + ")");
  }
  return *this;
}

OptionChecker& OptionChecker::InRangeAbove(const std::string& field, double value, double lo,
                                           double hi) {
  if (!(value > lo && value <= hi)) {
    problems_.push_back(field + " must be in (" + FormatOptionValue(lo) + ", " +
                        FormatOptionValue(hi) + "] (got " + FormatOptionValue(value) + ")");
  }
  return *this;
}

OptionChecker& OptionChecker::InRangeBelow(const std::string& field, double value, double lo,
                                           double hi) {
  if (!(value >= lo && value < hi)) {
    problems_.push_back(field + " must be in [" + FormatOptionValue(lo) + ", " +
                        FormatOptionValue(hi) + ") (got " + FormatOptionValue(value) + ")");
  }
  return *this;
}

OptionChecker& OptionChecker::Positive(const std::string& field, double value) {
  if (!(value > 0 && std::isfinite(value))) {
    problems_.push_back(field + " must be > 0 and finite (got " + FormatOptionValue(value) + ")");
  }
  return *this;
}

OptionChecker& OptionChecker::ValidZone(const std::string& fields, double theta_min_rad,
                                        double theta_max_rad) {
  // The rule of Zone's constructor (basis/zone.cc), which rounds a horizon a hair beyond 90 deg.
  if (!(theta_min_rad >= 0 && theta_min_rad < theta_max_rad &&
        theta_max_rad <= M_PI / 2 + 1e-12)) {
    problems_.push_back(fields + " must satisfy 0 <= theta_min < theta_max <= 90 deg (got " +
                        FormatOptionValue(theta_min_rad * 180 / M_PI) + ", " +
                        FormatOptionValue(theta_max_rad * 180 / M_PI) + " deg)");
  }
  return *this;
}

OptionChecker& OptionChecker::AtLeast(const std::string& field, double value, double lo) {
  if (!(value >= lo && !std::isnan(value))) {
    problems_.push_back(field + " must be >= " + FormatOptionValue(lo) + " (got " +
                        FormatOptionValue(value) + ")");
  }
  return *this;
}

OptionChecker& OptionChecker::Above(const std::string& field, double value, double lo) {
  if (!(value > lo)) {
    problems_.push_back(field + " must be > " + FormatOptionValue(lo) + " (got " +
                        FormatOptionValue(value) + ")");
  }
  return *this;
}

OptionChecker& OptionChecker::Require(bool ok, const std::string& field,
                                      const std::string& problem) {
  if (!ok) problems_.push_back(field + " " + problem);
  return *this;
}

void OptionChecker::ThrowIfInvalid() const {
  if (!problems_.empty()) throw InvalidOptions(name_, problems_);
}

}  // namespace zbrdf
