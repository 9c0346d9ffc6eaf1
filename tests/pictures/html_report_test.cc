// The session report page and the folder index: what the first screen says (the summary before
// every other section, the raw metadata last and folded), the words for errors at the thresholds
// docs/preview.md gives, n/a for what is missing or not finite, and the index's rows and links.
// tests/tools/report_browser_test.sh checks the same pages in a browser.
#include "pictures/html_report.h"

#include <gtest/gtest.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <regex>

#include "acquisition/zonal.h"
#include "basis/error.h"
#include "pictures/image.h"
#include "tests/acquisition/session_fixture.h"
#include "tests/test_files.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

namespace fs = std::filesystem;
using testing::TempDir;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

ReportOptions SmallOptions() {
  ReportOptions options;
  options.preview_size = 32;
  options.preview_spp = 2;
  options.metric_samples = 1024;
  return options;
}

// A simulated session: zonal.exr, report.json with a warning, a GGX fit close to the truth.
void MakeFittedSession(const std::string& dir,
                       const nlohmann::json& fit = {{"spec", "ggx:alpha=0.32,F0=0.48,kd=0.1"},
                                                    {"model", "ggx"},
                                                    {"error_in_zone", 0.012},
                                                    {"error_cosine_l2", 0.25}}) {
  fs::create_directories(dir);
  testing::WriteSessionJson(dir, "ggx:alpha=0.3,F0=0.5,kd=0.1");
  testing::WriteJson(dir + "/report.json", {{"wall_time_s", {{"simulate", 1.5}, {"total", 3.25}}},
                                            {"capture_time_model_s", 86.4},
                                            {"coefficient_error_in_zone", 0.027},
                                            {"order", 2},
                                            {"zone_deg", {9.0, 57.0}},
                                            {"warnings", {"exposure bracket clipped 3 pixels"}}});
  WriteZonalExr(dir + "/zonal.exr", testing::MakeZonalData());
  testing::WriteJson(dir + "/fit-ggx.json", fit);
}

// The page without its images' base64 and its summary comment (where any word may occur).
// (std::regex recurses per character and overflows the stack on pages this long.)
std::string TextOf(std::string html) {
  const size_t comment = html.find("<!-- zbrdf-summary ");
  if (comment != std::string::npos) html.erase(comment, html.find("-->", comment) + 3 - comment);
  std::string out;
  for (size_t at = 0; at < html.size();) {
    const size_t data = html.find("base64,", at);
    if (data == std::string::npos) {
      out += html.substr(at);
      break;
    }
    out += html.substr(at, data + 7 - at);
    at = data + 7;
    while (at < html.size() && (std::isalnum(static_cast<unsigned char>(html[at])) ||
                                html[at] == '+' || html[at] == '/' || html[at] == '=')) {
      ++at;
    }
  }
  return out;
}

// `html` with every <details> element (nested ones inside) cut out.
std::string WithoutDetails(const std::string& html) {
  std::string out;
  int depth = 0;
  for (size_t at = 0; at < html.size();) {
    const size_t open = html.find("<details", at), close = html.find("</details>", at);
    const size_t next = std::min(open, close);
    if (next == std::string::npos) {
      if (depth == 0) out += html.substr(at);
      break;
    }
    if (depth == 0) out += html.substr(at, next - at);
    if (next == open) {
      ++depth;
      at = open + 8;
    } else {
      depth = std::max(0, depth - 1);
      at = close + 10;
      if (depth == 0 && at < html.size() && html[at] == '\n') ++at;
    }
  }
  return out;
}

