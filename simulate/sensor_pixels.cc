#include "simulate/sensor_pixels.h"

#include <algorithm>
#include <cmath>

#include "basis/cpu_features.h"
#include "simulate/normal_sampler.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define ZBRDF_SENSOR_AVX2 1
#endif

namespace zbrdf {
namespace {

constexpr uint64_t kGolden = 0x9e3779b97f4a7c15ull;  // 2^64 / phi, the pixels' key stride

// std::nearbyint(x), as an integer, in the default rounding mode (to nearest, ties to even),
// for 0 <= x < 2^31, without its library call (x86-64's baseline has no rounding instruction).
// Clamping to [0, max_dn] first and rounding after equals rounding first: the bounds are
// integers.
int64_t RoundHalfEven(double x) {
  const int64_t whole = static_cast<int64_t>(x);
  const double fraction = x - static_cast<double>(whole);  // exact (Sterbenz)
  return whole + ((fraction > 0.5) | ((fraction == 0.5) & (whole & 1)));
}

uint16_t SensorPixel(float rate, int64_t p, const SensorPixelModel& m,
                     const ZigguratNormal& normal) {
  double electrons = std::max(0.0, static_cast<double>(rate) * m.exposure_s);
  double read = 0;
  if (m.add_noise) {
    uint64_t h = HashMix(m.key + static_cast<uint64_t>(p) * kGolden);
    auto next_word = [&h]() {
      h = HashMix(h);
      return h;
    };
    const bool poisson = electrons < 30;
    if (poisson && electrons > 0) {  // (a pixel off the sample has mean 0: no draw)
      const double limit = std::exp(-electrons);
      double product = UniformFromHash(next_word());
      int count = 0;
      while (product > limit && count < 1000) {
        product *= UniformFromHash(next_word());
        ++count;
      }
      electrons = count;
    }
    read = m.read_noise_e * normal.Sample(next_word);
    if (!poisson) {
      electrons += std::sqrt(electrons) * normal.Sample(next_word);
      electrons = std::max(0.0, electrons);
    }
  }
  electrons = std::min(electrons, m.full_well_e);
  const double dn = m.dark_level_dn + (electrons + read) / m.gain_e_per_dn;
  return static_cast<uint16_t>(RoundHalfEven(std::clamp(dn, 0.0, m.max_dn)));
}

#ifdef ZBRDF_SENSOR_AVX2
#define ZBRDF_AVX2 __attribute__((target("avx2"), always_inline)) inline

// a * c mod 2^64 per lane, from 32 x 32 -> 64-bit products (AVX2 has no 64-bit multiply).
ZBRDF_AVX2 __m256i Multiply64(__m256i a, uint64_t c) {
  const __m256i c_low = _mm256_set1_epi64x(static_cast<int64_t>(c & 0xffffffffu));
  const __m256i c_high = _mm256_set1_epi64x(static_cast<int64_t>(c >> 32));
  const __m256i low_low = _mm256_mul_epu32(a, c_low);
  const __m256i cross = _mm256_add_epi64(_mm256_mul_epu32(_mm256_srli_epi64(a, 32), c_low),
                                         _mm256_mul_epu32(a, c_high));
  return _mm256_add_epi64(low_low, _mm256_slli_epi64(cross, 32));
}

ZBRDF_AVX2 __m256i HashMix4(__m256i x) {
  x = _mm256_add_epi64(x, _mm256_set1_epi64x(static_cast<int64_t>(kGolden)));
  x = Multiply64(_mm256_xor_si256(x, _mm256_srli_epi64(x, 30)), 0xbf58476d1ce4e5b9ull);
  x = Multiply64(_mm256_xor_si256(x, _mm256_srli_epi64(x, 27)), 0x94d049bb133111ebull);
  return _mm256_xor_si256(x, _mm256_srli_epi64(x, 31));
}

// An integer below 2^52 per lane, exactly, as a double: its bits under 2^52's exponent.
ZBRDF_AVX2 __m256d SmallIntegerToDouble(__m256i u) {
  const __m256d two52 = _mm256_set1_pd(0x1.0p52);
  return _mm256_sub_pd(_mm256_castsi256_pd(_mm256_or_si256(u, _mm256_castpd_si256(two52))), two52);
}

// UniformFromHash per lane: the word's top 53 bits, split at bit 32 so each part converts
// exactly; their sum is below 2^53, so exact too.
ZBRDF_AVX2 __m256d Uniform4(__m256i word) {
  const __m256i top = _mm256_srli_epi64(word, 11);
  const __m256d high = SmallIntegerToDouble(_mm256_srli_epi64(top, 32));
  const __m256d low = SmallIntegerToDouble(_mm256_and_si256(top, _mm256_set1_epi64x(0xffffffff)));
  return _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(high, _mm256_set1_pd(0x1.0p32)), low),
                       _mm256_set1_pd(0x1.0p-53));
}

