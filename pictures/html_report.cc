#include "pictures/html_report.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <tuple>

#include "acquisition/session.h"
#include "acquisition/session_brdf.h"
#include "acquisition/zonal.h"
#include "basis/atomic_file.h"
#include "basis/error.h"
#include "basis/option_checker.h"
#include "brdf/material_spec.h"
#include "brdf/sh_brdf.h"
#include "brdf/sh_file.h"
#include "drivers/bgr_png.h"
#include "pictures/brdf_compare.h"
#include "pictures/brdf_figure.h"
#include "pictures/brdf_plots.h"
#include "pictures/environment.h"
#include "pictures/image.h"
#include "pictures/material_ball.h"

namespace zbrdf {
namespace {

namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kThumbnailSize = 96;    // the index page's balls, pixels
constexpr int kSummaryBallMax = 320;  // the summary's balls are shown this wide at most
constexpr int kVisibleWarnings = 4;   // the summary shows these; the rest are folded
constexpr int kSearchDepth = 3;       // FindSessionFolders' default, repeated in messages
// The image error's balls: at most this size, this many times the previews' samples per pixel
// (the same number of samples as a 256-pixel preview at 4 times fewer per pixel).
constexpr int kImageErrorSize = 64;
constexpr int kImageErrorSppFactor = 8;
constexpr char kSummaryMarker[] = "<!-- zbrdf-summary ";

// The summary's first screen is 1280x800 (tests/tools/report_browser_test.sh checks it): the
// balls at their rendered size on the left, the facts beside them.
constexpr const char* kStyle =
    "body{font-family:sans-serif;font-size:15px;max-width:1240px;margin:0 auto;padding:10px 20px;"
    "color:#222;line-height:1.35}"
    "h1{font-size:1.5em;margin:.1em 0 .15em}h2{font-size:1.2em;border-bottom:1px solid #ccc;"
    "margin-top:1.6em}h3{font-size:1.05em;margin:.8em 0 .3em}"
    ".summary{display:flex;gap:22px;align-items:flex-start;border-bottom:2px solid #444;"
    "padding-bottom:8px}.balls{display:flex;gap:10px;flex:none}"
    // A caption as wide as its ball: a long material spec wraps instead of widening the column.
    ".balls figure{margin:0;display:table}.balls figcaption{display:table-caption;"
    "caption-side:bottom;overflow-wrap:anywhere}.balls img{max-width:none}"
    ".facts{flex:1;min-width:0}.facts h1,.sub,.fit{overflow-wrap:anywhere}"
    ".sub{color:#555;font-size:.9em;margin:0 0 .4em}"
    ".verdict{font-size:1.2em;margin:.3em 0}.fit{margin:.3em 0}"
    "table{border-collapse:collapse;margin:.4em 0}td,th{border:1px solid #ddd;padding:.2em .5em;"
    "text-align:left;vertical-align:top}th{background:#f4f4f4}"
    "td.num{text-align:right;white-space:nowrap}.word{font-weight:bold;padding:0 .3em}"
    ".w-excellent{background:#cdeecd}.w-good{background:#e3f3cf}.w-fair{background:#fdeebb}"
    ".w-poor{background:#f8cccc}.w-na{background:#eee;color:#555}"
    ".why{font-size:.85em;color:#555}"
    ".warn{background:#fff6d8;border-left:4px solid #e0b000;padding:.15em .6em;margin:.2em 0;"
    "font-size:.9em}.ok{color:#2a7a2a;font-size:.9em}"
    ".note{background:#f0f4fa;border-left:4px solid #7090c0;padding:.3em .8em;margin:.5em 0}"
    ".error{background:#fde8e8;border-left:4px solid #d03030;padding:.3em .8em;margin:.5em 0}"
    "figure{display:inline-block;margin:.4em 1em .4em 0;vertical-align:top}"
    "figcaption{font-size:.85em;color:#555}img{max-width:100%;height:auto}"
    "details{margin:.3em 0}summary{cursor:pointer}details>summary{font-weight:bold}"
    ".scale summary{font-weight:normal;font-size:.85em;color:#555}"
    "pre{background:#f7f7f7;padding:.6em;overflow:auto;font-size:.85em}"
    "#sessions{font-size:.9em}#sessions img{max-width:none}";

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream file(path);
  if (!file) return nullptr;
  nlohmann::json j = nlohmann::json::parse(file, nullptr, false);
  return j.is_discarded() ? nlohmann::json(nullptr) : j;
}

std::string ReadBytes(const std::string& path, size_t max_bytes = std::string::npos) {
  std::ifstream file(path, std::ios::binary);
  if (max_bytes == std::string::npos) {
    std::ostringstream buffer;
    buffer << file.rdbuf();
    return buffer.str();
  }
  std::string bytes(max_bytes, '\0');
  file.read(bytes.data(), static_cast<std::streamsize>(max_bytes));
  bytes.resize(static_cast<size_t>(file.gcount()));
  return bytes;
}

// A number of a JSON object, NaN where it is missing, null (nlohmann writes NaN as null) or not a
// number.
double Number(const nlohmann::json& j, const std::string& key) {
  if (!j.is_object() || !j.contains(key) || !j[key].is_number()) return kNaN;
  return j[key].get<double>();
}

std::string StringField(const nlohmann::json& j, const std::string& key) {
  if (!j.is_object() || !j.contains(key) || !j[key].is_string()) return "";
  return j[key].get<std::string>();
}

std::string Printf(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

std::string FormatSeconds(double s) {
  if (!std::isfinite(s) || s < 0) return "n/a";
  if (s < 120) return Printf("%.1f s", s);
  const long total = std::lround(s);
  return std::to_string(total / 60) + " min " + std::to_string(total % 60) + " s";
}

std::string ImageTag(const std::string& png_bytes, const std::string& alt, int width = 0,
                     int height = 0) {
  std::string size;
  if (width > 0 && height > 0) {
    size = " width=\"" + std::to_string(width) + "\" height=\"" + std::to_string(height) + "\"";
  }
  return "<img alt=\"" + HtmlEscape(alt) + "\"" + size + " src=\"data:image/png;base64," +
         Base64Encode(png_bytes) + "\">";
}

// display: the width shown, if the image is larger (0: its own size).
std::string Figure(const cv::Mat& image, const std::string& caption, const std::string& id = "",
                   int display = 0) {
  int width = image.cols, height = image.rows;
  if (display > 0 && width > display) {
    height = static_cast<int>(std::lround(static_cast<double>(height) * display / width));
    width = display;
  }
  return "<figure" + (id.empty() ? std::string() : " id=\"" + id + "\"") + ">" +
         ImageTag(EncodeBgrPng(image), caption, width, height) + "<figcaption>" +
         HtmlEscape(caption) + "</figcaption></figure>\n";
}

std::string Scalar(const nlohmann::json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_float()) {
    const double x = v.get<double>();
    return std::isfinite(x) ? Printf("%.5g", x) : "n/a (not finite)";
  }
  if (v.is_null()) return "n/a (null)";
  return v.dump();
}

// A long text folded into a <details> element showing its first line.
std::string Folded(const std::string& text) {
  if (text.size() <= 160 && text.find('\n') == std::string::npos) return HtmlEscape(text);
  const std::string first = text.substr(0, std::min(text.find('\n'), size_t{80}));
  return "<details><summary>" + HtmlEscape(first) + " ...</summary><pre>" +
         HtmlEscape(text.substr(0, 20000)) + "</pre></details>";
}

// A JSON object as a two-column table; nested objects as nested tables (two levels), arrays of
// scalars inline (the first 12 items), long texts and deeper structures folded.
std::string JsonTable(const nlohmann::json& j, int depth = 0) {
  if (!j.is_object()) return HtmlEscape(Scalar(j));
  std::string html = "<table>";
  for (auto it = j.begin(); it != j.end(); ++it) {
    const nlohmann::json& v = it.value();
    std::string value;
    const bool scalar_array =
        v.is_array() &&
        std::none_of(v.begin(), v.end(), [](const nlohmann::json& x) { return x.is_structured(); });
    if (v.is_object() && depth < 2) {
      value = JsonTable(v, depth + 1);
    } else if (scalar_array) {
      std::string items;
      size_t shown = 0;
      for (const auto& x : v) {
        if (shown++ == 12) break;
        items += (items.empty() ? "" : ", ") + Scalar(x);
      }
      if (v.size() > 12) items += ", ... (" + std::to_string(v.size()) + " items)";
      value = HtmlEscape(items);
    } else if (v.is_structured()) {
      value = Folded(v.dump(1));
    } else {
      value = Folded(Scalar(v));
    }
    html += "<tr><th>" + HtmlEscape(it.key()) + "</th><td>" + value + "</td></tr>";
  }
  return html + "</table>\n";
}

// Keys anywhere in a report that name errors, warnings or failures, with their values.
void CollectProblems(const nlohmann::json& j, const std::string& prefix,
                     std::vector<std::string>* out) {
  if (!j.is_object()) return;
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string key = prefix.empty() ? it.key() : prefix + "." + it.key();
    const bool problem = it.key().find("warning") != std::string::npos || it.key() == "errors" ||
                         it.key() == "failures" || it.key() == "conditions";
    if (problem && !(it.value().is_array() && it.value().empty())) {
      if (it.value().is_array()) {
        for (const auto& x : it.value()) out->push_back(key + ": " + Scalar(x));
      } else {
        out->push_back(key + ": " + Scalar(it.value()));
      }
    } else if (it.value().is_object()) {
      CollectProblems(it.value(), key, out);
    }
  }
}

