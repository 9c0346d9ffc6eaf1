// The session report page, the plots it embeds, and the commands that people run.
#include "pictures/html_report.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <regex>

#include "acquisition/zonal.h"
#include "basis/error.h"
#include "basis/spherical_harmonics.h"
#include "brdf/material_spec.h"
#include "pictures/brdf_plots.h"
#include "pictures/image.h"
#include "tests/acquisition/session_fixture.h"
#include "tests/test_files.h"

namespace zbrdf {
namespace {

using testing::TempDir;

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

TEST(SessionReport, SelfContainedPageWithEverySection) {
  TempDir dir("report");
  testing::WriteSessionJson(dir.path(), "ggx:alpha=0.3,F0=0.5,kd=0.1");
  testing::WriteJson(dir.File("report.json"),
                     {{"wall_time_s", {{"simulate", 1.5}, {"total", 3.25}}},
                      {"coefficient_error_in_zone", 0.012},
                      {"warnings", {"exposure bracket clipped 3 pixels"}}});
  WriteZonalExr(dir.File("zonal.exr"), testing::MakeZonalData());
  testing::WriteJson(dir.File("fit-ggx.json"), {{"spec", "ggx:alpha=0.32,F0=0.48,kd=0.1"}});
  // A calibration figure in the calibration folder.
  std::filesystem::create_directories(dir.File("calibration"));
  const cv::Mat card(20, 30, CV_8UC3, cv::Scalar(120, 120, 120));
  WritePng(dir.File("calibration/graycard.png"), card);
  ReportOptions options;
  options.preview_size = 32;
  options.preview_spp = 4;
  options.metric_samples = 4096;
  const SessionReportPage page = BuildSessionReport(dir.path(), options);
  for (const char* section :
       {"Session", "Timings and errors", "Calibration", "Fitted BRDF", "True material",
        "Fit against truth", "Coefficient energy", "Files"}) {
    EXPECT_NE(std::find(page.sections.begin(), page.sections.end(), section), page.sections.end())
        << section;
  }
  const std::string& html = page.html;
  // Self-contained: no external resources of any kind.
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
  EXPECT_GE(images, 10);
  // The calibration figure is embedded byte for byte; timings and warnings are shown.
  EXPECT_NE(html.find(Base64Encode(testing::ReadFile(dir.File("calibration/graycard.png")))),
            std::string::npos);
  EXPECT_NE(html.find("exposure bracket clipped 3 pixels"), std::string::npos);
  EXPECT_NE(html.find("3.25"), std::string::npos);
  EXPECT_NE(html.find("ggx:alpha=0.32"), std::string::npos);
}

TEST(SessionReport, NotASessionIsAnInputError) {
  TempDir dir("report_empty");
  EXPECT_THROW(BuildSessionReport(dir.path(), {}), InputError);
}

}  // namespace
}  // namespace zbrdf
