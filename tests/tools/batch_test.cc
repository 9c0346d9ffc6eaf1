#include "tools/batch.h"

#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include "basis/atomic_file.h"
#include "basis/error.h"
#include "tests/tools/simulated_sessions.h"
#include "tests/tools/tools_test_util.h"
#include "tools/fit_all.h"
#include "tools/slurm.h"

extern char** environ;

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {
namespace fs = std::filesystem;

// Three cheap materials at order 2, one model: a batch of a few seconds per item (the transports
// come from the build tree's cache after the first run).
constexpr char kMaterials[] = "lambert:0.5,ggx:alpha=0.4,F0=0.5,kd=0.2,lambert:0.2";

FitAllOptions SmallBatch(const std::string& out) {
  FitAllOptions options;
  options.rig_path = testing::ThesisRigPath();
  options.order = 2;
  options.out_dir = out;
  options.materials = ExpandMaterialList(kMaterials);
  options.models = {"ggx"};
  options.parallel_materials = 1;
  return options;
}

std::string FreshDir(const std::string& name) {
  const std::string dir = testing::TestBuildDir(name);
  fs::remove_all(dir);
  return dir;
}

TEST(ShardTest, ParsesAndSplitsEveryItemIntoExactlyOneShard) {
  const Shard s = Shard::Parse("2/5");
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 5);
  EXPECT_EQ(s.ToString(), "2/5");
  for (const char* bad : {"", "3", "5/5", "-1/4", "1/0", "a/4", "1/4x", "/4", "1/"}) {
    EXPECT_THROW(Shard::Parse(bad), InputError) << bad;
  }
  for (int count = 1; count <= 6; ++count) {
    for (size_t item = 0; item < 20; ++item) {
      int owners = 0;
      for (int index = 0; index < count; ++index) owners += Shard{index, count}.Owns(item);
      EXPECT_EQ(owners, 1) << item << " of " << count << " shards";
    }
  }
  EXPECT_TRUE(Shard{}.IsWhole());
}

TEST(BatchManifestTest, RoundTripsAndRejectsUnsafeItems) {
  BatchManifest m;
  m.command = "fit-all";
  m.args = {"--out", "x"};
  m.options = {{"order", 2}};
  m.items = {{"a", "items/a.json"}, {"b", "items/b.json"}};
  const BatchManifest back = BatchManifest::FromJson(m.ToJson(), "test");
  EXPECT_TRUE(back.SameWork(m));
  EXPECT_EQ(back.args, m.args);
  BatchManifest other = m;
  other.options["order"] = 3;
  EXPECT_FALSE(other.SameWork(m));
  for (const char* result : {"../x.json", "/etc/passwd", ""}) {
    nlohmann::json j = m.ToJson();
    j["items"][0]["result"] = result;
    EXPECT_THROW(BatchManifest::FromJson(j, "test"), InputError) << result;
  }
  nlohmann::json repeated = m.ToJson();
  repeated["items"][1]["id"] = "a";
  EXPECT_THROW(BatchManifest::FromJson(repeated, "test"), InputError);
  EXPECT_THROW(BatchManifest::FromJson(nlohmann::json::array(), "test"), InputError);
}

TEST(FitAllBatchTest, ShardedRunsMergeToTheUnshardedTable) {
  const std::string whole = FreshDir("test-batch-whole"), sharded = FreshDir("test-batch-sharded");
  ::setenv("ZBRDF_CACHE_DIR", testing::TestBuildDir("test-cache").c_str(), 0);
  const FitAllSummary one = RunFitAll(SmallBatch(whole));
  ASSERT_EQ(one.failed, 0);
  ASSERT_EQ(one.table["rows"].size(), 3u);
  // Manifest first, items in the materials' order.
  const BatchManifest manifest = ReadManifest(whole);
  ASSERT_EQ(manifest.items.size(), 3u);
  EXPECT_EQ(manifest.items[1].id, "ggx-alpha-0.4-F0-0.5-kd-0.2");

  // Two shards, the second run first: the order the shards run in does not matter.
  for (int index : {1, 0}) {
    FitAllOptions options = SmallBatch(sharded);
    options.shard = {index, 2};
    const FitAllSummary part = RunFitAll(options);
    EXPECT_EQ(part.items, index == 0 ? 2 : 1);  // items 0 and 2; item 1
    EXPECT_FALSE(fs::exists(sharded + "/fit-all.csv")) << "a shard writes no table";
  }
  const FitAllSummary merged = ReduceFitAll(sharded);
  EXPECT_EQ(testing::ReadFile(whole + "/fit-all.csv"), testing::ReadFile(sharded + "/fit-all.csv"));
  nlohmann::json a = one.table, b = merged.table;
  for (auto* t : {&a, &b}) {
    for (auto& row : (*t)["rows"]) row.erase("fit_time_s");  // measured, not a result
  }
  EXPECT_EQ(a, b);

  // A shard of other work is refused, naming the manifest.
  FitAllOptions other = SmallBatch(sharded);
  other.order = 3;
  other.shard = {0, 2};
  try {
    RunFitAll(other);
    ADD_FAILURE() << "a shard with other options ran";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("manifest.json"), std::string::npos) << e.what();
  }
  // A rerun finds every row and computes nothing.
  const FitAllSummary again = RunFitAll(SmallBatch(sharded));
  EXPECT_EQ(again.reused_items, 3);
  EXPECT_EQ(again.simulated + again.fitted, 0);
  EXPECT_EQ(testing::ReadFile(whole + "/fit-all.csv"), testing::ReadFile(sharded + "/fit-all.csv"));
}