std::string FindCalibrationFigure(const std::string& dir, const nlohmann::json& session) {
  std::vector<std::string> candidates = {dir + "/graycard.png", dir + "/calibration/graycard.png"};
  if (session.is_object() && session.contains("calibration") &&
      session["calibration"].is_string()) {
    const fs::path calibration = session["calibration"].get<std::string>();
    for (const fs::path& base : {calibration, fs::path(dir) / calibration}) {
      candidates.push_back((base / "graycard.png").string());
      candidates.push_back((base.parent_path() / "graycard.png").string());
    }
  }
  for (const std::string& c : candidates) {
    std::error_code error;
    if (fs::is_regular_file(c, error)) return c;
  }
  return "";
}

std::string NowUtc() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%d %H:%M UTC", &tm);
  return text;
}

std::string FolderName(const std::string& dir) {
  const fs::path path(dir);
  return path.filename().empty() ? path.parent_path().filename().string()
                                 : path.filename().string();
}

// The fit report beside a session's BRDF file (fit-<model>.exr -> fit-<model>.json; a fit report
// is its own) and the model's name ("sh" for an SH conversion, "" if unknown).
std::pair<std::string, std::string> FitReportOf(const std::string& brdf_path) {
  const fs::path path(brdf_path);
  const std::string stem = path.stem().string();
  if (stem.rfind(kFitReportPrefix, 0) == 0) {
    const std::string model = stem.substr(std::string(kFitReportPrefix).size());
    return {(path.parent_path() / (stem + ".json")).string(), model};
  }
  if (stem == "sh" || stem.rfind(kShFilePrefix, 0) == 0) return {"", "sh"};
  return {"", ""};
}

std::string ModelName(const std::string& model) {
  if (model == "prior") return "prior (measured materials, whole hemisphere)";
  if (model == "dbrdf") return "D-BRDF";
  if (model == "ggx") return "GGX";
  if (model == "ward") return "Ward";
  if (model == "as") return "Ashikhmin-Shirley";
  if (model == "sh") return "SH conversion (no fit)";
  return model.empty() ? "unknown" : model;
}

int WordRank(const std::string& word) {
  if (word == "excellent") return 0;
  if (word == "good") return 1;
  if (word == "fair") return 2;
  if (word == "poor") return 3;
  return -1;
}

std::string WordClass(const std::string& word) { return WordRank(word) < 0 ? "w-na" : "w-" + word; }

std::string ScaleText(ErrorMeasure measure) {
  const ErrorScale s = ScaleOf(measure);
  return "excellent below " + FormatPercent(s.excellent) + ", good below " + FormatPercent(s.good) +
         ", fair below " + FormatPercent(s.fair) + ", poor above";
}

// "zbrdf fit SESSION ..." with the session's folder in place of SESSION.
std::string WithSession(std::string text, const std::string& dir) {
  for (size_t at = text.find("SESSION"); at != std::string::npos;
       at = text.find("SESSION", at + dir.size())) {
    text.replace(at, 7, dir);
  }
  return text;
}

// What the sample is: a simulated session's material spec, else what kind of session it is.
std::string MaterialLabel(const SessionSummary& s) {
  if (!s.material.empty()) return s.material;
  return s.kind == "hardware" ? "measured sample" : "sample";
}

// The thresholds, folded: one line until opened.
std::string ScaleDetails() {
  return "<details class=\"scale\"><summary>How the words are chosen (~: an estimate without "
         "the truth)</summary><div class=\"why\">In the zone: " +
         ScaleText(ErrorMeasure::kInZone) +
         ". Whole hemisphere: " + ScaleText(ErrorMeasure::kHemisphere) +
         ". Image: " + ScaleText(ErrorMeasure::kImage) +
         ". The reasons are in docs/preview.md (Words for errors).</div></details>\n";
}

// "23.9% fair" as table cells (number, word), or n/a with the reason.
std::string ErrorCells(const SummaryError& e) {
  const std::string word = e.Word();
  if (WordRank(word) < 0) {
    return "<td class=\"num w-na\">n/a</td><td class=\"w-na\">" + HtmlEscape(e.missing) + "</td>";
  }
  return "<td class=\"num\">" + std::string(e.estimated ? "~" : "") + FormatPercent(e.value) +
         "</td><td class=\"" + WordClass(word) + "\" title=\"" + HtmlEscape(ScaleText(e.measure)) +
         "\"><span class=\"word\">" + word + "</span></td>";
}

// One cell for the index: "23.9% fair", or n/a with the reason as its title.
std::string IndexErrorCell(const SessionSummary& s, const std::string& id) {
  for (const SummaryError& e : s.errors) {
    if (e.id != id) continue;
    const std::string word = e.Word();
    if (WordRank(word) < 0) {
      return "<td class=\"w-na\" title=\"" + HtmlEscape(e.missing) + "\">n/a</td>";
    }
    return "<td class=\"num " + WordClass(word) + "\" title=\"" + HtmlEscape(e.basis) + "\">" +
           (e.estimated ? "~" : "") + FormatPercent(e.value) + "<br><span class=\"word\">" + word +
           "</span></td>";
  }
  return "<td class=\"w-na\" title=\"not measured for this session\">n/a</td>";
}

// JSON inside an HTML comment: "--" may not occur in it. In JSON it can only occur inside a
// string, where \u002d is the same character.
std::string CommentSafeJson(const nlohmann::json& j) {
  // Invalid UTF-8 (a path in another encoding) is replaced, not thrown on.
  std::string text = j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  for (size_t at = text.find("--"); at != std::string::npos; at = text.find("--", at)) {
    text.replace(at + 1, 1, "\\u002d");
  }
  return text;
}

