// Checking and formatting of model parameters, shared by the models' constructors (which
// validate) and their Spec() methods (which print a canonical material spec).
//
// Validation failures throw InputError with a message of the form
// "ggx: alpha must be > 0 (got -0.2)": the model, the parameter's spec key, the rule, the value.
// Numbers print in the shortest form that reads back to the same double, so that a Spec()
// string recreates a model exactly.
#pragma once

#include <string>
#include <string_view>

#include "basis/vec3.h"

namespace zbrdf {

// Shortest decimal text that parses back to exactly `value` ("0.18", "1e-07", "nan").
std::string FormatDouble(double value);
// One number when all channels are equal ("0.5"), else three ("0.1,0.2,0.5").
std::string FormatRgb(const Rgb& value);

// Each throws InputError "MODEL: KEY must be ... (got VALUE)" when the rule fails; NaN and
// infinities always fail.
void RequireFinite(std::string_view model, std::string_view key, double value);
void RequireNonNegative(std::string_view model, std::string_view key, double value);
void RequireNonNegative(std::string_view model, std::string_view key, const Rgb& value);
void RequirePositive(std::string_view model, std::string_view key, double value);
void RequireInUnitInterval(std::string_view model, std::string_view key, double value);
void RequireInUnitInterval(std::string_view model, std::string_view key, const Rgb& value);

// Probability of choosing the specular lobe of a two-lobe mixture from (non-negative) estimates
// of the lobes' energies: w_specular / (w_specular + w_diffuse), or 1/2 when both are zero.
double SpecularLobeProbability(double w_specular, double w_diffuse);

}  // namespace zbrdf
