#include "basis/cpu_features.h"

namespace zbrdf {

bool CpuHasAvx2() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  static const bool have = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return have;
#else
  return false;
#endif
}

bool CpuHasF16c() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  static const bool have = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("f16c") != 0 && __builtin_cpu_supports("avx") != 0;
  }();
  return have;
#else
  return false;
#endif
}

}  // namespace zbrdf