// Everything the report reads about a session, read once.
struct SessionInputs {
  std::string dir, name;
  nlohmann::json session, report, autofit, fit_report;
  std::string fit_model, fit_file, fit_report_path;
  bool recommended = false;
  std::shared_ptr<const Brdf> fitted, truth;
  std::string truth_spec;
  std::vector<std::string> notes;
};

SessionInputs ReadInputs(const std::string& dir) {
  SessionInputs in;
  std::optional<SessionFolder> folder;
  try {
    folder = SessionFolder::Open(dir);
  } catch (const InputError& e) {
    throw InputError(dir + " is not a session folder (" + e.what() +
                     "); give the folder zbrdf simulate or zbrdf capture wrote");
  }
  in.dir = dir;
  in.name = FolderName(dir);
  in.session = folder->session();
  in.report = ReadJson(SessionPath(dir, kReportFile));
  in.autofit = ReadJson(SessionPath(dir, kAutoFitFile));
  try {
    const BrdfFile file = ReadSessionBrdf(dir);
    in.fitted = file.brdf;
    in.fit_file = fs::path(file.path).filename().string();
    std::tie(in.fit_report_path, in.fit_model) = FitReportOf(file.path);
    if (!in.fit_report_path.empty()) in.fit_report = ReadJson(in.fit_report_path);
    const std::string model = StringField(in.fit_report, "model");
    if (!model.empty()) in.fit_model = model;
    const std::string recommended = StringField(in.autofit, "recommended");
    in.recommended = !recommended.empty() && recommended == in.fit_model;
  } catch (const InputError& e) {
    in.notes.push_back(e.what());
  }
  if (!folder->material().empty()) {
    in.truth_spec = folder->material();
    try {
      in.truth = MakeBrdf(in.truth_spec);
    } catch (const InputError& e) {
      in.notes.push_back(std::string("true material: ") + e.what());
    }
  }
  return in;
}

std::string ZoneText(const nlohmann::json& report, const nlohmann::json& session) {
  const nlohmann::json* zone = nullptr;
  if (report.is_object() && report.contains("zone_deg")) zone = &report["zone_deg"];
  if (zone == nullptr && session.is_object() && session.contains("plan") &&
      session["plan"].is_object() && session["plan"].contains("zone_deg")) {
    zone = &session["plan"]["zone_deg"];
  }
  if (zone == nullptr || !zone->is_array() || zone->size() != 2 || !(*zone)[0].is_number() ||
      !(*zone)[1].is_number()) {
    return "";
  }
  return Printf("%.1f", (*zone)[0].get<double>()) + "-" + Printf("%.1f", (*zone)[1].get<double>()) +
         " deg";
}

int OrderOf(const SessionInputs& in) {
  for (const nlohmann::json* j : {&in.report, &in.fit_report}) {
    if (j->is_object() && j->contains("order") && (*j)["order"].is_number_integer()) {
      return (*j)["order"].get<int>();
    }
  }
  if (in.session.is_object() && in.session.contains("plan") && in.session["plan"].is_object() &&
      in.session["plan"].contains("order") && in.session["plan"]["order"].is_number_integer()) {
    return in.session["plan"]["order"].get<int>();
  }
  return -1;
}

// The session's warnings: the capture's and processing's (report.json), the fit's (its report's
// warnings and conditions), and what is missing for an answer.
std::vector<std::string> Warnings(const SessionInputs& in) {
  std::vector<std::string> out;
  if (!in.report.is_object()) {
    out.push_back("no report.json: the session has not been processed (zbrdf process SESSION)");
  } else {
    if (in.report.contains("complete") && in.report["complete"].is_boolean() &&
        !in.report["complete"].get<bool>()) {
      out.push_back("the capture is incomplete: " + Scalar(in.report.value("frames_captured", 0)) +
                    " of " + Scalar(in.report.value("frames", 0)) +
                    " frames; continue it with --resume");
    }
    const double saturated = Number(in.report, "saturated_pixel_lobes");
    if (saturated > 0) {
      out.push_back(Printf("%.0f", saturated) +
                    " pixel-lobes were saturated at every exposure and left out (a shorter "
                    "--shortest-exposure-us keeps them)");
    }
    const double rejected = Number(in.report, "journal_lines_rejected");
    if (rejected > 0) {
      out.push_back(Printf("%.0f", rejected) + " journal lines were rejected on resume: " +
                    StringField(in.report, "first_rejection"));
    }
    CollectProblems(in.report, "report.json", &out);
  }
  if (!in.fitted) {
    out.push_back("no fit yet: run zbrdf fit SESSION --model auto");
  } else if (in.fit_model == "sh") {
    out.push_back(
        "the session's BRDF is its SH conversion, which outside the zone is "
        "extrapolation: run zbrdf fit SESSION --model auto");
  } else if (!in.autofit.is_object()) {
    out.push_back(
        "no recommendation: zbrdf fit SESSION --model auto compares the prior, the "
        "D-BRDF and GGX and recommends one");
  }
  if (in.fit_report.is_object()) {
    const std::string file = fs::path(in.fit_report_path).filename().string();
    if (in.fit_report.contains("fitted") && in.fit_report["fitted"].is_boolean() &&
        !in.fit_report["fitted"].get<bool>()) {
      out.push_back(file + ": nothing was fitted (see its conditions)");
    }
    for (const char* key : {"warnings", "conditions"}) {
      if (!in.fit_report.contains(key) || !in.fit_report[key].is_array()) continue;
      for (const auto& x : in.fit_report[key]) out.push_back(file + ": " + Scalar(x));
    }
  }
  for (const std::string& note : in.notes) {
    if (note.rfind("true material", 0) == 0) out.push_back(note);
  }
  std::vector<std::string> unique;
  for (const std::string& w : out) {
    if (std::find(unique.begin(), unique.end(), w) == unique.end()) unique.push_back(w);
  }
  return unique;
}

