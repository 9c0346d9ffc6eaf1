// Non-cryptographic hashes: they detect damage, not tampering.
//
// FNV-1a, 64-bit (Fowler, Noll, Vo; http://www.isthe.com/chongo/tech/comp/fnv/): the hash of
// cache keys, rig identities, journal lines, and frame checksums of sessions written before
// XXH3 took that over.
//
// XXH3, 64-bit, seed 0 (Collet; Debian's libxxhash): the checksum of frame files and of their
// samples. FNV-1a takes a multiply per byte (~0.7 GB/s: 5.6 ms of the ~20 ms a full-resolution
// frame spends on the frame writer's thread); XXH3 reads 32 bytes a step (BM_FrameChecksum).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace zbrdf {

inline constexpr uint64_t kFnv1a64Offset = 14695981039346656037ull;
inline constexpr uint64_t kFnv1a64Prime = 1099511628211ull;

// Continues hash h over size bytes (start with kFnv1a64Offset).
inline uint64_t Fnv1a64(const void* data, size_t size, uint64_t h = kFnv1a64Offset) {
  const unsigned char* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) {
    h ^= p[i];
    h *= kFnv1a64Prime;
  }
  return h;
}

inline uint64_t Fnv1a64(std::string_view bytes, uint64_t h = kFnv1a64Offset) {
  return Fnv1a64(bytes.data(), bytes.size(), h);
}

// XXH3_64bits of size bytes.
uint64_t Xxh3_64(const void* data, size_t size);
inline uint64_t Xxh3_64(std::string_view bytes) { return Xxh3_64(bytes.data(), bytes.size()); }

}  // namespace zbrdf
