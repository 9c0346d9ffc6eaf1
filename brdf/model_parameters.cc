#include "brdf/model_parameters.h"

#include <charconv>
#include <cmath>

#include "basis/error.h"

namespace zbrdf {
namespace {

[[noreturn]] void FailParameter(std::string_view model, std::string_view key, std::string_view rule,
                                const std::string& got) {
  throw InputError(std::string(model) + ": " + std::string(key) + " must be " + std::string(rule) +
                   " (got " + got + ")");
}

void Check(std::string_view model, std::string_view key, double value, bool ok,
           std::string_view rule) {
  if (!std::isfinite(value)) FailParameter(model, key, "a finite number", FormatDouble(value));
  if (!ok) FailParameter(model, key, rule, FormatDouble(value));
}

void CheckRgb(std::string_view model, std::string_view key, const Rgb& value, bool ok,
              std::string_view rule) {
  if (!value.IsFinite()) FailParameter(model, key, "finite numbers", FormatRgb(value));
  if (!ok) FailParameter(model, key, rule, FormatRgb(value));
}

}  // namespace

std::string FormatDouble(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

std::string FormatRgb(const Rgb& value) {
  if (value.r == value.g && value.g == value.b) return FormatDouble(value.r);
  return FormatDouble(value.r) + "," + FormatDouble(value.g) + "," + FormatDouble(value.b);
}

void RequireFinite(std::string_view model, std::string_view key, double value) {
  Check(model, key, value, true, "");
}

void RequireNonNegative(std::string_view model, std::string_view key, double value) {
  Check(model, key, value, value >= 0, ">= 0");
}

void RequireNonNegative(std::string_view model, std::string_view key, const Rgb& value) {
  CheckRgb(model, key, value, value.r >= 0 && value.g >= 0 && value.b >= 0, ">= 0");
}

void RequirePositive(std::string_view model, std::string_view key, double value) {
  Check(model, key, value, value > 0, "> 0");
}

void RequireInUnitInterval(std::string_view model, std::string_view key, double value) {
  Check(model, key, value, value >= 0 && value <= 1, "in [0, 1]");
}

void RequireInUnitInterval(std::string_view model, std::string_view key, const Rgb& value) {
  const auto in = [](double v) { return v >= 0 && v <= 1; };
  CheckRgb(model, key, value, in(value.r) && in(value.g) && in(value.b), "in [0, 1]");
}

double SpecularLobeProbability(double w_specular, double w_diffuse) {
  const double sum = w_specular + w_diffuse;
  return sum > 0 ? w_specular / sum : 0.5;
}

}  // namespace zbrdf
