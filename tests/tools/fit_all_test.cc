#include "tools/fit_all.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "basis/error.h"
#include "brdf/nbrdf.h"
#include "tests/tools/simulated_sessions.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

TEST(FitAllTest, ExpandsMaterialLists) {
  const auto list = ExpandMaterialList("ggx:alpha=0.2,F0=0.5,kd=0.1,0.2,0.3,lambert:0.5");
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0], "ggx:alpha=0.2,F0=0.5,kd=0.1,0.2,0.3");
  EXPECT_EQ(list[1], "lambert:0.5");
  const auto merl = ExpandMaterialList("merl:*");
  EXPECT_EQ(merl.size(), BundledMaterialNames().size());
  EXPECT_EQ(merl[0], "merl:" + BundledMaterialNames()[0]);
  EXPECT_EQ(MaterialFolderName("merl:blue-acrylic"), "merl-blue-acrylic");
  EXPECT_EQ(MaterialFolderName("ggx:alpha=0.2,F0=0.5"), "ggx-alpha-0.2-F0-0.5");
}

TEST(FitAllTest, TabulatesErrorsAndResumes) {
  ::setenv("ZBRDF_CACHE_DIR", testing::TestBuildDir("test-cache").c_str(), 0);
  const std::string out = testing::TestBuildDir("test-fit-all");
  testing::FileLock lock(out + ".lock");
  std::filesystem::remove_all(out);
  FitAllOptions options;
  options.rig_path = testing::ThesisRigPath();
  options.order = 2;
  options.out_dir = out;
  options.materials = ExpandMaterialList("lambert:0.5,ggx:alpha=0.4,F0=0.5,kd=0.2");
  options.models = {"dbrdf", "ggx"};
  const FitAllSummary first = RunFitAll(options);
  EXPECT_EQ(first.simulated, 2);
  EXPECT_EQ(first.fitted, 4);
  EXPECT_EQ(first.failed, 0);
  ASSERT_EQ(first.table["rows"].size(), 2u);
  for (const auto& row : first.table["rows"]) {
    for (const char* model : {"dbrdf", "ggx"}) {
      ASSERT_TRUE(row["error_cosine_l2"][model].is_number()) << row.dump();
    }
    // GGX describes both materials exactly (a Lambertian is GGX with F0 = 0): even order-2 data
    // give them to a few percent.
    EXPECT_LT(row["error_cosine_l2"]["ggx"].get<double>(), 0.05) << row.dump();
  }
  EXPECT_TRUE(first.table["summary"]["ggx"]["median_error_cosine_l2"].is_number());
  EXPECT_TRUE(std::filesystem::exists(out + "/fit-all.csv"));
  // Run again: every material's row is found in DIR/items/.
  const FitAllSummary second = RunFitAll(options);
  EXPECT_EQ(second.reused_items, 2);
  EXPECT_EQ(second.simulated + second.fitted, 0);
  EXPECT_EQ(second.table["summary"], first.table["summary"]);
  // Without the rows, the sessions and fit reports in the folder are found.
  std::filesystem::remove_all(out + "/items");
  const FitAllSummary third = RunFitAll(options);
  EXPECT_EQ(third.simulated, 0);
  EXPECT_EQ(third.reused_sessions, 2);
  EXPECT_EQ(third.fitted, 0);
  EXPECT_EQ(third.reused_fits, 4);
  EXPECT_EQ(third.table["summary"], first.table["summary"]);
  options.models = {"phong"};
  EXPECT_THROW(RunFitAll(options), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
