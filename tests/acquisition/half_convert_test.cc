#include "acquisition/half_convert.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// The independent reference is Imath's own conversion (software, as this build compiles it).
void ExpectSameAsImath(const std::vector<float>& in) {
  std::vector<half> out(in.size());
  FloatsToHalf(in.data(), in.size(), out.data());
  for (size_t k = 0; k < in.size(); ++k) {
    const half expected(in[k]);
    if (std::isnan(in[k])) {
      EXPECT_TRUE(out[k].isNan()) << "input " << k << " NaN";
      continue;
    }
    ASSERT_EQ(out[k].bits(), expected.bits()) << "input " << k << " = " << in[k] << " (bits 0x"
                                              << std::hex << std::bit_cast<uint32_t>(in[k]) << ")";
  }
}

TEST(HalfConvertTest, EveryTieAndNeighbourOfEveryHalfRoundsAsImath) {
  // For each finite half h: h itself, the float midway to the next half (a tie, which must go
  // to the even one), and the floats one ulp either side of the midpoint.
  std::vector<float> in;
  for (uint32_t bits = 0; bits < 0x10000; ++bits) {
    const half h = half(half::FromBits, static_cast<uint16_t>(bits));
    const half next = half(half::FromBits, static_cast<uint16_t>(bits + 1));
    if (!h.isFinite() || !next.isFinite() || (bits & 0x7fff) == 0x7bff) continue;
    const float a = h, b = next;
    const float mid = 0.5f * (a + b);  // exact: halves have 11 significant bits
    in.insert(in.end(), {a, mid, std::nextafter(mid, a), std::nextafter(mid, b)});
  }
  // Overflow (65520 is the tie between 65504 and infinity), infinities, zeros, NaN, and lengths
  // that leave a tail shorter than 8.
  in.insert(in.end(),
            {65504.0f, 65519.99f, 65520.0f, 70000.0f, -65520.0f,
             std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(), 0.0f,
             -0.0f, std::numeric_limits<float>::quiet_NaN(), 1e-30f, -1e-30f,
             std::numeric_limits<float>::denorm_min()});
  ASSERT_GT(in.size(), 200000u);
  ExpectSameAsImath(in);
  for (size_t n = 0; n < 20; ++n) ExpectSameAsImath(std::vector<float>(in.begin(), in.begin() + n));
}

TEST(HalfConvertTest, AStrideThroughAllFloatsRoundsAsImath) {
  std::vector<float> in;
  for (uint64_t bits = 0; bits <= 0xffffffffull; bits += 4099) {
    in.push_back(std::bit_cast<float>(static_cast<uint32_t>(bits)));
  }
  ExpectSameAsImath(in);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
