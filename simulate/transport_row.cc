#include "simulate/transport_row.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "basis/cpu_features.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define ZBRDF_ROW_PRODUCT_AVX2 1
#endif

namespace zbrdf {

static_assert(sizeof(TransportEntry) == 4, "a row is read as 32-bit lanes: step low, weight high");

PackedRowStart PackRow(std::span<const TransportSample> samples, TransportEntry* out,
                       size_t* count) {
  *count = 0;
  double largest = 0;
  for (const TransportSample& e : samples) {
    largest = std::max(largest, std::abs(static_cast<double>(e.weight)));
  }
  if (!(largest > 0)) return {};
  PackedRowStart start;
  start.first_index = samples.front().index;
  start.scale = static_cast<float>(largest / 32767);
  const double inverse_scale = 1.0 / start.scale;
  uint32_t previous = start.first_index;
  TransportEntry* next = out;
  for (const TransportSample& e : samples) {
    uint32_t step = e.index - previous;
    for (; step > 0xffffu; step -= 0xffffu) *next++ = {0xffffu, 0};
    // |q| <= 32767 up to the scale's rounding to float. Rounded to nearest (ties to even) by
    // adding and taking away 1.5 * 2^52, exact for |x| < 2^51: std::lround was a library call
    // per entry.
    constexpr double kRound = 0x1.8p52;
    const double rounded = (e.weight * inverse_scale + kRound) - kRound;
    const double q = std::clamp(rounded, -32767.0, 32767.0);
    *next++ = {static_cast<uint16_t>(step), static_cast<int16_t>(q)};
    previous = e.index;
  }
  *count = static_cast<size_t>(next - out);
  return start;
}

PackedRowStart AppendPackedRow(std::span<const TransportSample> samples,
                               std::vector<TransportEntry>* row) {
  // The steps add up to the indices' span: its bound is PackRow's for a projector of that many
  // pixels.
  uint32_t span = 0;
  if (!samples.empty()) span = samples.back().index - samples.front().index;
  const size_t begin = row->size();
  row->resize(begin + PackedRowMaxEntries(samples.size(), span));
  size_t count = 0;
  const PackedRowStart start = PackRow(samples, row->data() + begin, &count);
  row->resize(begin + count);
  return start;
}

namespace {

// Entries begin .. row.size() - 1 into the partial sums (entry e into partial[e % 4]), the
// projector pixel stepping on from j; then the sums combined in the one order.
double FinishRowProduct(std::span<const TransportEntry> row, size_t begin, uint32_t j,
                        const float* radiance, double partial[4]) {
  for (size_t e = begin; e < row.size(); ++e) {
    j += row[e].step;
    partial[e % 4] += static_cast<double>(static_cast<float>(row[e].weight) * radiance[j]);
  }
  return (partial[0] + partial[1]) + (partial[2] + partial[3]);
}

}  // namespace

double RowProductScalar(std::span<const TransportEntry> row, uint32_t first,
                        const float* radiance) {
  double partial[4] = {0, 0, 0, 0};
  return FinishRowProduct(row, 0, first, radiance, partial);
}

void RowProductsScalar(std::span<const TransportEntry> row, uint32_t first,
                       const float* radiance_interleaved, double out[kRowProductPatterns]) {
  constexpr int kPatterns = kRowProductPatterns;
  double partial[4][kPatterns] = {};
  uint32_t j = first;
  for (size_t e = 0; e < row.size(); ++e) {
    j += row[e].step;
    const float weight = static_cast<float>(row[e].weight);
    const float* radiance = radiance_interleaved + static_cast<size_t>(kPatterns) * j;
    for (int i = 0; i < kPatterns; ++i) {
      partial[e % 4][i] += static_cast<double>(weight * radiance[i]);
    }
  }
  for (int i = 0; i < kPatterns; ++i) {
    out[i] = (partial[0][i] + partial[1][i]) + (partial[2][i] + partial[3][i]);
  }
}

#ifdef ZBRDF_ROW_PRODUCT_AVX2
namespace {

// Eight entries per step: their projector pixels by a prefix sum of the steps across the lanes,
// the radiances by one gather, the products in float; entries e..e+3 then e+4..e+7 (e a
// multiple of 8) are added to the four partial sums, lane k holding sum k.
// A full-resolution frame's product (92 M entries, 2 cores): 60 ms one entry at a time, 52 ms
// with gathers, 45 ms with the prefetch below; without the gathers at all it would be 44 ms,
// so what is left is reading the entries.
__attribute__((target("avx2"))) double RowProductAvx2(std::span<const TransportEntry> row,
                                                      uint32_t first, const float* radiance) {
  const size_t n = row.size(), whole = n - n % 8;
  __m256d sums = _mm256_setzero_pd();
  __m256i base = _mm256_set1_epi32(static_cast<int>(first));  // the previous entry's pixel
  const __m256i step_mask = _mm256_set1_epi32(0xffff);
  const __m256i lane3 = _mm256_setr_epi32(0, 0, 0, 0, 3, 3, 3, 3);
  const __m256i lane7 = _mm256_set1_epi32(7);
  for (size_t e = 0; e < whole; e += 8) {
    __m256i lanes;
    static_assert(sizeof(lanes) == 8 * sizeof(TransportEntry));
    // 2 kB ahead (a prefetch never faults, past the row's end included): the entries are one
    // stream, and the hardware's prefetch alone left a core at ~4 GB/s (a full-resolution
    // product 52 -> 45 ms).
    _mm_prefetch(reinterpret_cast<const char*>(reinterpret_cast<uintptr_t>(row.data() + e) + 2048),
                 _MM_HINT_T0);
    lanes = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(row.data() + e));
    __m256i steps = _mm256_and_si256(lanes, step_mask);
    const __m256i weights = _mm256_srai_epi32(lanes, 16);  // sign-extended
    // Inclusive prefix sum: within each 128-bit half, then the low half's total into the high.
    steps = _mm256_add_epi32(steps, _mm256_slli_si256(steps, 4));
    steps = _mm256_add_epi32(steps, _mm256_slli_si256(steps, 8));
    steps = _mm256_add_epi32(
        steps, _mm256_blend_epi32(_mm256_setzero_si256(), _mm256_permutevar8x32_epi32(steps, lane3),
                                  0xf0));
    const __m256i pixels = _mm256_add_epi32(base, steps);
    base = _mm256_permutevar8x32_epi32(pixels, lane7);
    const __m256 products =
        _mm256_mul_ps(_mm256_cvtepi32_ps(weights), _mm256_i32gather_ps(radiance, pixels, 4));
    sums = _mm256_add_pd(sums, _mm256_cvtps_pd(_mm256_castps256_ps128(products)));
    sums = _mm256_add_pd(sums, _mm256_cvtps_pd(_mm256_extractf128_ps(products, 1)));
  }
  alignas(32) double partial[4];
  _mm256_store_pd(partial, sums);
  // The tail, into the same sums (whole % 4 == 0).
  return FinishRowProduct(row, whole,
                          static_cast<uint32_t>(_mm_cvtsi128_si32(_mm256_castsi256_si128(base))),
                          radiance, partial);
}

// Entry e's products with the kRowProductPatterns images, added to the partial sums k = e mod 4
// of patterns 0-3 (low) and 4-7 (high).
__attribute__((target("avx2"), always_inline)) inline void AddEntryProducts(
    TransportEntry entry, uint32_t* j, const float* radiance_interleaved, __m256d* low,
    __m256d* high) {
  *j += entry.step;
  const __m256 products =
      _mm256_mul_ps(_mm256_set1_ps(static_cast<float>(entry.weight)),
                    _mm256_loadu_ps(radiance_interleaved + static_cast<size_t>(8) * *j));
  *low = _mm256_add_pd(*low, _mm256_cvtps_pd(_mm256_castps256_ps128(products)));
  *high = _mm256_add_pd(*high, _mm256_cvtps_pd(_mm256_extractf128_ps(products, 1)));
}

// One entry at a time, its kRowProductPatterns radiances in one load.
__attribute__((target("avx2"))) void RowProductsAvx2(std::span<const TransportEntry> row,
                                                     uint32_t first,
                                                     const float* radiance_interleaved,
                                                     double out[kRowProductPatterns]) {
  static_assert(kRowProductPatterns == 8, "one AVX2 register of floats per projector pixel");
  __m256d low[4], high[4];
  for (int k = 0; k < 4; ++k) low[k] = high[k] = _mm256_setzero_pd();
  const size_t n = row.size();
  const TransportEntry* entries = row.data();
  uint32_t j = first;
  // A second cursor kAhead entries ahead prefetches their radiances: the interleaved image
  // (15 MB at full resolution) is far larger than a core's cache, and the loads are random.
  constexpr size_t kAhead = 32;
  uint32_t j_ahead = first;
  size_t ahead = 0;
  auto prefetch_next = [&]() __attribute__((always_inline)) {
    if (ahead < n) {
      j_ahead += entries[ahead++].step;
      _mm_prefetch(
          reinterpret_cast<const char*>(radiance_interleaved + static_cast<size_t>(8) * j_ahead),
          _MM_HINT_T0);
    }
  };
  for (size_t a = 0; a < kAhead; ++a) prefetch_next();
  size_t e = 0;
  for (; e + 4 <= n; e += 4) {
    _mm_prefetch(reinterpret_cast<const char*>(reinterpret_cast<uintptr_t>(entries + e) + 2048),
                 _MM_HINT_T0);
    prefetch_next();
    prefetch_next();
    prefetch_next();
    prefetch_next();
    AddEntryProducts(entries[e], &j, radiance_interleaved, &low[0], &high[0]);
    AddEntryProducts(entries[e + 1], &j, radiance_interleaved, &low[1], &high[1]);
    AddEntryProducts(entries[e + 2], &j, radiance_interleaved, &low[2], &high[2]);
    AddEntryProducts(entries[e + 3], &j, radiance_interleaved, &low[3], &high[3]);
  }
  for (int k = 0; e < n; ++e, ++k) {
    AddEntryProducts(entries[e], &j, radiance_interleaved, &low[k], &high[k]);
  }
  _mm256_storeu_pd(out,
                   _mm256_add_pd(_mm256_add_pd(low[0], low[1]), _mm256_add_pd(low[2], low[3])));
  _mm256_storeu_pd(out + 4,
                   _mm256_add_pd(_mm256_add_pd(high[0], high[1]), _mm256_add_pd(high[2], high[3])));
}

}  // namespace
#endif

double RowProduct(std::span<const TransportEntry> row, uint32_t first, const float* radiance) {
#ifdef ZBRDF_ROW_PRODUCT_AVX2
  if (CpuHasAvx2()) return RowProductAvx2(row, first, radiance);
#endif
  return RowProductScalar(row, first, radiance);
}

void RowProducts(std::span<const TransportEntry> row, uint32_t first,
                 const float* radiance_interleaved, double out[kRowProductPatterns]) {
#ifdef ZBRDF_ROW_PRODUCT_AVX2
  if (CpuHasAvx2()) return RowProductsAvx2(row, first, radiance_interleaved, out);
#endif
  RowProductsScalar(row, first, radiance_interleaved, out);
}

}  // namespace zbrdf
