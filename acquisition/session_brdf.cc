#include "acquisition/session_brdf.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "basis/error.h"

namespace zbrdf {

namespace fs = std::filesystem;

std::vector<std::string> SessionShFiles(const std::string& dir) {
  std::vector<std::string> files;
  if (fs::exists(dir + "/sh.exr")) files.push_back(dir + "/sh.exr");
  std::vector<std::string> targets;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("sh-", 0) == 0 && entry.path().extension() == ".exr") {
      targets.push_back(entry.path().string());
    }
  }
  std::sort(targets.begin(), targets.end());
  files.insert(files.end(), targets.begin(), targets.end());
  return files;
}

std::vector<std::string> SessionBrdfFiles(const std::string& dir) {
  std::vector<std::string> files;
  if (fs::exists(dir + "/fit-dbrdf.exr")) files.push_back(dir + "/fit-dbrdf.exr");
  std::vector<std::string> fits;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    // fit-dbrdf.json is the D-BRDF fit's report; the model itself is fit-dbrdf.exr.
    if (name.rfind("fit-", 0) == 0 && entry.path().extension() == ".json" &&
        name != "fit-dbrdf.json") {
      fits.push_back(entry.path().string());
    }
  }
  std::sort(fits.begin(), fits.end());
  files.insert(files.end(), fits.begin(), fits.end());
  const std::vector<std::string> sh = SessionShFiles(dir);
  files.insert(files.end(), sh.begin(), sh.end());
  return files;
}

BrdfFile ReadSessionBrdf(const std::string& dir) {
  const std::vector<std::string> files = SessionBrdfFiles(dir);
  if (files.empty()) {
    std::string hint;
    std::ifstream session(dir + "/session.json");
    const nlohmann::json j = session ? nlohmann::json::parse(session, nullptr, false) : nullptr;
    if (j.is_object() && j.contains("material") && j["material"].is_string()) {
      hint = "; this simulated session's true material is " + j["material"].get<std::string>() +
             ", which can be given as INPUT itself";
    }
    throw InputError("session " + dir +
                     " has no BRDF yet: none of fit-dbrdf.exr, fit-<model>.json, sh.exr or "
                     "sh-<target>.exr. Run "
                     "zbrdf fit (D-BRDF and analytic fits) or zbrdf convert (SH) on it first" +
                     hint);
  }
  std::string skipped;
  for (const std::string& file : files) {
    try {
      return ReadBrdfFile(file);
    } catch (const InputError& e) {
      if (fs::path(file).extension() != ".json") throw;
      skipped += std::string(skipped.empty() ? "" : "; ") + e.what();
    }
  }
  throw InputError("session " + dir + " has fit reports but no fitted model (" + skipped +
                   "); check zbrdf fit's conditions, or run zbrdf convert for SH");
}

}  // namespace zbrdf
