#include "acquisition/session_brdf.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "acquisition/session.h"
#include "basis/error.h"

namespace zbrdf {

namespace fs = std::filesystem;

namespace {

// The files in `dir` whose names start with `prefix` and end with `extension`, by name.
std::vector<std::string> FilesByName(const std::string& dir, const std::string& prefix,
                                     const std::string& extension) {
  std::vector<std::string> files;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) == 0 && entry.path().extension() == extension) {
      files.push_back(entry.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

std::vector<std::string> SessionShFiles(const std::string& dir) {
  std::vector<std::string> files;
  if (fs::exists(SessionPath(dir, kShFile))) files.push_back(SessionPath(dir, kShFile));
  const std::vector<std::string> targets = FilesByName(dir, kShFilePrefix, ".exr");
  files.insert(files.end(), targets.begin(), targets.end());
  return files;
}

// The file holding model `name`'s fit in the session.
std::string FitFileOf(const std::string& dir, const std::string& name) {
  if (name == "dbrdf") return SessionPath(dir, kDBrdfFitFile);
  if (name == "prior") return SessionPath(dir, kPriorFitFile);
  return SessionPath(dir, FitReportFileName(name));
}

std::vector<std::string> SessionBrdfFiles(const std::string& dir) {
  std::vector<std::string> files;
  auto add = [&files](const std::string& path) {
    if (fs::exists(path) && std::find(files.begin(), files.end(), path) == files.end()) {
      files.push_back(path);
    }
  };
  // The recommendation of zbrdf fit --model auto first.
  if (std::ifstream in(SessionPath(dir, kAutoFitFile)); in) {
    const nlohmann::json choice = nlohmann::json::parse(in, nullptr, false);
    if (choice.is_object() && choice.contains("recommended") && choice["recommended"].is_string()) {
      const std::string name = choice["recommended"].get<std::string>();
      if (!name.empty() && name.find('/') == std::string::npos) add(FitFileOf(dir, name));
    }
  }
  add(SessionPath(dir, kPriorFitFile));
  add(SessionPath(dir, kDBrdfFitFile));
  // Reports that are not models: the D-BRDF's and the prior's (their models are the .exr files),
  // and the auto choice.
  for (const std::string& fit : FilesByName(dir, kFitReportPrefix, ".json")) {
    const std::string name = fs::path(fit).filename().string();
    if (name != FitReportFileName("dbrdf") && name != FitReportFileName("prior") &&
        name != kAutoFitFile) {
      add(fit);
    }
  }
  const std::vector<std::string> sh = SessionShFiles(dir);
  files.insert(files.end(), sh.begin(), sh.end());
  return files;
}

BrdfFile ReadSessionBrdf(const std::string& dir) {
  const std::vector<std::string> files = SessionBrdfFiles(dir);
  if (files.empty()) {
    std::string hint, material;
    if (SessionFolder::Exists(dir)) {
      try {
        material = SessionFolder::Open(dir).material();
      } catch (const InputError&) {
        // A damaged session.json: no hint.
      }
    }
    if (!material.empty()) {
      hint = "; this simulated session's true material is " + material +
             ", which can be given as INPUT itself";
    }
    throw InputError("session " + dir +
                     " has no BRDF yet: none of fit-prior.exr, fit-dbrdf.exr, fit-<model>.json, "
                     "sh.exr or "
                     "sh-<target>.exr. Run "
                     "zbrdf fit (--model auto recommends one) or zbrdf convert (SH) on it first" +
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