pid_t Spawn(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  const int error = ::posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return error == 0 ? pid : -1;
}

TEST(FitAllBatchTest, AKilledShardRerunsOnlyItsMissingItems) {
  const std::string dir = FreshDir("test-batch-killed");
  ::setenv("ZBRDF_CACHE_DIR", testing::TestBuildDir("test-cache").c_str(), 0);
  const std::vector<std::string> argv = {
      testing::ZbrdfBinary(), "fit-all", "--rig", testing::ThesisRigPath(), "--materials", kMaterials,
      "--order", "2", "--models", "ggx", "--jobs", "1", "--out", dir, "--shard", "0/1"};
  // Killed (SIGKILL, like a Slurm time limit's last word) once the second item has started.
  const pid_t pid = Spawn(argv);
  ASSERT_GT(pid, 0);
  const std::string second_marker = dir + "/running/ggx-alpha-0.4-F0-0.5-kd-0.2.json";
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(3);
  while (!fs::exists(second_marker) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(fs::exists(second_marker)) << "the second item never started";

  const BatchManifest manifest = ReadManifest(dir);
  const std::string first_result = dir + "/" + manifest.items[0].result;
  ASSERT_TRUE(fs::exists(first_result));
  struct stat before {};
  ASSERT_EQ(::stat(first_result.c_str(), &before), 0);
  // The killed item shows as stale (its process is gone), the third as pending.
  const auto states = BatchStatus(dir, 1);
  ASSERT_EQ(states.size(), 3u);
  EXPECT_EQ(states[0].state, ItemState::kDone);
  EXPECT_EQ(states[1].state, ItemState::kStale);
  EXPECT_EQ(states[2].state, ItemState::kPending);
  EXPECT_EQ(ShardsWithMissingItems(states), std::vector<int>{0});

  // The rerun does only the two missing items; the first one's result is not rewritten.
  FitAllOptions options = SmallBatch(dir);
  options.shard = {0, 1};
  const FitAllSummary rerun = RunFitAll(options);
  EXPECT_EQ(rerun.reused_items, 1);
  EXPECT_EQ(rerun.fitted, 2);
  struct stat after {};
  ASSERT_EQ(::stat(first_result.c_str(), &after), 0);
  EXPECT_EQ(after.st_ino, before.st_ino);
  EXPECT_EQ(after.st_mtim.tv_nsec, before.st_mtim.tv_nsec);
  for (const ItemStatus& s : BatchStatus(dir, 1)) EXPECT_EQ(s.state, ItemState::kDone) << s.item.id;
  EXPECT_FALSE(fs::exists(second_marker));
}

TEST(SlurmTest, SiteFilesAreCheckedAndTimeLimitsFollowTheEstimate) {
  const std::string dir = testing::TestBuildDir("test-batch-site");
  fs::create_directories(dir);
  WriteFileAtomically(dir + "/site.yaml",
                      "partition: short\naccount: lab\nsetup: module load zbrdf\n"
                      "sbatch: ['--qos=normal', '--constraint=avx2']\ncpus_per_task: 4\n");
  const SlurmSite site = SlurmSite::Load(dir + "/site.yaml");
  EXPECT_EQ(site.partition, "short");
  EXPECT_EQ(site.sbatch_lines.size(), 2u);
  EXPECT_EQ(site.cpus_per_task, 4);
  EXPECT_EQ(SlurmSite::FromJson(site.ToJson()).ToJson(), site.ToJson());
  WriteFileAtomically(dir + "/bad.yaml", "partiton: short\n");
  try {
    SlurmSite::Load(dir + "/bad.yaml");
    ADD_FAILURE() << "a misspelt key was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("partiton"), std::string::npos) << e.what();
  }
  EXPECT_THROW(SlurmSite::Load(dir + "/missing.yaml"), InputError);
  // 3x the estimate plus 5 minutes: 10 items of 60 s -> 35 min.
  EXPECT_EQ(SlurmTimeLimitMinutes(60, 10), 35);
  EXPECT_EQ(ShellQuote("a b'c"), "'a b'\\''c'");
  EXPECT_EQ(ShellQuote("--out=results/x"), "--out=results/x");
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
