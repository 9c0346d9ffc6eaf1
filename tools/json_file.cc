#include "tools/json_file.h"

#include <fstream>

namespace zbrdf {

nlohmann::json ReadJsonOrNull(const std::string& path) {
  std::ifstream in(path);
  if (!in) return nullptr;
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  return j.is_discarded() ? nlohmann::json(nullptr) : j;
}

}  // namespace zbrdf
