// The commands people run (export, preview, plot, compare, report), end to end through the zbrdf
// binary on a synthetic session.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "acquisition/zonal.h"
#include "basis/png.h"
#include "basis/spherical_harmonics.h"
#include "brdf/material_spec.h"
#include "pictures/image.h"
#include "tests/acquisition/session_fixture.h"
#include "tools_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

using testing::TempDir;

// Regression (stress suite): `convert` of a simulated mirror session printed its summary with
// get<double>() on the errors, which are null for a delta material (f_r is a distribution), and
// failed with a JSON type error after writing the SH file.
TEST(Commands, ConvertOfADeltaMaterialSessionPrintsUndefinedErrorsAsNa) {
  TempDir dir("commands-convert-mirror");
  const std::string s = dir.File("session");
  std::filesystem::create_directories(s);
  testing::WriteSessionJson(s, "mirror:0.9");
  WriteZonalExr(s + "/zonal.exr", testing::MakeZonalData());
  ASSERT_EQ(testing::RunZbrdf("convert " + s + " --to sh", dir.File("out.txt"), dir.File("err.txt")), 0)
      << testing::ReadFile(dir.File("err.txt"));
  EXPECT_NE(testing::ReadFile(dir.File("out.txt")).find("n/a in the zone"), std::string::npos)
      << testing::ReadFile(dir.File("out.txt"));
}

// Options are validated where they enter the library, and the CLI prints what Validate() says:
// the struct, the field, the accepted range and the value.
TEST(Commands, BadOptionsAreReportedByFieldAndRange) {
  TempDir dir("commands-bad-options");
  EXPECT_EQ(testing::RunZbrdf("fit " + dir.path() + " --f0-range 0.6,0.2", dir.File("out.txt"),
                              dir.File("err.txt")),
            2);
  const std::string err = testing::ReadFile(dir.File("err.txt"));
  EXPECT_NE(err.find("zbrdf fit: error: FitSessionOptions: dbrdf.f0_min, f0_max must satisfy 0 "
                     "<= f0_min <= f0_max <= 1 (--f0-range; got 0.6, 0.2)"),
            std::string::npos)
      << err;
}

TEST(Commands, ExportPreviewPlotCompareReportOnASession) {
  TempDir dir("commands");
  const std::string s = dir.File("session");
  std::filesystem::create_directories(s);
  testing::WriteSessionJson(s, "merl:red-fabric");
  testing::WriteJson(s + "/report.json", {{"wall_time_s", {{"total", 1.0}}}});
  WriteZonalExr(s + "/zonal.exr", testing::MakeZonalData());
  WriteDBrdfFile(s + "/fit-dbrdf.exr", testing::MakeDBrdf(), {{"test", true}});
  auto run = [&](const std::string& args) {
    return testing::RunZbrdf(args, dir.File("out.txt"), dir.File("err.txt"));
  };
  ASSERT_EQ(run("export " + s + " --format dbrdf --out " + dir.File("copy.exr")), 0)
      << testing::ReadFile(dir.File("err.txt"));
  EXPECT_EQ(run("export " + s + " --format sh --out " + dir.File("x.exr")), 2);  // no SH data
  EXPECT_NE(testing::ReadFile(dir.File("err.txt")).find("zbrdf convert"), std::string::npos);
  ASSERT_EQ(run("export " + s + " --format rgl --out " + dir.File("m.bsdf") +
                " --rgl-theta 6 "
                "--rgl-samples 12"),
            0)
      << testing::ReadFile(dir.File("err.txt"));
  for (const char* f : {"m.bsdf", "m.spectral.bsdf", "m.mitsuba.xml", "m.pbrt"}) {
    EXPECT_TRUE(std::filesystem::exists(dir.File(f))) << f;
  }
  ASSERT_EQ(run("preview " + s + " --size 24 --spp 2 --out " + dir.File("ball.png") + " --exr " +
                dir.File("ball.exr")),
            0)
      << testing::ReadFile(dir.File("err.txt"));
  const PngImage ball = DecodePng(testing::ReadFile(dir.File("ball.png")), "ball.png");
  EXPECT_EQ(ball.height, 24);
  const RgbImage linear = ReadExrImage(dir.File("ball.exr"));
  EXPECT_EQ(linear.width, 24);
  EXPECT_EQ(run("preview lambert:0.5 --light dir:30,0 --envmap sky --out " + dir.File("x.png")), 2);
  ASSERT_EQ(run("plot " + s + " --out " + dir.File("plots")), 0)
      << testing::ReadFile(dir.File("err.txt"));
  for (const char* f : {"slices.png", "slices-log.png", "band-energy.png", "plot.json"}) {
    EXPECT_TRUE(std::filesystem::exists(dir.File(std::string("plots/") + f))) << f;
  }
  ASSERT_EQ(run("compare merl:red-fabric " + s + " --size 24 --spp 2 --samples 4096 --out " +
                dir.File("cmp")),
            0)
      << testing::ReadFile(dir.File("err.txt"));
  const nlohmann::json metrics =
      nlohmann::json::parse(testing::ReadFile(dir.File("cmp/metrics.json")));
  EXPECT_GT(metrics["render"]["rmse"].get<double>(), 0.0);
  EXPECT_GT(metrics["brdf_cosine_weighted_l2"]["l2_mean"].get<double>(), 0.0);
  ASSERT_EQ(run("report " + s + " --size 24 --spp 2"), 0) << testing::ReadFile(dir.File("err.txt"));
  EXPECT_GT(testing::ReadFile(s + "/report.html").size(), 10000u);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
