#include "acquisition/half_convert.h"

#include "basis/cpu_features.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define ZBRDF_HAVE_F16C_PATH 1
#endif

namespace zbrdf {
namespace {

void FloatsToHalfScalar(const float* in, size_t n, half* out) {
  for (size_t k = 0; k < n; ++k) out[k] = half(in[k]);
}

#ifdef ZBRDF_HAVE_F16C_PATH
__attribute__((target("avx,f16c"))) void FloatsToHalfF16c(const float* in, size_t n, half* out) {
  size_t k = 0;
  for (; k + 8 <= n; k += 8) {
    const __m128i h = _mm256_cvtps_ph(_mm256_loadu_ps(in + k), _MM_FROUND_TO_NEAREST_INT);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + k), h);
  }
  FloatsToHalfScalar(in + k, n - k, out + k);
}
#endif

}  // namespace

void FloatsToHalf(const float* in, size_t n, half* out) {
  static_assert(sizeof(half) == 2, "half must be the 16-bit IEEE format");
#ifdef ZBRDF_HAVE_F16C_PATH
  if (CpuHasF16c()) {
    FloatsToHalfF16c(in, n, out);
    return;
  }
#endif
  FloatsToHalfScalar(in, n, out);
}

}  // namespace zbrdf
#undef ZBRDF_HAVE_F16C_PATH
