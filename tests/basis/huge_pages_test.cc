#include "basis/huge_pages.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "basis/freed_memory.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// The kernel's transparent huge page mode ("always", "madvise" or "never"), empty if unknown.
std::string ThpMode() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string line;
  std::getline(in, line);
  const size_t open = line.find('['), close = line.find(']');
  return open == std::string::npos || close == std::string::npos
             ? ""
             : line.substr(open + 1, close - open - 1);
}

// kB of `field` ("AnonHugePages", "Rss") of the mapping that holds address p (/proc/self/smaps),
// -1 if not found.
long SmapsKbAt(const void* p, const std::string& field) {
  std::ifstream in("/proc/self/smaps");
  const uintptr_t a = reinterpret_cast<uintptr_t>(p);
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> lo >> dash >> hi && dash == '-') {
      inside = a >= lo && a < hi;
      continue;
    }
    if (inside && line.rfind(field + ":", 0) == 0) return std::stol(line.substr(field.size() + 1));
  }
  return -1;
}
long AnonHugePagesKbAt(const void* p) { return SmapsKbAt(p, "AnonHugePages"); }

TEST(HugePagesTest, AssignGivesTheValuesWhateverThePages) {
  std::vector<float> v(10, 3.0f);
  for (size_t n : {size_t{0}, size_t{1}, size_t{1000}, size_t{3} << 20}) {
    AssignInHugePages(&v, n, 0.5f);
    ASSERT_EQ(v.size(), n);
    for (size_t k = 0; k < n; k += 4099) ASSERT_EQ(v[k], 0.5f) << k;
    if (n > 0) {
      EXPECT_EQ(v.back(), 0.5f);
    }
  }
  AdviseHugePagesDiscardingContents(nullptr, 0);  // nothing to advise: no effect
}

TEST(HugePagesTest, ShrinkingInPlaceKeepsTheValuesAndGivesTheRestBack) {
  // 64 MB touched, cut to its first 4 MB: the values stay, the array stays where it was (no
  // copy), and the resident memory of the mapping that holds it (the heap, where the freed
  // memory setting of the test binaries sends every block, with what else lives there) falls by
  // about the 60 MB cut off.
  std::vector<float> v(size_t{16} << 20);
  for (size_t k = 0; k < v.size(); ++k) v[k] = static_cast<float>(k % 1000);
  const float* const data = v.data();
  const long before = SmapsKbAt(data, "Rss");
  ShrinkInPlace(&v, size_t{1} << 20);
  ASSERT_EQ(v.size(), size_t{1} << 20);
  EXPECT_EQ(v.data(), data);
  for (size_t k = 0; k < v.size(); k += 997) ASSERT_EQ(v[k], static_cast<float>(k % 1000)) << k;
  const long after = SmapsKbAt(data, "Rss");
  if (before < 0 || after < 0) GTEST_SKIP() << "no /proc/self/smaps entry for the array";
  // 60 MB given back, less at most a 2 MB huge page at the cut.
  EXPECT_GE(before - after, 58 * 1024) << "before " << before << " kB, after " << after;
  ShrinkInPlace(&v, 0);  // everything given back: still a valid, empty vector
  EXPECT_TRUE(v.empty());
  DiscardPages(nullptr, 0);
}

TEST(HugePagesTest, AnAdvisedArrayGetsHugePagesWhereTheKernelGivesThem) {
  const std::string mode = ThpMode();
  if (mode != "madvise" && mode != "always") GTEST_SKIP() << "THP is '" << mode << "' here";
  // 16 MB: at least six whole 2 MB pages inside, wherever the allocation starts.
  std::vector<float> v;
  AssignInHugePages(&v, size_t{4} << 20, 1.0f);
  const long kb = AnonHugePagesKbAt(v.data() + v.size() / 2);
  if (kb < 0) GTEST_SKIP() << "no /proc/self/smaps entry for the array";
  // The kernel may lack free 2 MB blocks (fragmentation), so any huge page counts; none at all
  // means the advice was not given or not where the array is.
  EXPECT_GT(kb, 0) << "THP mode " << mode;
}

// The allocator keeps freed memory (basis/freed_memory.h; the test binaries' main() sets it, as
// zbrdf's does), so an array may be given pages an earlier one touched, which are 4 kB pages
// whatever is advised after: AssignInHugePages gives them back first. Before it did, one of two
// full-resolution simulations with the allocator's setting took 35 s instead of 26 s (the
// direction grid's random lookups are what huge pages speed up).
TEST(HugePagesTest, AnArrayInMemoryTouchedBeforeStillGetsHugePages) {
  const std::string mode = ThpMode();
  if (mode != "madvise" && mode != "always") GTEST_SKIP() << "THP is '" << mode << "' here";
  KeepFreedMemoryForReuse();
  constexpr size_t kFloats = size_t{4} << 20;  // 16 MB, as above
  const void* touched = nullptr;
  {
    std::vector<float> before(kFloats, 2.0f);  // touched in 4 kB pages (not advised)
    touched = before.data();
  }
  std::vector<float> v;
  AssignInHugePages(&v, kFloats, 1.0f);
  const long kb = AnonHugePagesKbAt(v.data() + v.size() / 2);
  if (kb < 0) GTEST_SKIP() << "no /proc/self/smaps entry for the array";
  // Whether the allocator reused the block is its choice; the test means something where it did
  // (glibc does, with the options above: the same address).
  if (v.data() != touched) GTEST_SKIP() << "the allocator did not reuse the freed block";
  EXPECT_GT(kb, 0) << "THP mode " << mode;
  for (size_t k = 0; k < kFloats; k += 4099) ASSERT_EQ(v[k], 1.0f) << k;
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
