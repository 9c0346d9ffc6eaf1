#include "simulate/transport_row.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "simulate/imaging.h"

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// A row and a radiance image from SplitMix64 words (fixed seed): steps of every size (0, small,
// up to 65535), weights over the whole int16 range, radiances with zeros among them.
struct RandomRow {
  std::vector<TransportEntry> row;
  std::vector<float> radiance;
  uint32_t first = 0;
};

// A radiance over 2^-40 .. 2^40: products that far apart round when summed in double, so
// that a sum in another order is another number (over a narrow range every order is exact).
float WideRadiance(uint64_t word) {
  return static_cast<float>(UniformFromHash(word) *
                            std::ldexp(1.0, static_cast<int>((word >> 3) % 81) - 40));
}

RandomRow MakeRow(uint64_t seed, size_t entries) {
  RandomRow r;
  uint64_t state = seed;
  auto word = [&state] { return state = HashMix(state); };
  r.first = static_cast<uint32_t>(word() % 5000);
  uint32_t j = r.first;
  for (size_t e = 0; e < entries; ++e) {
    const uint64_t w = word();
    uint16_t step = static_cast<uint16_t>(w % 300);
    if (w % 7 == 0) step = 0;        // as every row's first entry has
    if (w % 97 == 1) step = 0xffff;  // the largest step
    const int16_t weight = static_cast<int16_t>(static_cast<int>((w >> 20) % 65535) - 32767);
    r.row.push_back({step, weight});
    j += step;
  }
  r.radiance.resize(j + 1);
  for (float& value : r.radiance) {
    const uint64_t w = word();
    value = w % 5 == 0 ? 0.0f : WideRadiance(w);
  }
  return r;
}

// The exact sum: a 16-bit weight times a 24-bit float is exact in double, and the long double
// sum of a few thousand such products is far more precise than the tolerance below.
long double ExactProduct(const RandomRow& r, long double* magnitude) {
  long double sum = 0;
  *magnitude = 0;
  uint32_t j = r.first;
  for (const TransportEntry& e : r.row) {
    j += e.step;
    const long double p = static_cast<long double>(e.weight) * r.radiance[j];
    sum += p;
    *magnitude += std::abs(p);
  }
  return sum;
}

// Every length from 0 to 40 (each step of 4 or 8 entries, and every tail), and long rows.
std::vector<size_t> RowLengths() {
  std::vector<size_t> lengths;
  for (size_t n = 0; n <= 40; ++n) lengths.push_back(n);
  for (size_t n : {255, 256, 257, 4000}) lengths.push_back(n);
  return lengths;
}

TEST(TransportRowTest, ProductsAreTheExactSumToFloatRounding) {
  uint64_t seed = 17;
  for (size_t n : RowLengths()) {
    for (int trial = 0; trial < 5; ++trial) {
      const RandomRow r = MakeRow(++seed, n);
      long double magnitude = 0;
      const long double exact = ExactProduct(r, &magnitude);
      // Each product rounded to float (half an ulp, 2^-24 relative), then n double additions:
      // |error| <= (2^-24 + n 2^-53) sum |w r|.
      const double bound = (0x1.0p-24 + n * 0x1.0p-53) * static_cast<double>(magnitude);
      const double fast = RowProduct(r.row, r.first, r.radiance.data());
      const double scalar = RowProductScalar(r.row, r.first, r.radiance.data());
      ASSERT_LE(std::abs(fast - static_cast<double>(exact)), bound)
          << n << " entries, trial " << trial;
      ASSERT_LE(std::abs(scalar - static_cast<double>(exact)), bound)
          << n << " entries, trial " << trial;
      // One summation order on every path: a frame does not depend on the CPU.
      ASSERT_EQ(fast, scalar) << n << " entries, trial " << trial;
    }
  }
}

TEST(TransportRowTest, EightImagesInOnePassGiveEachImagesProductBitForBit) {
  // Eight different images (a lane mix-up gives another image's product), interleaved as
  // RowProducts reads them.
  uint64_t seed = 1000;
  for (size_t n : RowLengths()) {
    const RandomRow r = MakeRow(++seed, n);
    std::vector<std::vector<float>> images(kRowProductPatterns, r.radiance);
    std::vector<float> interleaved(r.radiance.size() * kRowProductPatterns);
    uint64_t state = seed;
    for (int i = 0; i < kRowProductPatterns; ++i) {
      for (size_t j = 0; j < r.radiance.size(); ++j) {
        state = HashMix(state);
        if (i > 0) images[i][j] = state % 4 == 0 ? 0.0f : WideRadiance(state);
        interleaved[j * kRowProductPatterns + i] = images[i][j];
      }
    }
    double fast[kRowProductPatterns], scalar[kRowProductPatterns];
    RowProducts(r.row, r.first, interleaved.data(), fast);
    RowProductsScalar(r.row, r.first, interleaved.data(), scalar);
    for (int i = 0; i < kRowProductPatterns; ++i) {
      const double alone = RowProduct(r.row, r.first, images[i].data());
      ASSERT_EQ(fast[i], alone) << n << " entries, image " << i;
      ASSERT_EQ(scalar[i], alone) << n << " entries, image " << i;
    }
  }
}

