#include "pictures/html_report.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "acquisition/session.h"
#include "acquisition/session_brdf.h"
#include "acquisition/zonal.h"
#include "basis/error.h"
#include "basis/option_checker.h"
#include "brdf/material_spec.h"
#include "brdf/sh_file.h"
#include "pictures/brdf_compare.h"
#include "pictures/brdf_plots.h"
#include "pictures/environment.h"
#include "pictures/image.h"
#include "pictures/material_ball.h"

namespace zbrdf {
namespace {

namespace fs = std::filesystem;

constexpr const char* kStyle =
    "body{font-family:sans-serif;max-width:1200px;margin:2em auto;color:#222;line-height:1.4}"
    "h1{font-size:1.6em}h2{font-size:1.25em;border-bottom:1px solid #ccc;margin-top:2em}"
    "table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ddd;padding:.25em .6em;"
    "text-align:left;vertical-align:top}th{background:#f4f4f4}img{max-width:100%;margin:.3em 0}"
    ".note{background:#fff6d8;border-left:4px solid #e0b000;padding:.4em .8em;margin:.5em 0}"
    ".error{background:#fde8e8;border-left:4px solid #d03030;padding:.4em .8em;margin:.5em 0}"
    "figure{display:inline-block;margin:.5em 1em .5em 0}figcaption{font-size:.85em;color:#555}"
    "pre{background:#f7f7f7;padding:.6em;overflow:auto;font-size:.85em}";

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream file(path);
  if (!file) return nullptr;
  nlohmann::json j = nlohmann::json::parse(file, nullptr, false);
  return j.is_discarded() ? nlohmann::json(nullptr) : j;
}

std::string ReadBytes(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

std::string ImageTag(const std::string& png_bytes, const std::string& alt) {
  return "<img alt=\"" + HtmlEscape(alt) + "\" src=\"data:image/png;base64," +
         Base64Encode(png_bytes) + "\">";
}

std::string Figure(const cv::Mat& image, const std::string& caption) {
  return "<figure>" + ImageTag(EncodePng(image), caption) + "<figcaption>" + HtmlEscape(caption) +
         "</figcaption></figure>\n";
}

std::string Scalar(const nlohmann::json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_float()) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.5g", v.get<double>());
    return text;
  }
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

// Keys anywhere in report.json that name errors, warnings or failures, with their values.
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

}  // namespace

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
  std::optional<SessionFolder> folder;
  try {
    folder = SessionFolder::Open(dir);
  } catch (const InputError& e) {
    throw InputError(dir + " is not a session folder (" + e.what() +
                     "); give the folder zbrdf simulate or zbrdf capture wrote");
  }
  const nlohmann::json& session = folder->session();
  const nlohmann::json report = ReadJson(SessionPath(dir, kReportFile));
  SessionReportPage page;
  std::string body;
  const std::string name = fs::path(dir).filename().empty()
                               ? fs::path(dir).parent_path().filename().string()
                               : fs::path(dir).filename().string();
  body += "<h1>zbrdf session report: " + HtmlEscape(name) + "</h1>\n<p>" + HtmlEscape(dir) +
          ", generated " + NowUtc() + ".</p>\n";

  // What was measured.
  page.sections.push_back("Session");
  body += "<h2>Session</h2>\n" + JsonTable(session);

  // Timings and errors.
  page.sections.push_back("Timings and errors");
  body += "<h2>Timings and errors</h2>\n";
  if (report.is_object()) {
    std::vector<std::string> problems;
    CollectProblems(report, "", &problems);
    CollectProblems(session, "session", &problems);
    for (const std::string& p : problems)
      body += "<div class=\"error\">" + HtmlEscape(p) + "</div>\n";
    if (report.contains("wall_time_s") && report["wall_time_s"].is_object()) {
      body += "<h3>Wall time (s)</h3>" + JsonTable(report["wall_time_s"]);
    }
    body += "<h3>report.json</h3>" + JsonTable(report);
  } else {
    page.notes.push_back("no report.json: the session has not been processed");
    body += "<div class=\"note\">No report.json: the session has not been processed yet.</div>\n";
  }

  // Calibration.
  const std::string graycard = FindCalibrationFigure(dir, session);
  page.sections.push_back("Calibration");
  body += "<h2>Calibration</h2>\n";
  if (!graycard.empty()) {
    body += "<figure>" + ImageTag(ReadBytes(graycard), "gray card") + "<figcaption>" +
            HtmlEscape(graycard) + "</figcaption></figure>\n";
  } else {
    page.notes.push_back("no calibration figure (graycard.png)");
    body +=
        "<div class=\"note\">No calibration figure (graycard.png in the session or its "
        "calibration folder).</div>\n";
  }

  // The BRDF: the session's fit or conversion; the true material of a simulated session.
  std::shared_ptr<const Brdf> fitted, truth;
  std::string fitted_what, truth_spec;
  try {
    const BrdfFile file = ReadSessionBrdf(dir);
    fitted = file.brdf;
    fitted_what = "session " + dir + ": " + file.description;
  } catch (const InputError& e) {
    page.notes.push_back(e.what());
    body += "<div class=\"note\">" + HtmlEscape(e.what()) + "</div>\n";
  }
  if (!folder->material().empty()) {
    truth_spec = folder->material();
    try {
      truth = MakeBrdf(truth_spec);
    } catch (const InputError& e) {
      page.notes.push_back(std::string("true material: ") + e.what());
    }
  }
  const Environment sky = Environment::Sky();
  BallOptions ball;
  ball.size = options.preview_size;
  ball.spp = options.preview_spp;
  auto previews = [&](const Brdf& brdf, const std::string& what) {
    std::string html;
    BallOptions directional = ball;
    directional.light_direction = Vec3{0.5, 0.5, std::sqrt(0.5)};
    html += Figure(ToneMap(RenderBall(brdf, nullptr, directional).image),
                   what + ": directional light (45 deg from the view, upper right)");
    html += Figure(ToneMap(RenderBall(brdf, &sky, ball).image), what + ": built-in sky");
    const auto slices = IncidencePlaneSlices(brdf, {0, 30, 60, 75});
    html += "<br>" + Figure(DrawIncidenceSlices(slices, what.substr(0, 100), false),
                            "f_r in the plane of incidence (linear)");
    html += Figure(DrawIncidenceSlices(slices, what.substr(0, 100), true),
                   "f_r in the plane of incidence (log10)");
    return html;
  };
  if (fitted) {
    page.sections.push_back("Fitted BRDF");
    std::string choice;
    const nlohmann::json autofit = ReadJson(SessionPath(dir, kAutoFitFile));
    if (autofit.is_object() && autofit.contains("recommended")) {
      // The recommendation of `zbrdf fit --model auto` and its reason (docs/prior.md).
      choice = "<p>Recommended by <code>zbrdf fit --model auto</code>: <b>" +
               HtmlEscape(autofit.value("recommended", std::string())) + "</b>. " +
               HtmlEscape(autofit.value("why", std::string())) + "</p>\n";
    }
    body += "<h2>Fitted BRDF</h2>\n<p>" + HtmlEscape(fitted_what) + "</p>\n" + choice +
            previews(*fitted, "fit");
  }
  if (truth) {
    page.sections.push_back("True material");
    body += "<h2>True material (simulated session)</h2>\n<p>" + HtmlEscape(truth_spec) + "</p>\n" +
            previews(*truth, "truth");
  }
  if (fitted && truth) {
    page.sections.push_back("Fit against truth");
    const MaterialComparison c =
        CompareMaterials(*truth, *fitted, &sky, ball, 0.0, options.metric_samples);
    body += "<h2>Fit against truth</h2>\n" +
            Figure(c.side_by_side, "A: truth, B: fit, difference") + JsonTable(c.ToJson());
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
    body += "<h2>Coefficient energy per band</h2>\n" +
            Figure(DrawBandEnergy(energies, "sum of squared coefficients per band l"),
                   "zonal (and SH) coefficients");
  } else {
    page.notes.push_back("no zonal.exr: no coefficient plot");
  }

  // The files.
  page.sections.push_back("Files");
  body += "<h2>Files</h2>\n<table><tr><th>file</th><th>bytes</th></tr>";
  std::vector<std::pair<std::string, uintmax_t>> files;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    if (entry.is_regular_file())
      files.emplace_back(entry.path().filename().string(), entry.file_size());
    if (entry.is_directory()) files.emplace_back(entry.path().filename().string() + "/", 0);
  }
  std::sort(files.begin(), files.end());
  for (const auto& [file, bytes] : files) {
    body += "<tr><td>" + HtmlEscape(file) + "</td><td>" + std::to_string(bytes) + "</td></tr>";
  }
  body += "</table>\n";
  page.html = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>zbrdf: " +
              HtmlEscape(name) + "</title><style>" + kStyle + "</style></head><body>\n" + body +
              "</body></html>\n";
  return page;
}

}  // namespace zbrdf