// ZigguratNormal::Sample's first try per lane: the rectangle under the curve (98.8%). *accepted
// has all bits set in the lanes where it holds; the others need the scalar path.
ZBRDF_AVX2 __m256d Normal4(__m256i word, const double* edges, __m256d* accepted) {
  const __m256i layer = _mm256_and_si256(word, _mm256_set1_epi64x(ZigguratNormal::kLayers - 1));
  const __m256d x = _mm256_mul_pd(Uniform4(word), _mm256_i64gather_pd(edges, layer, 8));
  const __m256d next_edge =
      _mm256_i64gather_pd(edges, _mm256_add_epi64(layer, _mm256_set1_epi64x(1)), 8);
  *accepted = _mm256_cmp_pd(x, next_edge, _CMP_LT_OQ);
  // The sign bit from the word's bit 7 (multiplying by -1 flips just that bit).
  const __m256i sign = _mm256_slli_epi64(
      _mm256_and_si256(word, _mm256_set1_epi64x(ZigguratNormal::kLayers)), 63 - 7);
  return _mm256_xor_pd(x, _mm256_castsi256_pd(sign));
}

__attribute__((target("avx2"))) void RenderSensorPixelsAvx2(std::span<const float> rate,
                                                            int64_t first,
                                                            const SensorPixelModel& m,
                                                            uint16_t* out) {
  const ZigguratNormal& normal = ZigguratNormal::Get();
  const double* edges = normal.edges().data();
  const __m256d zero = _mm256_setzero_pd(), thirty = _mm256_set1_pd(30);
  const __m256d exposure_s = _mm256_set1_pd(m.exposure_s),
                read_noise = _mm256_set1_pd(m.read_noise_e);
  const __m256d full_well = _mm256_set1_pd(m.full_well_e), dark = _mm256_set1_pd(m.dark_level_dn);
  const __m256d gain = _mm256_set1_pd(m.gain_e_per_dn), max_dn = _mm256_set1_pd(m.max_dn);
  const __m256d half = _mm256_set1_pd(0.5);
  const __m256i lane_keys =
      _mm256_setr_epi64x(0, static_cast<int64_t>(kGolden), static_cast<int64_t>(2 * kGolden),
                         static_cast<int64_t>(3 * kGolden));
  const size_t n = rate.size(), whole = n - n % 4;
  for (size_t i = 0; i < whole; i += 4) {
    const int64_t p = first + static_cast<int64_t>(i);
    // max(x, 0) takes 0 where x is NaN, like std::max(0.0, x).
    __m256d electrons = _mm256_max_pd(
        _mm256_mul_pd(_mm256_cvtps_pd(_mm_loadu_ps(rate.data() + i)), exposure_s), zero);
    __m256d read = zero;
    int scalar_lanes = 0;  // lanes the scalar path redoes: a Poisson count, or a rejected point
    if (m.add_noise) {
      const __m256i h = HashMix4(_mm256_add_epi64(
          _mm256_set1_epi64x(static_cast<int64_t>(m.key + static_cast<uint64_t>(p) * kGolden)),
          lane_keys));
      const __m256i word1 = HashMix4(h);
      __m256d accepted1, accepted2;
      read = _mm256_mul_pd(read_noise, Normal4(word1, edges, &accepted1));
      const __m256d shot = _mm256_cmp_pd(electrons, thirty, _CMP_GE_OQ);
      const __m256d poisson = _mm256_andnot_pd(shot, _mm256_cmp_pd(electrons, zero, _CMP_GT_OQ));
      __m256d redo = _mm256_or_pd(
          poisson, _mm256_andnot_pd(accepted1, _mm256_castsi256_pd(_mm256_set1_epi64x(-1))));
      if (_mm256_movemask_pd(shot) != 0) {  // (most pixels lie off the sample, with mean 0)
        const __m256d n2 = Normal4(HashMix4(word1), edges, &accepted2);
        const __m256d noisy = _mm256_max_pd(
            _mm256_add_pd(electrons, _mm256_mul_pd(_mm256_sqrt_pd(electrons), n2)), zero);
        electrons = _mm256_blendv_pd(electrons, noisy, shot);
        redo = _mm256_or_pd(redo, _mm256_andnot_pd(accepted2, shot));
      }
      scalar_lanes = _mm256_movemask_pd(redo);
    }
    // min(x, full well) and the clamp, in std::min's and std::clamp's operand order.
    electrons =
        _mm256_blendv_pd(electrons, full_well, _mm256_cmp_pd(full_well, electrons, _CMP_LT_OQ));
    __m256d dn = _mm256_add_pd(dark, _mm256_div_pd(_mm256_add_pd(electrons, read), gain));
    dn = _mm256_blendv_pd(dn, zero, _mm256_cmp_pd(dn, zero, _CMP_LT_OQ));
    dn = _mm256_blendv_pd(dn, max_dn, _mm256_cmp_pd(max_dn, dn, _CMP_LT_OQ));
    // Round half to even: the whole part, then up past a half, or at a half to an even count.
    const __m128i whole_part = _mm256_cvttpd_epi32(dn);
    const __m256d fraction = _mm256_sub_pd(dn, _mm256_cvtepi32_pd(whole_part));
    const __m256d up = _mm256_or_pd(
        _mm256_cmp_pd(fraction, half, _CMP_GT_OQ),
        _mm256_and_pd(_mm256_cmp_pd(fraction, half, _CMP_EQ_OQ),
                      _mm256_castsi256_pd(_mm256_cvtepi32_epi64(_mm_sub_epi32(
                          _mm_setzero_si128(), _mm_and_si128(whole_part, _mm_set1_epi32(1)))))));
    // up's lanes are all ones or zeros: its 32-bit halves, packed, subtract 1 where set.
    const __m128i up32 = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(
        _mm256_castpd_si256(up), _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7)));
    const __m128i counts = _mm_sub_epi32(whole_part, up32);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + i), _mm_packus_epi32(counts, counts));
    for (int lane = 0; scalar_lanes != 0; ++lane, scalar_lanes >>= 1) {
      if (scalar_lanes & 1) out[i + lane] = SensorPixel(rate[i + lane], p + lane, m, normal);
    }
  }
  for (size_t i = whole; i < n; ++i) {
    out[i] = SensorPixel(rate[i], first + static_cast<int64_t>(i), m, normal);
  }
}