// The accuracy figures of the summary (docs/preview.md, "The summary").
std::vector<SummaryError> Errors(const SessionInputs& in, const std::string& zone,
                                 const MaterialComparison* comparison,
                                 const ImageError* image_error) {
  std::vector<SummaryError> out;
  const bool simulated = !in.truth_spec.empty();
  const std::string zone_label = zone.empty() ? "" : " (" + zone + ")";
  // The capture: the measured coefficients against the true ones (simulated sessions).
  const double capture = Number(in.report, "coefficient_error_in_zone");
  if (std::isfinite(capture)) {
    out.push_back({"capture", "capture, in the zone" + zone_label, ErrorMeasure::kInZone, capture,
                   "zonal coefficients against the material's true coefficients", "", false});
  }
  const std::string no_fit = "no fit yet: zbrdf fit SESSION --model auto";

  SummaryError in_zone{"zone", "fit, in the zone" + zone_label, ErrorMeasure::kInZone, kNaN, "", "",
                       false};
  SummaryError hemisphere{
      "hemisphere", "fit, whole hemisphere", ErrorMeasure::kHemisphere, kNaN, "", "", false};
  SummaryError image{"image", "image (ball under the sky)", ErrorMeasure::kImage, kNaN, "", "",
                     false};
  if (!in.fitted) {
    in_zone.missing = hemisphere.missing = image.missing = no_fit;
  } else {
    // In the zone: against the truth, else the recommendation's cross-validated error.
    const double truth_zone = Number(in.fit_report, "error_in_zone");
    double cv = kNaN;
    if (in.recommended && in.autofit.contains("candidates") &&
        in.autofit["candidates"].is_array()) {
      for (const auto& c : in.autofit["candidates"]) {
        if (StringField(c, "model") == in.fit_model) cv = Number(c, "cv_error");
      }
    }
    if (simulated && std::isfinite(truth_zone)) {
      in_zone.value = truth_zone;
      in_zone.basis = "cosine-weighted L2 against the true material, over the zone";
    } else if (std::isfinite(cv)) {
      in_zone.value = cv;
      in_zone.estimated = true;
      in_zone.basis = "cross-validated: held-out zonal coefficients (no truth to compare with)";
    } else if (simulated && in.fit_report.is_object() && in.fit_report.contains("error_in_zone")) {
      in_zone.missing = "the comparison with the truth gave no finite number (see the fit report)";
    } else if (simulated) {
      in_zone.missing =
          "the fit report has no comparison with the truth (zbrdf fit ran with "
          "--no-compare, or the BRDF is an SH conversion)";
    } else {
      in_zone.missing = "no truth; zbrdf fit SESSION --model auto gives a cross-validated error";
    }
    // Over the hemisphere: against the truth (the fit report's, else the report's own Monte
    // Carlo estimate), else the prior fit's one-sigma uncertainty.
    const double truth_hemisphere = Number(in.fit_report, "error_cosine_l2");
    const double uncertainty = in.fit_report.contains("uncertainty")
                                   ? Number(in.fit_report["uncertainty"], "relative_hemisphere")
                                   : kNaN;
    if (simulated && std::isfinite(truth_hemisphere)) {
      hemisphere.value = truth_hemisphere;
      hemisphere.basis = "cosine-weighted L2 against the true material (Ngan et al. 2005)";
    } else if (comparison != nullptr && std::isfinite(comparison->distance.RelativeMean())) {
      hemisphere.value = comparison->distance.RelativeMean();
      hemisphere.basis = "cosine-weighted L2 against the true material, Monte Carlo estimate";
    } else if (std::isfinite(uncertainty)) {
      hemisphere.value = uncertainty;
      hemisphere.estimated = true;
      hemisphere.basis = "estimated: the prior fit's one-sigma uncertainty (no truth)";
    } else {
      hemisphere.missing = simulated ? "the true material could not be read"
                                     : "no truth; only the prior fit estimates it (zbrdf fit "
                                       "SESSION --model auto or --model prior)";
    }
    if (image_error != nullptr && std::isfinite(image_error->relative_rmse)) {
      image.value = image_error->relative_rmse;
      image.basis =
          "relative RMSE of the fit's ball against the truth's under the built-in sky, "
          "without the renders' sampling noise";
    } else if (image_error != nullptr) {
      image.missing = "the true material's ball is black: a relative error is undefined";
    } else {
      image.missing = simulated ? "the true material could not be read"
                                : "no true material to render against (hardware session)";
    }
  }
  out.push_back(in_zone);
  out.push_back(hemisphere);
  out.push_back(image);
  return out;
}

cv::Mat Thumbnail(const cv::Mat& ball) {
  cv::Mat small;
  cv::resize(ball, small, cv::Size(kThumbnailSize, kThumbnailSize), 0, 0, cv::INTER_AREA);
  return small;
}

// The <header> of the page: the answer.
std::string SummaryHtml(const SessionInputs& in, const SessionSummary& s, const std::string& zone,
                        const cv::Mat& fit_ball, const cv::Mat& truth_ball) {
  std::string html = "<header class=\"summary\" id=\"summary\">\n<div class=\"balls\">";
  if (!fit_ball.empty()) {
    html += Figure(fit_ball, "fit: " + (s.fit.empty() ? s.fit_file : s.fit) + ", built-in sky",
                   "ball-fit", kSummaryBallMax);
  }
  if (!truth_ball.empty())
    html += Figure(truth_ball, "truth: " + s.material, "ball-truth", kSummaryBallMax);
  html += "</div>\n<div class=\"facts\">\n";
  html += "<h1>" + HtmlEscape(s.material.empty() ? MaterialLabel(s) + " " + s.name : s.material) +
          "</h1>\n";
  std::string sub = "session " + HtmlEscape(s.name);
  if (!s.kind.empty()) sub += " &middot; " + HtmlEscape(s.kind);
  const std::string rig = StringField(in.session, "rig_name");
  if (!rig.empty()) sub += " on " + HtmlEscape(rig);
  if (!zone.empty()) sub += " &middot; zone " + HtmlEscape(zone);
  if (s.order >= 0) sub += ", order " + std::to_string(s.order);
  html += "<p class=\"sub\">" + sub + " &middot; report of " + NowUtc() + "</p>\n";

  const std::string verdict = s.Verdict();
  const bool estimated_only =
      std::all_of(s.errors.begin(), s.errors.end(),
                  [](const SummaryError& e) { return e.estimated || !std::isfinite(e.value); });
  html += "<p class=\"verdict\" id=\"verdict\">Accuracy: <span class=\"word " + WordClass(verdict) +
          "\">" + verdict + "</span> <span class=\"why\">" +
          (WordRank(verdict) < 0 ? (s.fit.empty() ? "no fit yet" : "nothing to measure it by")
                                 : std::string(estimated_only ? "estimated, " : "") +
                                       "the worst of the figures below") +
          "</span></p>\n";

  html += "<p class=\"fit\" id=\"fit\">Fit: ";
  if (s.fit.empty()) {
    html += "<b>none yet</b> <span class=\"why\">(zbrdf fit " + HtmlEscape(in.dir) +
            " --model auto)</span>";
  } else {
    html += "<b>" + HtmlEscape(ModelName(s.fit)) + "</b> <span class=\"why\">(" +
            HtmlEscape(s.fit_file) + ")</span>" +
            (s.recommended ? ", recommended by <code>zbrdf fit --model auto</code>" : "");
    if (!s.fit_why.empty()) html += "<br><span class=\"why\">" + HtmlEscape(s.fit_why) + "</span>";
  }
  html += "</p>\n<table id=\"errors\"><tr><th>error</th><th>value</th><th>in words</th></tr>\n";
  for (const SummaryError& e : s.errors) {
    html += "<tr title=\"" + HtmlEscape(e.basis.empty() ? e.missing : e.basis) + "\"><th>" +
            HtmlEscape(e.label) + "</th>" + ErrorCells(e) + "</tr>\n";
  }
  html += "</table>\n";
  html += ScaleDetails();
  html += "<p id=\"rig-time\">Rig time: <b>" + FormatSeconds(s.rig_time_s) + "</b>";
  if (std::isfinite(s.rig_time_s) && s.kind == "simulated") html += " (the virtual rig's clock)";
  const double frames = Number(in.report, "frames");
  if (std::isfinite(frames)) html += " &middot; " + Printf("%.0f", frames) + " frames";
  html += "</p>\n<div id=\"warnings\">";
  if (s.warnings.empty()) {
    html += "<p class=\"ok\">No warnings.</p>";
  } else {
    const size_t shown = std::min(s.warnings.size(), size_t{kVisibleWarnings});
    for (size_t i = 0; i < shown; ++i) {
      html += "<div class=\"warn\">" + HtmlEscape(s.warnings[i]) + "</div>\n";
    }
    if (s.warnings.size() > shown) {
      html += "<details><summary>" + std::to_string(s.warnings.size() - shown) +
              " more warnings</summary>";
      for (size_t i = shown; i < s.warnings.size(); ++i) {
        html += "<div class=\"warn\">" + HtmlEscape(s.warnings[i]) + "</div>\n";
      }
      html += "</details>";
    }
  }
  return html + "</div>\n</div>\n</header>\n";
}

