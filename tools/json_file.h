// Reading the JSON files zbrdf's commands write (reports, batch manifests and item results),
// where a missing or damaged file means "not there yet" rather than an error.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace zbrdf {

// The parsed file, or null when it is missing, unreadable or not valid JSON.
nlohmann::json ReadJsonOrNull(const std::string& path);

}  // namespace zbrdf
