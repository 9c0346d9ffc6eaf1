// `zbrdf report`: self-contained HTML pages about sessions (docs/preview.md, "zbrdf report").
//
// A session's page (SESSION/report.html) leads with the answer. Its first screen (1280x800) holds
// the summary: the material ball of the session's BRDF under the built-in sky (beside the true
// material's, for a simulated session), the recommended fit, its accuracy in numbers and in words,
// the rig time and the warnings. The pictures follow at a size one can judge (the fit against the
// truth, balls under a directional light, polar plots, the layout of the thesis's figure 3.3, the
// fit candidates, coefficient energy, the calibration figure); the raw metadata (session.json,
// report.json, the fit reports, the files) come last, folded into <details>. A folder of sessions
// gets an index page: one row per session with its ball, material, fit, errors and links.
//
// Pages load nothing: images are base64 PNG data URIs, the style is inline and there is no
// script, so a page can be mailed or archived as one file. No number on a page reads NaN or inf:
// a missing or non-finite value reads "n/a" with the reason.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace zbrdf {

struct ReportOptions {
  int preview_size = 256;  // the balls of the summary (shown at 320 at most) and the pictures
  int preview_spp = 32;
  int64_t metric_samples = 1 << 16;  // Monte Carlo samples of a BRDF distance the report computes

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

// Words for relative errors, one scale per measure; docs/preview.md ("Words for errors") gives
// the reasons for each number. An error below `excellent` reads "excellent", below `good`
// "good", below `fair` "fair", anything larger "poor"; a NaN, infinite or negative one "n/a".
enum class ErrorMeasure {
  kInZone,      // relative L2 of f^ = f_r cos(theta_i) over the measured zone (the capture's
                // coefficients, or a fit against the truth or its held-out coefficients)
  kHemisphere,  // cosine-weighted L2 over the whole hemisphere, relative (Ngan et al. 2005)
  kImage,       // relative RMSE of the fit's material ball against the truth's (built-in sky)
};
struct ErrorScale {
  double excellent, good, fair;  // upper bounds, exclusive
};
inline constexpr ErrorScale kInZoneScale{0.05, 0.15, 0.30};
inline constexpr ErrorScale kHemisphereScale{0.20, 0.40, 0.60};
inline constexpr ErrorScale kImageScale{0.03, 0.07, 0.15};
ErrorScale ScaleOf(ErrorMeasure measure);
std::string AccuracyWord(ErrorMeasure measure, double relative_error);

// One accuracy figure of the summary.
struct SummaryError {
  // "capture" (the measured coefficients, simulated sessions), "zone", "hemisphere", "image"
  // (the fit's).
  std::string id;
  std::string label;  // "fit, in the zone (11.3-54.9 deg)"
  ErrorMeasure measure = ErrorMeasure::kInZone;
  double value = 0;        // relative; NaN where not available
  std::string basis;       // how it was obtained ("against the true material", "cross-validated")
  std::string missing;     // why it is not available (value NaN), and how to get it
  bool estimated = false;  // an estimate without the truth (cross-validation, uncertainty)
  std::string Word() const { return AccuracyWord(measure, value); }
};

// What the top of a session's page says; the folder index shows the same.
struct SessionSummary {
  std::string name;          // the session folder's name
  std::string kind;          // "simulated", "hardware" (session.json)
  std::string material;      // a simulated session's true material spec; "" for hardware
  std::string fit;           // the model of the session's BRDF: "prior", "dbrdf", "ggx", ..., "sh"
  bool recommended = false;  // fit is `zbrdf fit --model auto`'s recommendation
  std::string fit_file;      // the file it was read from (its name in the session)
  std::string fit_why;       // the recommendation's reason
  int order = -1;            // zonal order (-1: unknown)
  double rig_time_s = 0;     // capture time on the rig (NaN: unknown)
  std::vector<SummaryError> errors;
  std::vector<std::string> warnings;
  std::string thumbnail_png;  // the fit's ball, small, PNG bytes ("" if there is no BRDF)

  // The worst word of the errors that have a value; "n/a" if none of the fit's has (no fit yet:
  // the capture's error alone does not make an answer).
  std::string Verdict() const;
  nlohmann::json ToJson() const;
  // Throws InputError if `j` is not what ToJson writes.
  static SessionSummary FromJson(const nlohmann::json& j);
};

struct SessionReportPage {
  std::string html;
  std::vector<std::string> sections;  // titles of the sections present, in page order
  std::vector<std::string> notes;     // what is missing and how to get it
  SessionSummary summary;
};

// Throws InputError if the folder is not a session (no session.json).
SessionReportPage BuildSessionReport(const std::string& session_dir, const ReportOptions& options);

// The summary a page written by BuildSessionReport carries (an HTML comment at its top); nullopt
// if the file is missing or carries none (a page of an older zbrdf).
std::optional<SessionSummary> ReadReportSummary(const std::string& page_path);

// The session folders under `dir` (not `dir` itself) down to `max_depth` levels (1: its
// subfolders); a session's own subfolders and hidden folders are not searched. Sorted by path.
std::vector<std::string> FindSessionFolders(const std::string& dir, int max_depth = 3);

// Whether SESSION/report.html must be written again: it is missing, older than a file at the top
// level of the session folder or than its calibration figure (the page's inputs), or carries no
// summary.
bool SessionReportIsStale(const std::string& session_dir);

// One row of a folder's index page.
struct IndexRow {
  std::string session_dir;
  std::string report_path;                // the session's report.html
  std::optional<SessionSummary> summary;  // nullopt: its page could not be made
  std::string error;                      // why (summary nullopt)
};
// The index page of a folder of sessions, written at `index_path` (links are relative to it).
std::string BuildIndexPage(const std::string& index_path, const std::vector<IndexRow>& rows);

// `zbrdf report DIR` on a folder of sessions: writes each session's report.html where it is
// stale (SessionReportIsStale; every one with `rebuild`), then the index page at `index_path`.
// A session whose page cannot be made gets a row saying why; the others are written.
// Throws InputError if `dir` holds no session (FindSessionFolders).
struct FolderReport {
  std::string index;                 // the index page written
  std::vector<std::string> written;  // session pages written
  std::vector<std::string> kept;     // session pages up to date, left as they were
  std::vector<std::string> failed;   // "SESSION: why"
};
FolderReport WriteFolderReport(const std::string& dir, const std::string& index_path,
                               const ReportOptions& options, bool rebuild);

// Helpers, exposed for tests.
std::string Base64Encode(const std::string& bytes);
std::string HtmlEscape(const std::string& text);
// 0.239 -> "23.9%", 0.0274 -> "2.74%", 5.03 -> "503%", 1e-6 -> "<0.01%"; non-finite: "n/a".
std::string FormatPercent(double fraction);

}  // namespace zbrdf