// The recommendation's candidates: cross-validated errors and, for a simulated session, their
// errors against the truth.
std::string CandidatesHtml(const nlohmann::json& autofit) {
  if (!autofit.is_object() || !autofit.contains("candidates") ||
      !autofit["candidates"].is_array()) {
    return "";
  }
  const std::string recommended = StringField(autofit, "recommended");
  const nlohmann::json truth =
      autofit.contains("errors_against_truth") ? autofit["errors_against_truth"] : nlohmann::json();
  std::string html =
      "<table><tr><th>model</th><th>cross-validated (held-out coefficients)</th>"
      "<th>in the zone, against the truth</th><th>whole hemisphere, against the truth</th></tr>\n";
  auto cell = [](ErrorMeasure measure, double value) {
    const std::string word = AccuracyWord(measure, value);
    if (WordRank(word) < 0) return std::string("<td class=\"w-na\">n/a</td>");
    return "<td class=\"num " + WordClass(word) + "\">" + FormatPercent(value) + " " + word +
           "</td>";
  };
  for (const auto& c : autofit["candidates"]) {
    const std::string model = StringField(c, "model");
    const nlohmann::json t = truth.is_object() && truth.contains(model) ? truth[model] : nullptr;
    html += "<tr><th>" + HtmlEscape(ModelName(model)) +
            (model == recommended ? " (recommended)" : "") + "</th>" +
            cell(ErrorMeasure::kInZone, Number(c, "cv_error")) +
            cell(ErrorMeasure::kInZone, Number(t, "error_in_zone")) +
            cell(ErrorMeasure::kHemisphere, Number(t, "error_cosine_l2")) + "</tr>\n";
  }
  return html + "</table>\n";
}

// The figure `zbrdf fit --figure` wrote with this fit (its report names it), if it is still there.
std::string ExistingFigure(const SessionInputs& in) {
  if (!in.fit_report.is_object() || !in.fit_report.contains("figure")) return "";
  const std::string named = StringField(in.fit_report["figure"], "path");
  if (named.empty()) return "";
  for (const fs::path& c :
       {fs::path(named), fs::path(in.dir) / named, fs::path(in.dir) / fs::path(named).filename()}) {
    if (c.is_relative() && c == fs::path(named)) continue;  // relative to an unknown folder
    std::error_code error;
    if (fs::is_regular_file(c, error)) return c.string();
  }
  return "";
}

}  // namespace

ErrorScale ScaleOf(ErrorMeasure measure) {
  switch (measure) {
    case ErrorMeasure::kInZone:
      return kInZoneScale;
    case ErrorMeasure::kHemisphere:
      return kHemisphereScale;
    case ErrorMeasure::kImage:
      return kImageScale;
  }
  return kInZoneScale;
}

std::string AccuracyWord(ErrorMeasure measure, double e) {
  if (!std::isfinite(e) || e < 0) return "n/a";
  const ErrorScale s = ScaleOf(measure);
  if (e < s.excellent) return "excellent";
  if (e < s.good) return "good";
  if (e < s.fair) return "fair";
  return "poor";
}

std::string FormatPercent(double fraction) {
  if (!std::isfinite(fraction)) return "n/a";
  const double percent = 100 * fraction;
  if (std::abs(percent) >= 100) return Printf("%.0f%%", percent);
  if (std::abs(percent) >= 10) return Printf("%.1f%%", percent);
  if (percent != 0 && std::abs(percent) < 0.01) return percent > 0 ? "<0.01%" : ">-0.01%";
  return Printf("%.2f%%", percent);
}

std::string SessionSummary::Verdict() const {
  if (std::none_of(errors.begin(), errors.end(), [](const SummaryError& e) {
        return e.id != "capture" && WordRank(e.Word()) >= 0;
      })) {
    return "n/a";
  }
  int worst = -1;
  std::string word = "n/a";
  for (const SummaryError& e : errors) {
    const std::string w = e.Word();
    if (WordRank(w) > worst) {
      worst = WordRank(w);
      word = w;
    }
  }
  return word;
}

nlohmann::json SessionSummary::ToJson() const {
  nlohmann::json errors_json = nlohmann::json::array();
  auto finite = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
  for (const SummaryError& e : errors) {
    errors_json.push_back({{"id", e.id},
                           {"label", e.label},
                           {"measure", static_cast<int>(e.measure)},
                           {"value", finite(e.value)},
                           {"word", e.Word()},
                           {"basis", e.basis},
                           {"missing", e.missing},
                           {"estimated", e.estimated}});
  }
  return {{"name", name},
          {"kind", kind},
          {"material", material},
          {"fit", fit},
          {"recommended", recommended},
          {"fit_file", fit_file},
          {"fit_why", fit_why},
          {"order", order},
          {"rig_time_s", finite(rig_time_s)},
          {"errors", errors_json},
          {"verdict", Verdict()},
          {"warnings", warnings},
          {"thumbnail_png", Base64Encode(thumbnail_png)}};
}

SessionSummary SessionSummary::FromJson(const nlohmann::json& j) {
  SessionSummary s;
  try {
    s.name = j.at("name").get<std::string>();
    s.kind = j.at("kind").get<std::string>();
    s.material = j.at("material").get<std::string>();
    s.fit = j.at("fit").get<std::string>();
    s.recommended = j.at("recommended").get<bool>();
    s.fit_file = j.at("fit_file").get<std::string>();
    s.fit_why = j.at("fit_why").get<std::string>();
    s.order = j.at("order").get<int>();
    s.rig_time_s = j.at("rig_time_s").is_number() ? j["rig_time_s"].get<double>() : kNaN;
    for (const auto& e : j.at("errors")) {
      const int measure = e.at("measure").get<int>();
      if (measure < 0 || measure > static_cast<int>(ErrorMeasure::kImage)) {
        throw InputError("unknown measure " + std::to_string(measure));
      }
      s.errors.push_back({e.at("id").get<std::string>(), e.at("label").get<std::string>(),
                          static_cast<ErrorMeasure>(measure),
                          e.at("value").is_number() ? e["value"].get<double>() : kNaN,
                          e.at("basis").get<std::string>(), e.at("missing").get<std::string>(),
                          e.at("estimated").get<bool>()});
    }
    s.warnings = j.at("warnings").get<std::vector<std::string>>();
    // Base64 back to bytes.
    const std::string text = j.at("thumbnail_png").get<std::string>();
    std::string bytes;
    uint32_t buffer = 0;
    int bits = 0;
    for (char c : text) {
      int v;
      if (c >= 'A' && c <= 'Z')
        v = c - 'A';
      else if (c >= 'a' && c <= 'z')
        v = c - 'a' + 26;
      else if (c >= '0' && c <= '9')
        v = c - '0' + 52;
      else if (c == '+')
        v = 62;
      else if (c == '/')
        v = 63;
      else if (c == '=')
        break;
      else
        throw InputError("thumbnail_png is not base64");
      buffer = (buffer << 6) | static_cast<uint32_t>(v);
      bits += 6;
      if (bits >= 8) {
        bits -= 8;
        bytes += static_cast<char>((buffer >> bits) & 0xff);
      }
    }
    s.thumbnail_png = bytes;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("report summary: ") + e.what());
  }
  return s;
}

