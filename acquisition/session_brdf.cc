#include "acquisition/session_brdf.h"

#include <algorithm>
#include <filesystem>

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

std::vector<std::string> SessionBrdfFiles(const std::string& dir) {
  std::vector<std::string> files;
  if (fs::exists(SessionPath(dir, kDBrdfFitFile))) files.push_back(SessionPath(dir, kDBrdfFitFile));
  // The D-BRDF fit's report is not a model (the model is fit-dbrdf.exr).
  for (const std::string& fit : FilesByName(dir, kFitReportPrefix, ".json")) {
    if (fs::path(fit).filename() != FitReportFileName("dbrdf")) files.push_back(fit);
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