TEST(Base64, Rfc4648Vectors) {
  EXPECT_EQ(Base64Encode(""), "");
  EXPECT_EQ(Base64Encode("f"), "Zg==");
  EXPECT_EQ(Base64Encode("fo"), "Zm8=");
  EXPECT_EQ(Base64Encode("foo"), "Zm9v");
  EXPECT_EQ(Base64Encode("foob"), "Zm9vYg==");
  EXPECT_EQ(Base64Encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(Base64Encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(Base64Encode(std::string("\xff\x00\x80", 3)), "/wCA");
  EXPECT_EQ(HtmlEscape("<a href=\"x\">&'"), "&lt;a href=&quot;x&quot;&gt;&amp;&#39;");
}

// The thresholds as docs/preview.md ("Words for errors") states them, not read from the code:
// just below each bound the better word, at it the worse one.
TEST(AccuracyWord, ThresholdsAreTheDocumentedOnes) {
  struct Case {
    ErrorMeasure measure;
    double excellent, good, fair;
  };
  for (const Case& c : {Case{ErrorMeasure::kInZone, 0.05, 0.15, 0.30},
                        Case{ErrorMeasure::kHemisphere, 0.20, 0.40, 0.60},
                        Case{ErrorMeasure::kImage, 0.03, 0.07, 0.15}}) {
    const double below = 1 - 1e-9;
    EXPECT_EQ(AccuracyWord(c.measure, 0.0), "excellent");
    EXPECT_EQ(AccuracyWord(c.measure, c.excellent * below), "excellent");
    EXPECT_EQ(AccuracyWord(c.measure, c.excellent), "good");
    EXPECT_EQ(AccuracyWord(c.measure, c.good * below), "good");
    EXPECT_EQ(AccuracyWord(c.measure, c.good), "fair");
    EXPECT_EQ(AccuracyWord(c.measure, c.fair * below), "fair");
    EXPECT_EQ(AccuracyWord(c.measure, c.fair), "poor");
    EXPECT_EQ(AccuracyWord(c.measure, 7.5), "poor");
    for (double bad : {kNaN, std::numeric_limits<double>::infinity(), -0.01}) {
      EXPECT_EQ(AccuracyWord(c.measure, bad), "n/a") << bad;
    }
  }
}

TEST(FormatPercent, DigitsAndNonFiniteValues) {
  EXPECT_EQ(FormatPercent(0.2389), "23.9%");
  EXPECT_EQ(FormatPercent(0.02742), "2.74%");
  EXPECT_EQ(FormatPercent(5.03), "503%");
  EXPECT_EQ(FormatPercent(0.0), "0.00%");
  EXPECT_EQ(FormatPercent(1e-6), "<0.01%");
  EXPECT_EQ(FormatPercent(kNaN), "n/a");
  EXPECT_EQ(FormatPercent(-std::numeric_limits<double>::infinity()), "n/a");
}

TEST(SessionReport, TheSummaryComesFirstAndTheRawMetadataLastFolded) {
  TempDir dir("report");
  MakeFittedSession(dir.path());
  fs::create_directories(dir.File("calibration"));
  const cv::Mat card(20, 30, CV_8UC3, cv::Scalar(120, 120, 120));
  WritePng(dir.File("calibration/graycard.png"), card);
  const SessionReportPage page = BuildSessionReport(dir.path(), SmallOptions());

  // Sections in page order: the answer first, the pictures, the raw metadata last.
  // Figure 3.3 without an SH conversion: the truth and the fit.
  const std::vector<std::string> expected = {
      "Summary",    "Fit against truth",  "Material balls", "Polar plots",
      "Figure 3.3", "Coefficient energy", "Calibration",    "Raw metadata"};
  EXPECT_EQ(page.sections, expected);
  const std::string& html = page.html;
  const size_t summary = html.find("id=\"summary\""), first_h2 = html.find("<h2");
  const size_t raw = html.find("id=\"raw-metadata\"");
  ASSERT_NE(summary, std::string::npos);
  ASSERT_NE(raw, std::string::npos);
  EXPECT_LT(summary, first_h2);
  // The summary holds both balls, the verdict, the fit, the errors, the rig time and the
  // warnings, before any other section.
  for (const char* id :
       {"ball-fit", "ball-truth", "verdict", "fit", "errors", "rig-time", "warnings"}) {
    const size_t at = html.find(std::string("id=\"") + id + "\"");
    EXPECT_GT(at, summary) << id;
    EXPECT_LT(at, first_h2) << id;
  }
  const std::string head = html.substr(summary, first_h2 - summary);
  EXPECT_NE(head.find("exposure bracket clipped 3 pixels"), std::string::npos);
  EXPECT_NE(head.find("86.4 s"), std::string::npos);
  EXPECT_NE(head.find("GGX"), std::string::npos);
  // The fit's errors in numbers and words: 1.2% in the zone, 25.0% over the hemisphere; the
  // capture's 2.70%.
  EXPECT_NE(head.find("1.20%</td><td class=\"w-excellent\""), std::string::npos);
  EXPECT_NE(head.find("25.0%</td><td class=\"w-good\""), std::string::npos);
  EXPECT_NE(head.find("2.70%</td><td class=\"w-excellent\""), std::string::npos);
  // After the raw-metadata mark nothing but folded <details> (and the section's end).
  const std::string tail = html.substr(raw);
  EXPECT_EQ(WithoutDetails(TextOf(tail)), "id=\"raw-metadata\">\n</section>\n</body></html>\n");
  // session.json's and report.json's keys are only there.
  EXPECT_GT(html.find("<th>wall_time_s</th>"), raw);
  EXPECT_GT(html.find("<th>calibration</th>"), raw);

  // Self-contained: no external resources of any kind, no script.
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  const std::regex src(R"(src="([^"]{0,12}))");
  int images = 0;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), src); it != std::sregex_iterator();
       ++it) {
    EXPECT_EQ((*it)[1].str().rfind("data:image/", 0), 0u) << (*it)[1];
    ++images;
  }
  EXPECT_GE(images, 9);
  // The calibration figure is embedded byte for byte.
  EXPECT_NE(html.find(Base64Encode(testing::ReadFile(dir.File("calibration/graycard.png")))),
            std::string::npos);
  EXPECT_FALSE(std::regex_search(TextOf(html), std::regex("\\b(NaN|nan|inf|Infinity)\\b")));
}

TEST(SessionReport, MissingAndNonFiniteNumbersReadNaWithTheReason) {
  TempDir dir("report_na");
  // nlohmann writes a non-finite number as null: the fit report's comparison gave none, and the
  // rig time is missing.
  MakeFittedSession(dir.path(), {{"spec", "ggx:alpha=0.32,F0=0.48,kd=0.1"},
                                 {"model", "ggx"},
                                 {"error_in_zone", nullptr},
                                 {"error_cosine_l2", kNaN}});
  nlohmann::json report = nlohmann::json::parse(testing::ReadFile(dir.File("report.json")));
  report.erase("capture_time_model_s");
  testing::WriteJson(dir.File("report.json"), report);
  const SessionReportPage page = BuildSessionReport(dir.path(), SmallOptions());
  const SessionSummary& s = page.summary;
  ASSERT_EQ(s.errors.size(), 4u);
  EXPECT_EQ(s.errors[1].id, "zone");
  EXPECT_TRUE(std::isnan(s.errors[1].value));
  EXPECT_EQ(s.errors[1].Word(), "n/a");
  EXPECT_NE(s.errors[1].missing.find("no finite number"), std::string::npos);
  // Over the hemisphere the report estimates the distance itself.
  EXPECT_EQ(s.errors[2].id, "hemisphere");
  EXPECT_TRUE(std::isfinite(s.errors[2].value));
  EXPECT_NE(s.errors[2].basis.find("Monte Carlo"), std::string::npos);
  EXPECT_TRUE(std::isnan(s.rig_time_s));
  EXPECT_NE(page.html.find("Rig time: <b>n/a</b>"), std::string::npos);
  EXPECT_NE(page.html.find("<td class=\"num w-na\">n/a</td><td class=\"w-na\">the comparison "
                           "with the truth gave no finite number"),
            std::string::npos);
  EXPECT_FALSE(std::regex_search(TextOf(page.html), std::regex("\\b(NaN|nan|inf|Infinity)\\b")));
  // The summary carries NaN as null and reads it back as NaN.
  const nlohmann::json j = s.ToJson();
  EXPECT_TRUE(j["rig_time_s"].is_null());
  EXPECT_TRUE(j["errors"][1]["value"].is_null());
  EXPECT_EQ(j["errors"][1]["word"], "n/a");
}

TEST(SessionReport, AHardwareSessionReadsItsCrossValidatedErrorAsAnEstimate) {
  TempDir dir("report_hw");
  testing::WriteSessionJson(dir.path(), "");
  WriteZonalExr(dir.File("zonal.exr"), testing::MakeZonalData());
  testing::WriteJson(dir.File("fit-ggx.json"),
                     {{"spec", "ggx:alpha=0.2,F0=0.5,kd=0.1"}, {"model", "ggx"}});
  testing::WriteJson(dir.File("fit-auto.json"),
                     {{"recommended", "ggx"},
                      {"why", "ggx predicts held-out coefficients best"},
                      {"candidates", {{{"model", "ggx"}, {"cv_error", 0.08}}}}});
  const SessionReportPage page = BuildSessionReport(dir.path(), SmallOptions());
  const SessionSummary& s = page.summary;
  EXPECT_TRUE(s.material.empty());
  EXPECT_TRUE(s.recommended);
  ASSERT_EQ(s.errors.size(), 3u);  // no capture error without the truth
  EXPECT_DOUBLE_EQ(s.errors[0].value, 0.08);
  EXPECT_TRUE(s.errors[0].estimated);
  EXPECT_EQ(s.errors[0].Word(), "good");
  EXPECT_TRUE(std::isnan(s.errors[1].value));
  EXPECT_TRUE(std::isnan(s.errors[2].value));
  EXPECT_NE(s.errors[2].missing.find("no true material"), std::string::npos);
  EXPECT_EQ(s.Verdict(), "good");
  EXPECT_NE(page.html.find("~8.00%"), std::string::npos);
  EXPECT_NE(page.html.find("estimated, the worst of the figures below"), std::string::npos);
  EXPECT_EQ(page.html.find("id=\"ball-truth\""), std::string::npos);
  // The warnings name the missing report.json and the command for this session.
  EXPECT_NE(std::find(s.warnings.begin(), s.warnings.end(),
                      "no report.json: the session has not been processed (zbrdf process " +
                          dir.path() + ")"),
            s.warnings.end());
}

TEST(SessionReport, WithoutAFitTheVerdictIsNaAndThePageSaysWhatToRun) {
  TempDir dir("report_nofit");
  MakeFittedSession(dir.path());
  fs::remove(dir.File("fit-ggx.json"));
  const SessionReportPage page = BuildSessionReport(dir.path(), SmallOptions());
  EXPECT_EQ(page.summary.Verdict(), "n/a");  // the capture's error alone is no answer
  EXPECT_TRUE(page.summary.fit.empty());
  EXPECT_TRUE(page.summary.thumbnail_png.empty());
  EXPECT_NE(page.html.find("no fit yet: run zbrdf fit " + dir.path() + " --model auto"),
            std::string::npos);
  EXPECT_EQ(page.sections.front(), "Summary");
  EXPECT_EQ(page.sections.back(), "Raw metadata");
}

TEST(SessionReport, ThePageCarriesItsSummary) {
  TempDir dir("report_summary");
  MakeFittedSession(dir.path());
  const SessionReportPage page = BuildSessionReport(dir.path(), SmallOptions());
  // A why with "--" (which may not occur in an HTML comment) survives.
  testing::WriteJson(dir.File("fit-auto.json"), {{"recommended", "ggx"}, {"why", "a --> b"}});
  const SessionReportPage with_why = BuildSessionReport(dir.path(), SmallOptions());
  EXPECT_EQ(with_why.summary.fit_why, "a --> b");
  testing::WriteFile(dir.File("report.html"), with_why.html);
  const std::optional<SessionSummary> read = ReadReportSummary(dir.File("report.html"));
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->ToJson(), with_why.summary.ToJson());
  EXPECT_FALSE(read->thumbnail_png.empty());
  EXPECT_EQ(read->thumbnail_png, with_why.summary.thumbnail_png);
  EXPECT_EQ(with_why.html.find("a --> b -->"), std::string::npos);
  EXPECT_FALSE(ReadReportSummary(dir.File("missing.html")).has_value());
  testing::WriteFile(dir.File("old.html"), "<!DOCTYPE html>\n<html></html>\n");
  EXPECT_FALSE(ReadReportSummary(dir.File("old.html")).has_value());
}