std::string Base64Encode(const std::string& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = (static_cast<uint8_t>(bytes[i]) << 16) |
                       (static_cast<uint8_t>(bytes[i + 1]) << 8) |
                       static_cast<uint8_t>(bytes[i + 2]);
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i + 1 == bytes.size()) {
    const uint32_t v = static_cast<uint8_t>(bytes[i]) << 16;
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == bytes.size()) {
    const uint32_t v =
        (static_cast<uint8_t>(bytes[i]) << 16) | (static_cast<uint8_t>(bytes[i + 1]) << 8);
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

std::string HtmlEscape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

void ReportOptions::Validate() const {
  OptionChecker check("ReportOptions");
  check.InRange("preview_size", preview_size, 8, 8192)
      .AtLeast("preview_spp", preview_spp, 1)
      .AtLeast("metric_samples", static_cast<double>(metric_samples), 16)
      .ThrowIfInvalid();
}

SessionReportPage BuildSessionReport(const std::string& dir, const ReportOptions& options) {
  options.Validate();
  SessionInputs in = ReadInputs(dir);
  SessionReportPage page;
  page.notes = in.notes;
  const std::string zone = ZoneText(in.report, in.session);

  // The balls: the fit and the truth under the built-in sky, rendered with the same samples
  // (CompareMaterials), so that their difference image shows the materials more than the noise.
  // The image error is measured apart, without the noise.
  const Environment sky = Environment::Sky();
  BallOptions ball;
  ball.size = options.preview_size;
  ball.spp = options.preview_spp;
  std::optional<MaterialComparison> comparison;
  std::optional<ImageError> image_error;
  cv::Mat fit_ball, truth_ball;
  if (in.fitted && in.truth) {
    comparison = CompareMaterials(*in.truth, *in.fitted, &sky, ball, 0.0, options.metric_samples);
    // The image error on smaller balls with more samples per pixel: its noise correction is
    // steadier where the noise is smaller than the difference (brdf_compare.h).
    BallOptions error_ball = ball;
    error_ball.size = std::min(ball.size, kImageErrorSize);
    error_ball.spp = kImageErrorSppFactor * ball.spp;
    image_error = NoiseCorrectedImageError(*in.truth, *in.fitted, &sky, error_ball);
    truth_ball = ToneMap(comparison->a.image);
    fit_ball = ToneMap(comparison->b.image);
  } else if (in.fitted) {
    fit_ball = ToneMap(RenderBall(*in.fitted, &sky, ball).image);
  } else if (in.truth) {
    truth_ball = ToneMap(RenderBall(*in.truth, &sky, ball).image);
  }

  SessionSummary& s = page.summary;
  s.name = in.name;
  s.kind = StringField(in.session, "kind");
  s.material = in.truth_spec;
  s.fit = in.fitted ? in.fit_model : "";
  s.recommended = in.recommended;
  s.fit_file = in.fitted ? in.fit_file : "";
  s.fit_why = in.recommended ? StringField(in.autofit, "why") : "";
  s.order = OrderOf(in);
  s.rig_time_s = Number(in.report, "capture_time_model_s");
  s.errors =
      Errors(in, zone, comparison ? &*comparison : nullptr, image_error ? &*image_error : nullptr);
  s.warnings = Warnings(in);
  // The commands the texts suggest, for this session.
  for (SummaryError& e : s.errors) e.missing = WithSession(e.missing, dir);
  for (std::string& w : s.warnings) w = WithSession(w, dir);
  if (!fit_ball.empty()) s.thumbnail_png = EncodeBgrPng(Thumbnail(fit_ball));

  std::string body;
  page.sections.push_back("Summary");
  body += SummaryHtml(in, s, zone, fit_ball, truth_ball);

  // The pictures.
  if (comparison) {
    page.sections.push_back("Fit against truth");
    const MaterialComparison& c = *comparison;
    body += "<h2 id=\"against-truth\">Fit against truth</h2>\n" +
            Figure(c.side_by_side,
                   "A: truth, B: fit, and |Y_A - Y_B| relative to the truth's "
                   "brightest pixel (built-in sky)") +
            "<table><tr><th>image: relative RMSE of the balls, without the sampling noise</th>"
            "<td class=\"num\">" +
            FormatPercent(image_error->relative_rmse) +
            "</td></tr><tr><th>the noise it was corrected for (in quadrature; balls of " +
            std::to_string(std::min(ball.size, kImageErrorSize)) + " pixels, " +
            std::to_string(kImageErrorSppFactor * ball.spp) +
            " samples per pixel, two renders "
            "of each)</th><td class=\"num\">" +
            FormatPercent(image_error->relative_noise) +
            "</td></tr><tr><th>image: relative RMSE of the two renders above (" +
            std::to_string(ball.spp) +
            " samples per pixel, the same ones for both: their noise "
            "partly cancels)</th>"
            "<td class=\"num\">" +
            FormatPercent(c.relative_rmse) +
            "</td></tr><tr><th>cosine-weighted L2, relative, mean over channels (Monte Carlo, " +
            std::to_string(options.metric_samples) + " samples)</th><td class=\"num\">" +
            FormatPercent(c.distance.RelativeMean()) + "</td></tr></table>\n";
  }
  if (in.fitted || in.truth) {
    page.sections.push_back("Material balls");
    body += "<h2 id=\"balls\">Material balls under a directional light</h2>\n";
    BallOptions directional = ball;
    directional.light_direction = Vec3{0.5, 0.5, std::sqrt(0.5)};
    const std::string caption = "directional light, 45 deg from the view, upper right";
    if (in.fitted) {
      body +=
          Figure(ToneMap(RenderBall(*in.fitted, nullptr, directional).image), "fit: " + caption);
    }
    if (in.truth) {
      body +=
          Figure(ToneMap(RenderBall(*in.truth, nullptr, directional).image), "truth: " + caption);
    }

    // The turntable `zbrdf preview SESSION --turntable N` wrote, as the animated PNG it is.
    const std::string turntable = SessionPath(dir, "turntable/animation.png");
    if (std::filesystem::is_regular_file(turntable)) {
      const nlohmann::json record = ReadJson(SessionPath(dir, "turntable/animation.json"));
      std::string caption = "turntable";
      if (record.is_object()) {
        caption = "turntable: " + std::to_string(record.value("frames", 0)) + " frames at " +
                  std::to_string(record.value("fps", 0)) + " fps, " +
                  record.value("sampler", std::string("?")) + " sampling, " +
                  std::to_string(record.value("spp", 0)) + " samples per pixel, " +
                  record.value("lighting", std::string("?")) + ", rendered in " +
                  Printf("%.1f s", record.value("seconds", 0.0));
      }
      page.sections.push_back("Turntable");
      body += "<h2 id=\"turntable\">Turntable</h2>\n<figure id=\"turntable-animation\">" +
              ImageTag(ReadBytes(turntable), caption) + "<figcaption>" + HtmlEscape(caption) +
              "</figcaption></figure>\n";
    } else {
      page.notes.push_back("no turntable: zbrdf preview " + dir +
                           " --turntable 30 --environment studio --sampler smc --spp 16 adds one");
    }

    page.sections.push_back("Polar plots");
    body += "<h2 id=\"polar\">f_r in the plane of incidence</h2>\n";
    std::vector<std::pair<std::string, const Brdf*>> brdfs;
    if (in.fitted) brdfs.emplace_back("fit (" + in.fit_model + ")", in.fitted.get());
    if (in.truth) brdfs.emplace_back("truth (" + in.truth_spec + ")", in.truth.get());
    for (bool log_scale : {false, true}) {
      for (const auto& [what, brdf] : brdfs) {
        const auto slices = IncidencePlaneSlices(*brdf, {0, 30, 60, 75});
        body += Figure(DrawIncidenceSlices(slices, what.substr(0, 100), log_scale),
                       what + ": " + (log_scale ? "log10 scale" : "linear scale"));
      }
    }
  }

  // Figure 3.3 of the thesis: truth | SH of the zonal data | fit.
  {
    const std::string existing = ExistingFigure(in);
    std::string figure_html;
    if (!existing.empty()) {
      figure_html = "<figure>" + ImageTag(ReadBytes(existing), "figure 3.3") + "<figcaption>" +
                    HtmlEscape(fs::path(existing).filename().string()) +
                    " (zbrdf fit --figure): ground truth | SH | fit</figcaption></figure>\n";
    } else if (in.fitted) {
      std::vector<FigurePanel> panels;
      std::unique_ptr<ShBrdf> sh;
      if (in.truth) panels.push_back({"ground truth", CosineWeightedOf(*in.truth)});
      const std::vector<std::string> sh_files = SessionShFiles(dir);
      if (!sh_files.empty() && in.fit_model != "sh") {
        try {
          sh = std::make_unique<ShBrdf>(ReadShFile(sh_files.front()), sh_files.front());
          const ShBrdf* p = sh.get();
          panels.push_back({"SH order " + std::to_string(p->data().order) + " (zonal data)",
                            [p](const Vec3& w_o, std::span<const Vec3> w_i, std::span<Rgb> f) {
                              p->CosineWeightedBatch(w_o, w_i, f);
                            }});
        } catch (const InputError& e) {
          page.notes.push_back(e.what());
        }
      }
      panels.push_back({in.fit_model + " fit", CosineWeightedOf(*in.fitted)});
      if (panels.size() >= 2) {
        figure_html = Figure(DrawSphereFigure(panels, options.preview_size),
                             "one directional light 40 deg from the view; magenta: f^ < 0");
      } else {
        page.notes.push_back(
            "figure 3.3 needs the truth or an SH conversion beside the fit "
            "(zbrdf convert SESSION --to sh)");
      }
    }
    if (!figure_html.empty()) {
      page.sections.push_back("Figure 3.3");
      body +=
          "<h2 id=\"figure-3-3\">Ground truth, SH and fit (the layout of the thesis's figure "
          "3.3)</h2>\n" +
          figure_html;
    }
  }

  const std::string candidates = CandidatesHtml(in.autofit);
  if (!candidates.empty()) {
    page.sections.push_back("Fit candidates");
    body += "<h2 id=\"candidates\">Fit candidates (zbrdf fit --model auto)</h2>\n" + candidates +
            "<p class=\"why\">" + HtmlEscape(StringField(in.autofit, "why")) + "</p>\n";
  }

  // Coefficient energy per band.
  std::vector<BandEnergy> energies;
  try {
    if (fs::exists(SessionPath(dir, kZonalFile)))
      energies.push_back(ZonalBandEnergy(ReadZonalExr(SessionPath(dir, kZonalFile))));
    const std::vector<std::string> sh_files = SessionShFiles(dir);
    if (!sh_files.empty()) energies.push_back(ShBandEnergy(ReadShFile(sh_files.front())));
  } catch (const InputError& e) {
    page.notes.push_back(e.what());
    body += "<div class=\"error\">" + HtmlEscape(e.what()) + "</div>\n";
  }
  if (!energies.empty()) {
    page.sections.push_back("Coefficient energy");
    body += "<h2 id=\"energy\">Coefficient energy per band</h2>\n" +
            Figure(DrawBandEnergy(energies, "sum of squared coefficients per band l"),
                   "zonal (and SH) coefficients");
  } else {
    page.notes.push_back("no zonal.exr: no coefficient plot");
  }

  // Calibration.
  const std::string graycard = FindCalibrationFigure(dir, in.session);
  page.sections.push_back("Calibration");
  body += "<h2 id=\"calibration\">Calibration</h2>\n<p>" +
          HtmlEscape(StringField(in.session, "calibration")) + "</p>\n";
  if (!graycard.empty()) {
    body += "<figure>" + ImageTag(ReadBytes(graycard), "gray card") + "<figcaption>" +
            HtmlEscape(graycard) + "</figcaption></figure>\n";
  } else {
    page.notes.push_back("no calibration figure (graycard.png)");
    body +=
        "<div class=\"note\">No calibration figure (graycard.png in the session or its "
        "calibration folder).</div>\n";
  }

  // The raw metadata, folded.
  for (std::string& note : page.notes) note = WithSession(note, dir);
  page.sections.push_back("Raw metadata");
  body += "<h2 id=\"raw\">Raw metadata</h2>\n<section id=\"raw-metadata\">\n";
  auto fold = [&body](const std::string& title, const std::string& content) {
    body += "<details><summary>" + HtmlEscape(title) + "</summary>\n" + content + "</details>\n";
  };
  if (!page.notes.empty()) {
    std::string notes;
    for (const std::string& n : page.notes)
      notes += "<div class=\"note\">" + HtmlEscape(n) + "</div>\n";
    fold("What is missing (" + std::to_string(page.notes.size()) + ")", notes);
  }
  fold("session.json: settings, devices, plan", JsonTable(in.session));
  if (in.report.is_object()) fold("report.json: timings and errors", JsonTable(in.report));
  if (in.autofit.is_object()) fold("fit-auto.json: the recommendation", JsonTable(in.autofit));
  if (in.fit_report.is_object()) {
    fold(fs::path(in.fit_report_path).filename().string() + ": the fit", JsonTable(in.fit_report));
  }
  std::vector<std::pair<std::string, uintmax_t>> files;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    if (entry.is_regular_file())
      files.emplace_back(entry.path().filename().string(), entry.file_size());
    if (entry.is_directory()) files.emplace_back(entry.path().filename().string() + "/", 0);
  }
  std::sort(files.begin(), files.end());
  std::string file_table = "<table><tr><th>file</th><th>bytes</th></tr>";
  for (const auto& [file, bytes] : files) {
    file_table += "<tr><td>" + HtmlEscape(file) + "</td><td class=\"num\">" +
                  std::to_string(bytes) + "</td></tr>";
  }
  fold("files (" + std::to_string(files.size()) + ") in " + dir, file_table + "</table>\n");
  body += "</section>\n";

  page.html = "<!DOCTYPE html>\n" + std::string(kSummaryMarker) + CommentSafeJson(s.ToJson()) +
              " -->\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>zbrdf: " +
              HtmlEscape(s.material.empty() ? in.name : s.material + " (" + in.name + ")") +
              "</title><style>" + kStyle + "</style></head><body>\n" + body + "</body></html>\n";
  return page;
}

