// A prior build split over shards (tools/prior_build.h): the merged prior file is the one a whole
// build writes, byte for byte; a shard reads only its own materials.
#include "tools/prior_build.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "tests/tools/simulated_sessions.h"
#include "tests/tools/tools_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {
namespace fs = std::filesystem;

TEST(PriorBuildTest, ShardsMergeToTheWholeBuildsFile) {
  const std::string dir = testing::TestBuildDir("test-prior-build");
  fs::remove_all(dir);
  fs::create_directories(dir);
  PriorBuildOptions o;
  o.from = {"merl:blue-acrylic", "merl:chrome", "rgl:cardboard", "lambert:0.5"};
  o.grid = HalfDiffGrid(8, 8, 4);
  // The whole build, as `zbrdf prior build` without batch flags does it.
  std::vector<PriorSource> sources;
  for (const PriorSourceRef& ref : CollectPriorSources(o.from)) sources.push_back(LoadPriorSource(ref));
  BrdfPrior whole = BuildPrior(sources, o.grid);
  whole.info["from"] = o.from;
  WritePriorFile(dir + "/whole.exr", whole);

  o.out = dir + "/sharded.exr";
  for (int index : {2, 0, 1}) {
    o.shard = {index, 3};
    EXPECT_EQ(RunPriorBuildShard(o), index == 0 ? 2 : 1);
    if (index == 2) {
      // Not all tabulated: the merge says how many are missing and what to run.
      try {
        ReducePriorBuild(o.BatchDir());
        ADD_FAILURE() << "merged with missing items";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("3 of 4 materials"), std::string::npos) << e.what();
      }
    }
  }
  const BrdfPrior merged = ReducePriorBuild(o.BatchDir());
  EXPECT_EQ(merged.materials, whole.materials);
  EXPECT_TRUE(merged.atoms == whole.atoms);
  EXPECT_EQ(testing::ReadFile(dir + "/whole.exr"), testing::ReadFile(dir + "/sharded.exr"));
}

TEST(PriorBuildTest, AShardReadsOnlyItsMaterialsAndTheMergeNamesABadOne) {
  // A folder library with one damaged file: listing it reads nothing; only the shard that owns
  // the damaged file fails on it, recording the failure, and the merge names it.
  const std::string dir = testing::TestBuildDir("test-prior-library");
  fs::remove_all(dir);
  fs::create_directories(dir + "/library");
  WriteFileAtomically(dir + "/library/a-damaged.binary", "not a MERL table");
  WriteFileAtomically(dir + "/library/b-notes.txt", "ignored");
  PriorBuildOptions o;
  o.from = {dir + "/library", "lambert:0.5"};
  o.grid = HalfDiffGrid(4, 4, 2);
  o.out = dir + "/lab.exr";
  const std::vector<PriorSourceRef> refs = CollectPriorSources(o.from);
  ASSERT_EQ(refs.size(), 2u);
  EXPECT_EQ(refs[0].name, "a-damaged");
  o.shard = {1, 2};
  EXPECT_EQ(RunPriorBuildShard(o), 1);  // the Lambertian: fine
  o.shard = {0, 2};
  EXPECT_EQ(RunPriorBuildShard(o), 1);  // tabulated as a failure, not thrown
  try {
    ReducePriorBuild(o.BatchDir());
    ADD_FAILURE() << "a prior was built with a damaged material";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a-damaged.binary"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(o.out));
  EXPECT_THROW(CollectPriorSources({"merl:no-such-material"}), InputError);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
