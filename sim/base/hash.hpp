// FNV-1a, 64 bits (Fowler, Noll, Vo): a fast, portable hash of bytes, for fingerprints that must
// be the same on every machine (a saved state's model, a world's motion state, a golden's files).
// Not for adversarial input.
#pragma once
#include <cstddef>
#include <cstdint>

namespace simreel {

constexpr uint64_t kFnvOffsetBasis = 0xcbf29ce484222325ull;
constexpr uint64_t kFnvPrime = 0x100000001b3ull;

// Continues hash h over n bytes at p.
inline uint64_t fnv1a(uint64_t h, const void* p, size_t n) {
  const unsigned char* b = static_cast<const unsigned char*>(p);
  for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * kFnvPrime;
  return h;
}

}  // namespace simreel
