// `zbrdf report`: one self-contained HTML page about a session (SESSION/report.html): what was
// measured and how (session.json), how long it took and how accurate it is (report.json), the
// calibration figure (graycard.png in the session or its calibration folder), previews and
// plots of the session's BRDF, the coefficient energy per band, and for simulated sessions the
// comparison with the true material. Images are embedded as base64 PNG data URIs and the style
// is inline: the page loads nothing else, so it can be mailed or archived as one file.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace zbrdf {

struct ReportOptions {
  int preview_size = 192;
  int preview_spp = 32;
  int64_t metric_samples = 1 << 16;

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
};

struct SessionReportPage {
  std::string html;
  std::vector<std::string> sections;  // titles of the sections present
  std::vector<std::string> notes;     // what is missing and how to get it
};

// Throws InputError if the folder is not a session (no session.json).
SessionReportPage BuildSessionReport(const std::string& session_dir, const ReportOptions& options);

// Helpers, exposed for tests.
std::string Base64Encode(const std::string& bytes);
std::string HtmlEscape(const std::string& text);

}  // namespace zbrdf
