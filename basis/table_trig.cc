#include "basis/table_trig.h"

namespace zbrdf {
namespace table_trig_internal {

Tables::Tables() {
  constexpr long double kTwoPi = 6.283185307179586476925286766559005768L;
  for (int k = 0; k <= kSinCosNodes; ++k) {
    const long double angle = kTwoPi * k / kSinCosNodes;
    cos_sin[2 * k] = static_cast<double>(std::cos(angle));
    cos_sin[2 * k + 1] = static_cast<double>(std::sin(angle));
  }
  for (int k = 0; k <= kAtanNodes; ++k) {
    atan[k] = static_cast<double>(std::atan(static_cast<long double>(k) / kAtanNodes));
  }
}

}  // namespace table_trig_internal
}  // namespace zbrdf
