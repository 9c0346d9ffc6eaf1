// A material's identity for caches of work done on it (the simulator's light transport, the
// true zonal coefficients): a hash of what the model returns at fixed direction pairs, not of
// its spec alone, so that two models with the same spec text but different values (a file
// edited in place, a parameter printed with fewer digits) never share a cache entry.
#pragma once

#include <cstdint>
#include <string>

#include "brdf/brdf.h"

namespace zbrdf {

// FNV-1a over the bit patterns of f_r at 96 fixed pairs (a quasi-random set over the
// hemisphere, plus mirror pairs near the normal and at grazing angles where glossy peaks
// live), GlossyProbability and GlossyPdf at a few of them, a delta material's sampled direction
// and reflectance, and Spec(). Deterministic across runs on the same build.
uint64_t MaterialFingerprint(const Brdf& material);

// "<spec> #<fingerprint in hex>": for cache keys and the headers of cache files.
std::string MaterialCacheKey(const Brdf& material);

}  // namespace zbrdf