TEST(TransportRowTest, EveryEntryReachesItsOwnPixel) {
  // One radiance of 1 at a time, every other 0: the product picks out exactly the weights of
  // the entries that land there (a lane-ordering or prefix-sum mistake moves them elsewhere).
  const RandomRow r = MakeRow(99, 37);
  std::vector<float> radiance(r.radiance.size(), 0.0f);
  std::vector<double> expected(radiance.size(), 0.0);
  uint32_t j = r.first;
  for (const TransportEntry& e : r.row) {
    j += e.step;
    expected[j] += e.weight;
  }
  for (size_t pixel = 0; pixel < radiance.size(); ++pixel) {
    if (expected[pixel] == 0 && pixel % 50 != 0) continue;  // every hit pixel and some misses
    radiance[pixel] = 1.0f;
    EXPECT_EQ(RowProduct(r.row, r.first, radiance.data()), expected[pixel]) << pixel;
    radiance[pixel] = 0.0f;
  }
}

TEST(TransportRowTest, PackingKeepsPixelsAndWeightsAcrossLargeGaps) {
  // Gaps of 0 (the first), small, exactly 65535, one beyond (one zero-weight step), and 229999
  // (three zero-weight steps of 65535, then 33394); weights of both signs over 5 decades.
  const std::vector<TransportSample> samples = {{7, 2.5f},       {12, -0.001f},    {65547, 40.0f},
                                                {131083, 3e-4f}, {361082, -17.0f}, {361083, 0.25f}};
  std::vector<TransportEntry> row = {{3, 99}};  // appended after what is there
  const PackedRowStart start = AppendPackedRow(samples, &row);
  EXPECT_EQ(start.first_index, 7u);
  EXPECT_FLOAT_EQ(start.scale, 40.0f / 32767);
  ASSERT_EQ(row.size(), 1u + samples.size() + 1 + 3);
  const std::span<const TransportEntry> packed(row.data() + 1, row.size() - 1);
  std::vector<float> radiance(samples.back().index + 1, 0.0f);
  for (const TransportSample& s : samples) {
    // Each pixel alone: its weight comes back to within half a unit of the scale.
    radiance[s.index] = 1.0f;
    EXPECT_NEAR(start.scale * RowProduct(packed, start.first_index, radiance.data()), s.weight,
                0.5 * start.scale)
        << s.index;
    radiance[s.index] = 0.0f;
  }
  // The largest weight is exactly 32767 units.
  EXPECT_EQ(row[3].weight, 32767);
  // Nothing to pack: nothing appended, scale 0.
  EXPECT_EQ(AppendPackedRow({}, &row).scale, 0.0f);
  const std::vector<TransportSample> zeros = {{4, 0.0f}, {9, 0.0f}};
  EXPECT_EQ(AppendPackedRow(zeros, &row).scale, 0.0f);
  EXPECT_EQ(row.size(), 1u + samples.size() + 1 + 3);
}

TEST(TransportRowTest, PackingIntoPlaceWritesTheSameEntriesWithinItsBound) {
  // PackRow into raw storage sized by PackedRowMaxEntries, guard entries after it: the same
  // entries as AppendPackedRow, within the bound, nothing written past it. Rows whose steps
  // nearly span the projector (the most gap steps) and random rows (fixed seed).
  constexpr uint32_t kProjector = 480000;
  std::vector<std::vector<TransportSample>> rows = {
      {{0, 1.0f}, {kProjector - 1, -2.0f}},
      {{5, 1.0f}, {65541, 1.0f}, {131077, 1.0f}, {196613, 3.0f}, {kProjector - 1, 0.5f}},
      {{123, 4.0f}}};
  std::mt19937 rng(3);
  for (int r = 0; r < 20; ++r) {
    std::vector<TransportSample> row;
    for (uint32_t j = rng() % 1000; j < kProjector; j += 1 + rng() % 20000) {
      row.push_back({j, std::uniform_real_distribution<float>(-1, 1)(rng)});
    }
    rows.push_back(row);
  }
  const TransportEntry guard{0x1234, -0x4321};
  for (const auto& samples : rows) {
    std::vector<TransportEntry> appended;
    const PackedRowStart expected = AppendPackedRow(samples, &appended);
    const size_t bound = PackedRowMaxEntries(samples.size(), kProjector);
    std::vector<TransportEntry> storage(bound + 4, guard);
    size_t count = 0;
    const PackedRowStart start = PackRow(samples, storage.data(), &count);
    EXPECT_EQ(start.first_index, expected.first_index);
    EXPECT_EQ(start.scale, expected.scale);
    ASSERT_EQ(count, appended.size());
    EXPECT_LE(count, bound);
    for (size_t e = 0; e < count; ++e) {
      EXPECT_EQ(storage[e].step, appended[e].step) << e;
      EXPECT_EQ(storage[e].weight, appended[e].weight) << e;
    }
    for (size_t e = bound; e < storage.size(); ++e) {
      EXPECT_EQ(storage[e].step, guard.step);
      EXPECT_EQ(storage[e].weight, guard.weight);
    }
  }
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