#undef ZBRDF_AVX2
#endif

}  // namespace

SensorPixelModel SensorPixelModel::Of(const SensorParams& sensor, double exposure_s) {
  SensorPixelModel m;
  m.exposure_s = exposure_s;
  m.read_noise_e = sensor.read_noise_e;
  m.full_well_e = sensor.full_well_e;
  m.dark_level_dn = sensor.dark_level_dn;
  m.gain_e_per_dn = sensor.gain_e_per_dn;
  m.max_dn = std::floor(std::min(sensor.saturation_dn, std::ldexp(1.0, sensor.bit_depth) - 1));
  return m;
}

void RenderSensorPixelsScalar(std::span<const float> rate, int64_t first,
                              const SensorPixelModel& model, uint16_t* out) {
  const ZigguratNormal& normal = ZigguratNormal::Get();
  for (size_t i = 0; i < rate.size(); ++i) {
    out[i] = SensorPixel(rate[i], first + static_cast<int64_t>(i), model, normal);
  }
}

void RenderSensorPixels(std::span<const float> rate, int64_t first, const SensorPixelModel& model,
                        uint16_t* out) {
#ifdef ZBRDF_SENSOR_AVX2
  if (CpuHasAvx2()) return RenderSensorPixelsAvx2(rate, first, model, out);
#endif
  RenderSensorPixelsScalar(rate, first, model, out);
}

}  // namespace zbrdf