std::optional<SessionSummary> ReadReportSummary(const std::string& page_path) {
  // The summary is on the page's second line; a thumbnail is about 20 KB of base64.
  const std::string head = ReadBytes(page_path, 1 << 20);
  const size_t start = head.find(kSummaryMarker);
  if (start == std::string::npos || start > 64) return std::nullopt;
  const size_t from = start + std::string(kSummaryMarker).size();
  const size_t end = head.find("-->", from);
  if (end == std::string::npos) return std::nullopt;
  const nlohmann::json j = nlohmann::json::parse(head.substr(from, end - from), nullptr, false);
  if (j.is_discarded()) return std::nullopt;
  try {
    return SessionSummary::FromJson(j);
  } catch (const InputError&) {
    return std::nullopt;
  }
}

namespace {

void FindSessions(const fs::path& dir, int depth, int max_depth, std::vector<std::string>* out) {
  if (depth > max_depth) return;
  std::vector<fs::path> folders;
  std::error_code error;
  for (const auto& entry :
       fs::directory_iterator(dir, fs::directory_options::skip_permission_denied, error)) {
    std::error_code e;
    const std::string name = entry.path().filename().string();
    if (!name.empty() && name[0] != '.' && entry.is_directory(e)) folders.push_back(entry.path());
  }
  std::sort(folders.begin(), folders.end());
  for (const fs::path& folder : folders) {
    if (SessionFolder::Exists(folder.string())) {
      out->push_back(folder.string());
    } else {
      FindSessions(folder, depth + 1, max_depth, out);
    }
  }
}

}  // namespace

