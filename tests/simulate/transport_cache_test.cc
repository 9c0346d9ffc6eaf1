// The transport cache (simulate/imaging.h, docs/simulator.md): a transport read back from the
// cache renders the same frames, bit for bit, as the one built; entries are keyed by the
// material's values, not its spec text; damaged entries are rebuilt; the folder is trimmed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "brdf/material_spec.h"
#include "simulate/imaging.h"
#include "tests/rig/rig_test_util.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

namespace fs = std::filesystem;

Pattern Gray(const Rig& rig) {
  Pattern p;
  p.width = rig.projector.lens.width;
  p.height = rig.projector.lens.height;
  p.bit_depth = rig.projector.bit_depth;
  p.levels.assign(static_cast<size_t>(p.width) * p.height, 200);
  return p;
}

std::vector<fs::path> Entries(const std::string& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path());
  return out;
}

class TransportCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ::testing::TempDir() + "/zbrdf-transport-cache-" + std::to_string(::getpid());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  ForwardModelOptions Options(uint64_t max_bytes = 1ull << 32) const {
    ForwardModelOptions o;
    o.row_stride = 8;  // an eighth of the rows: the cache does not care, and it is 8x faster
    o.cache_dir = dir_;
    o.cache_max_bytes = max_bytes;
    return o;
  }
  std::string dir_;
};

TEST_F(TransportCacheTest, ACachedTransportRendersTheSameFramesBitForBit) {
  const auto& shared = testing::SharedFastThesisRig();
  const auto material = MakeBrdf("ggx:alpha=0.2,F0=0.5,kd=0.1");
  ForwardModelOptions uncached = Options();
  uncached.cache_dir.clear();
  const ForwardModel reference(shared.optics, shared.maps, *material, uncached);
  const ForwardModel built(shared.optics, shared.maps, *material, Options());
  EXPECT_FALSE(built.from_cache());
  // Constructed while `built` may still be writing the entry on its own thread: it waits for
  // that write and loads it rather than building again.
  const ForwardModel loaded(shared.optics, shared.maps, *material, Options());
  EXPECT_TRUE(loaded.from_cache());
  ASSERT_EQ(Entries(dir_).size(), 1u);
  EXPECT_EQ(loaded.transport_entries(), reference.transport_entries());
  const Pattern pattern = Gray(shared.rig);
  EXPECT_EQ(loaded.ElectronRate(pattern), reference.ElectronRate(pattern));
  EXPECT_EQ(loaded.Render(pattern, 5000, 7).data, reference.Render(pattern, 5000, 7).data);
}

TEST_F(TransportCacheTest, EntriesAreKeyedByTheMaterialsValuesAndSeed) {
  const auto& shared = testing::SharedFastThesisRig();
  const auto a = MakeBrdf("ggx:alpha=0.2,F0=0.5,kd=0.1");
  const auto b = MakeBrdf("ggx:alpha=0.2001,F0=0.5,kd=0.1");  // another material, nearly the same
  const ForwardModel first(shared.optics, shared.maps, *a, Options());
  const ForwardModel other(shared.optics, shared.maps, *b, Options());
  EXPECT_FALSE(other.from_cache());
  ForwardModelOptions seeded = Options();
  seeded.seed = 2;
  const ForwardModel reseeded(shared.optics, shared.maps, *a, seeded);
  EXPECT_FALSE(reseeded.from_cache());
  for (const ForwardModel* model : {&first, &other, &reseeded}) model->WaitForCacheWrite();
  EXPECT_EQ(Entries(dir_).size(), 3u);
}

TEST_F(TransportCacheTest, DamagedEntriesAreRebuiltAndTheFolderIsTrimmed) {
  const auto& shared = testing::SharedFastThesisRig();
  // Glossy materials: a Lambertian's transport has no entries to damage (simulate/imaging.h).
  const auto a = MakeBrdf("ggx:alpha=0.3,F0=0.5,kd=0.1");
  const ForwardModel built(shared.optics, shared.maps, *a, Options());
  built.WaitForCacheWrite();
  ASSERT_EQ(Entries(dir_).size(), 1u);
  ASSERT_GT(built.transport_entries(), 0u);
  const fs::path entry = Entries(dir_)[0];
  const uint64_t size = fs::file_size(entry);
  // Truncated: rebuilt and rewritten whole.
  fs::resize_file(entry, size / 2);
  const ForwardModel after_truncation(shared.optics, shared.maps, *a, Options());
  EXPECT_FALSE(after_truncation.from_cache());
  after_truncation.WaitForCacheWrite();
  EXPECT_EQ(fs::file_size(entry), size);
  // A projector index out of range (damage inside the file, the size intact): rebuilt, never
  // used to index the pattern. The first pixel's first projector index lies 8 (end mark) +
  // 20 x pixels (control) + 4 x entries (steps and weights) + 4 x pixels (weight scales) +
  // 4 x pixels (first indices) bytes before the end.
  {
    const uint64_t pixels = static_cast<uint64_t>(shared.rig.camera.width) * shared.rig.camera.height;
    std::fstream f(entry, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size - 8 - 28 * pixels - 4 * built.transport_entries()));
    const uint32_t bad = 0xffffffffu;
    f.write(reinterpret_cast<const char*>(&bad), 4);
  }
  const ForwardModel after_damage(shared.optics, shared.maps, *a, Options());
  EXPECT_FALSE(after_damage.from_cache());
  const ForwardModel repaired(shared.optics, shared.maps, *a, Options());
  EXPECT_TRUE(repaired.from_cache());
  // A cap smaller than one entry: nothing is written, and what was there is trimmed away.
  const auto b = MakeBrdf("ggx:alpha=0.3,F0=0.5,kd=0.25");
  const ForwardModel tiny_cap(shared.optics, shared.maps, *b, Options(size / 2));
  EXPECT_FALSE(tiny_cap.from_cache());
  tiny_cap.WaitForCacheWrite();
  EXPECT_EQ(Entries(dir_).size(), 1u);  // b was not written (too large for the cap)
  // A cap of one entry: writing a second trims the least recently used.
  const ForwardModel second(shared.optics, shared.maps, *b, Options(size + size / 2));
  second.WaitForCacheWrite();
  EXPECT_EQ(Entries(dir_).size(), 1u);
  const ForwardModel b_again(shared.optics, shared.maps, *b, Options(size + size / 2));
  EXPECT_TRUE(b_again.from_cache());
  // Cap 0: neither read nor written.
  const ForwardModel off(shared.optics, shared.maps, *b, Options(0));
  EXPECT_FALSE(off.from_cache());
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
