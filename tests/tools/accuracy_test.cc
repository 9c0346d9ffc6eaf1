// The accuracy benchmark (tools/accuracy.h) on one MERL and one RGL material: leave-one-out
// priors, per-item files, the reduce step's tables.
#include "tools/accuracy.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "basis/error.h"
#include "tests/tools/simulated_sessions.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

namespace fs = std::filesystem;

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// The JSON without measured times (keys ending in "time_s"), which differ from run to run, and
// the session folders' paths (in each run's own folder).
nlohmann::json WithoutTimes(nlohmann::json j) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end();) {
      const std::string key = it.key();
      if (key == "session" || (key.size() >= 6 && key.compare(key.size() - 6, 6, "time_s") == 0)) {
        it = j.erase(it);
      } else {
        *it = WithoutTimes(*it);
        ++it;
      }
    }
  } else if (j.is_array()) {
    for (auto& v : j) v = WithoutTimes(v);
  }
  return j;
}

TEST(AccuracyTest, MerlMaterialsAreLeftOutOfThePriorAndRglMaterialsAreNot) {
  const std::string out = testing::TestBuildDir("test-accuracy");
  fs::remove_all(out);
  // The benchmark simulates into out/sessions/<rig>-o<order>/<folder>; the shared test sessions
  // (made once for the whole suite) stand in for them.
  fs::create_directories(out + "/sessions/thesis-o4");
  fs::create_directory_symlink(testing::SimulatedSession("merl:gold-metallic-paint", 4),
                               out + "/sessions/thesis-o4/merl-gold-metallic-paint");
  fs::create_directory_symlink(testing::SimulatedSession("rgl:paper_yellow", 4),
                               out + "/sessions/thesis-o4/rgl-paper_yellow");
  AccuracyOptions o;
  o.out_dir = out;
  o.orders = {4};
  o.materials = {"merl:gold-metallic-paint,rgl:paper_yellow"};
  o.candidates = {"prior"};
  o.images = false;
  const AccuracySummary summary = RunAccuracy(o);
  EXPECT_EQ(summary.items, 2);
  EXPECT_EQ(summary.failed, 0);
  const nlohmann::json merl = ReadJson(out + "/items/thesis-o4/merl-gold-metallic-paint.json");
  EXPECT_TRUE(merl["leave_one_out"].get<bool>());
  EXPECT_EQ(merl["prior_excluded"], nlohmann::json::array({"gold-metallic-paint"}));
  EXPECT_EQ(merl["device"], "merl");
  EXPECT_TRUE(merl["ngan"]["hemisphere"].is_number());  // in Ngan et al.'s 86
  EXPECT_TRUE(merl["errors"]["recommended"]["hemisphere"].is_number());
  const nlohmann::json rgl = ReadJson(out + "/items/thesis-o4/rgl-paper_yellow.json");
  EXPECT_FALSE(rgl["leave_one_out"].get<bool>());  // not in the MERL prior: nothing to leave out
  EXPECT_EQ(rgl["prior_excluded"], nlohmann::json::array());
  EXPECT_EQ(rgl["device"], "rgl");
  // The reduce step: one summary per (rig, order, device), the CSV and markdown tables, plots.
  const nlohmann::json table = ReadJson(out + "/accuracy.json");
  EXPECT_EQ(table["summary"].size(), 2u);
  for (const char* f : {"accuracy.csv", "accuracy.md", "cdf-thesis-o4-merl.png", "bars-thesis-o4-rgl.png"}) {
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  }
  // A second run reuses the items.
  const AccuracySummary again = RunAccuracy(o);
  EXPECT_EQ(again.reused, 2);
  EXPECT_EQ(again.computed, 0);

  // Sharded (tools/batch.h): each shard runs its item, the reduce step gives the same tables.
  const std::string sharded = testing::TestBuildDir("test-accuracy-sharded");
  fs::remove_all(sharded);
  fs::create_directories(sharded);
  fs::create_directory_symlink(out + "/sessions", sharded + "/sessions");
  o.out_dir = sharded;
  for (int index : {1, 0}) {
    o.shard = {index, 2};
    const AccuracySummary part = RunAccuracy(o);
    EXPECT_EQ(part.items, 1);
    EXPECT_EQ(part.computed, 1);
  }
  EXPECT_FALSE(fs::exists(sharded + "/accuracy.json")) << "a shard writes no table";
  ReduceAccuracy(sharded);
  EXPECT_EQ(WithoutTimes(ReadJson(sharded + "/accuracy.json")), WithoutTimes(table));
  EXPECT_TRUE(fs::exists(sharded + "/accuracy.md"));
}

TEST(AccuracyTest, RejectsBadOptions) {
  AccuracyOptions o;
  EXPECT_THROW(o.Validate(), InputError);  // no output folder
  o.out_dir = "/tmp/x";
  o.candidates = {"phong"};
  EXPECT_THROW(o.Validate(), InputError);
  EXPECT_EQ(MaterialDevice("merl:chrome"), "merl");
  EXPECT_EQ(MaterialDevice("rgl:cardboard"), "rgl");
  EXPECT_EQ(MaterialDevice("ggx:alpha=0.2"), "other");
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