std::vector<std::string> FindSessionFolders(const std::string& dir, int max_depth) {
  std::vector<std::string> out;
  FindSessions(fs::path(dir), 1, max_depth, &out);
  return out;
}

bool SessionReportIsStale(const std::string& dir) {
  const std::string page = SessionPath(dir, kReportPageFile);
  std::error_code error;
  const fs::file_time_type page_time = fs::last_write_time(page, error);
  if (error) return true;
  std::vector<fs::path> inputs;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    std::error_code e;
    // The page itself, the writer lock (rewritten by every writer) and files being written.
    if (!entry.is_regular_file(e) || name == kReportPageFile || name == kLockFile ||
        name.find(".tmp") != std::string::npos) {
      continue;
    }
    inputs.push_back(entry.path());
  }
  const std::string graycard = FindCalibrationFigure(dir, ReadJson(SessionPath(dir, kSessionFile)));
  if (!graycard.empty()) inputs.emplace_back(graycard);
  for (const fs::path& input : inputs) {
    std::error_code e;
    const fs::file_time_type t = fs::last_write_time(input, e);
    if (!e && t > page_time) return true;
  }
  return !ReadReportSummary(page).has_value();
}

std::string BuildIndexPage(const std::string& index_path, const std::vector<IndexRow>& rows) {
  const fs::path base = fs::absolute(fs::path(index_path)).parent_path();
  auto link = [&base](const std::string& path) {
    std::error_code error;
    fs::path relative = fs::relative(fs::absolute(path), base, error);
    if (error || relative.empty()) relative = fs::absolute(path);
    // Relative URLs: path segments as they are, with the characters HTML and URLs reserve
    // percent-encoded.
    std::string url;
    for (unsigned char c : relative.generic_string()) {
      if (std::isalnum(c) ||
          std::string("/-_.~+,=@").find(static_cast<char>(c)) != std::string::npos) {
        url += static_cast<char>(c);
      } else {
        url += Printf("%%%02X", c);
      }
    }
    return url;
  };
  std::string body;
  body += "<h1>zbrdf sessions: " + HtmlEscape(FolderName(base.string())) +
          "</h1>\n<p class=\"sub\">" + std::to_string(rows.size()) + " sessions under " +
          HtmlEscape(base.string()) + ", index of " + NowUtc() + "</p>\n" + ScaleDetails();
  body +=
      "<table id=\"sessions\"><tr><th>ball</th><th>session, material</th><th>fit</th>"
      "<th>accuracy</th><th>fit, in the zone</th><th>fit, whole hemisphere</th>"
      "<th>image</th><th>capture, in the zone</th><th>rig time</th><th>warnings</th></tr>\n";
  for (const IndexRow& row : rows) {
    const std::string report = link(row.report_path);
    const std::string folder = link(row.session_dir) + "/";
    const std::string name = FolderName(row.session_dir);
    const std::string where = "<br><span class=\"why\">" + HtmlEscape(link(row.session_dir)) +
                              " &middot; <a href=\"" + folder + "\">folder</a></span>";
    body += "<tr class=\"session\">";
    if (!row.summary) {
      body += "<td></td><td><b>" + HtmlEscape(name) + "</b>" + where +
              "</td><td colspan=\"8\" class=\"error\">no report: " + HtmlEscape(row.error) +
              "</td></tr>\n";
      continue;
    }
    const SessionSummary& s = *row.summary;
    body += "<td>" +
            (s.thumbnail_png.empty() ? std::string("<span class=\"why\">no BRDF yet</span>")
                                     : "<a href=\"" + report + "\">" +
                                           ImageTag(s.thumbnail_png, "ball of " + name,
                                                    kThumbnailSize, kThumbnailSize) +
                                           "</a>") +
            "</td>";
    body += "<td><a href=\"" + report + "\">" + HtmlEscape(name) + "</a><br><b>" +
            HtmlEscape(MaterialLabel(s)) + "</b>" + where + "</td>";
    body += "<td>" + (s.fit.empty() ? std::string("none yet") : HtmlEscape(s.fit)) +
            (s.recommended ? "<br><span class=\"why\">recommended</span>" : "") +
            (s.order >= 0 ? "<br><span class=\"why\">order " + std::to_string(s.order) + "</span>"
                          : "") +
            "</td>";
    const std::string verdict = s.Verdict();
    body +=
        "<td class=\"" + WordClass(verdict) + "\"><span class=\"word\">" + verdict + "</span></td>";
    body += IndexErrorCell(s, "zone") + IndexErrorCell(s, "hemisphere") +
            IndexErrorCell(s, "image") + IndexErrorCell(s, "capture");
    body += "<td class=\"num\">" + FormatSeconds(s.rig_time_s) + "</td>";
    body += "<td>" +
            (s.warnings.empty() ? std::string("<span class=\"ok\">none</span>")
                                : "<span title=\"" + HtmlEscape(s.warnings.front()) + "\">" +
                                      std::to_string(s.warnings.size()) + "</span>") +
            "</td></tr>\n";
  }
  body += "</table>\n";
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>zbrdf: " +
         HtmlEscape(FolderName(base.string())) + " (" + std::to_string(rows.size()) +
         " sessions)</title><style>" + kStyle + "</style></head><body>\n" + body +
         "</body></html>\n";
}

FolderReport WriteFolderReport(const std::string& dir, const std::string& index_path,
                               const ReportOptions& options, bool rebuild) {
  options.Validate();
  const std::vector<std::string> sessions = FindSessionFolders(dir, kSearchDepth);
  if (sessions.empty()) {
    throw InputError(dir +
                     " is neither a session folder (no session.json) nor a folder holding "
                     "sessions (none within " +
                     std::to_string(kSearchDepth) +
                     " levels below it); give a folder zbrdf simulate or zbrdf capture wrote, or "
                     "a folder above such folders");
  }
  FolderReport result;
  std::vector<IndexRow> rows;
  for (const std::string& session : sessions) {
    IndexRow row;
    row.session_dir = session;
    row.report_path = SessionPath(session, kReportPageFile);
    try {
      if (rebuild || SessionReportIsStale(session)) {
        SessionReportPage page = BuildSessionReport(session, options);
        WriteFileAtomically(row.report_path, page.html);
        row.summary = std::move(page.summary);
        result.written.push_back(row.report_path);
      } else {
        row.summary = ReadReportSummary(row.report_path);
        result.kept.push_back(row.report_path);
      }
    } catch (const InputError& e) {
      row.error = e.what();
    } catch (const NumericalError& e) {
      row.error = e.what();
    }
    if (!row.summary) result.failed.push_back(session + ": " + row.error);
    rows.push_back(std::move(row));
  }
  WriteFileAtomically(index_path, BuildIndexPage(index_path, rows));
  result.index = index_path;
  return result;
}

}  // namespace zbrdf