TEST(SessionReport, NotASessionIsAnInputError) {
  TempDir dir("report_empty");
  EXPECT_THROW(BuildSessionReport(dir.path(), {}), InputError);
}

TEST(FolderReport, FindsSessionsThreeLevelsDownButNotInsideSessionsOrHiddenFolders) {
  TempDir dir("report_find");
  for (const char* s : {"a", "x/b", "x/y/c", "x/y/z/too-deep", ".hidden/d", "a/inner"}) {
    fs::create_directories(dir.File(s));
    testing::WriteSessionJson(dir.File(s), "lambert:0.5");
  }
  fs::create_directories(dir.File("empty/folder"));
  const std::vector<std::string> expected = {dir.File("a"), dir.File("x/b"), dir.File("x/y/c")};
  EXPECT_EQ(FindSessionFolders(dir.path()), expected);
  EXPECT_EQ(FindSessionFolders(dir.path(), 1), std::vector<std::string>{dir.File("a")});
}

TEST(FolderReport, IndexHasOneRowPerSessionLinkingItsPageAndRewritesOnlyStalePages) {
  TempDir dir("report_index");
  MakeFittedSession(dir.File("one"));
  MakeFittedSession(dir.File("group/two"));
  fs::create_directories(dir.File("group/broken"));
  testing::WriteFile(dir.File("group/broken/session.json"), "{ not json");
  const std::string index = dir.File("index.html");
  const FolderReport first = WriteFolderReport(dir.path(), index, SmallOptions(), false);
  EXPECT_EQ(first.index, index);
  const std::vector<std::string> written = {dir.File("group/two/report.html"),
                                            dir.File("one/report.html")};
  EXPECT_EQ(first.written, written);
  EXPECT_TRUE(first.kept.empty());
  ASSERT_EQ(first.failed.size(), 1u);
  EXPECT_EQ(first.failed[0].rfind(dir.File("group/broken") + ": ", 0), 0u);

  const std::string html = testing::ReadFile(index);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  // One row per session; the broken one says why, the others link their page and folder, with
  // the ball, the material, the fit and its errors in numbers and words.
  const std::regex row("<tr class=\"session\">");
  EXPECT_EQ(
      std::distance(std::sregex_iterator(html.begin(), html.end(), row), std::sregex_iterator()),
      3);
  EXPECT_NE(html.find("href=\"one/report.html\""), std::string::npos);
  EXPECT_NE(html.find("href=\"group/two/report.html\""), std::string::npos);
  EXPECT_NE(html.find("href=\"group/two/\">folder</a>"), std::string::npos);
  EXPECT_NE(html.find("no report: "), std::string::npos);
  EXPECT_NE(html.find("ggx:alpha=0.3,F0=0.5,kd=0.1"), std::string::npos);
  EXPECT_NE(html.find("25.0%<br><span class=\"word\">good</span>"), std::string::npos);
  EXPECT_NE(html.find("width=\"96\" height=\"96\" src=\"data:image/png;base64,"),
            std::string::npos);
  EXPECT_FALSE(std::regex_search(TextOf(html), std::regex("\\b(NaN|nan|inf|Infinity)\\b")));

  // Nothing changed: every page is kept. A newer input makes its page stale.
  EXPECT_FALSE(SessionReportIsStale(dir.File("one")));
  const FolderReport second = WriteFolderReport(dir.path(), index, SmallOptions(), false);
  EXPECT_TRUE(second.written.empty());
  EXPECT_EQ(second.kept.size(), 2u);
  fs::last_write_time(dir.File("one/fit-ggx.json"),
                      fs::last_write_time(dir.File("one/report.html")) + std::chrono::seconds(5));
  EXPECT_TRUE(SessionReportIsStale(dir.File("one")));
  const FolderReport third = WriteFolderReport(dir.path(), index, SmallOptions(), false);
  EXPECT_EQ(third.written, std::vector<std::string>{dir.File("one/report.html")});
  const FolderReport rebuilt = WriteFolderReport(dir.path(), index, SmallOptions(), true);
  EXPECT_EQ(rebuilt.written.size(), 2u);

  // An index elsewhere links with ../.
  fs::create_directories(dir.File("pages"));
  WriteFolderReport(dir.path(), dir.File("pages/all.html"), SmallOptions(), false);
  EXPECT_NE(testing::ReadFile(dir.File("pages/all.html")).find("href=\"../one/report.html\""),
            std::string::npos);

  TempDir empty("report_index_empty");
  EXPECT_THROW(WriteFolderReport(empty.path(), empty.File("index.html"), SmallOptions(), false),
               InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
