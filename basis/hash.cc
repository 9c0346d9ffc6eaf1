#include "basis/hash.h"

// The whole implementation inlined from libxxhash's header (its documented XXH_INLINE_ALL
// mode): no library to link, and the fuzz build's sanitizers see all of it.
#define XXH_INLINE_ALL
#include <xxhash.h>

namespace zbrdf {

uint64_t Xxh3_64(const void* data, size_t size) { return XXH3_64bits(data, size); }

}  // namespace zbrdf
