// Two non-negative indices (shapes of a pair, vertices of an edge) in one 64-bit key, the first in
// the high half: keys sort by (first, second), the order every pair list is kept in.
#pragma once
#include <cstdint>

namespace simreel {

inline uint64_t pair_key(int a, int b) {
  return ((uint64_t)(uint32_t)a << 32) | (uint32_t)b;
}
inline int pair_first(uint64_t key) {
  return (int)(key >> 32);
}
inline int pair_second(uint64_t key) {
  return (int)(key & 0xFFFFFFFFu);
}

}  // namespace simreel
