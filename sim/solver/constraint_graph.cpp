#include "sim/solver/constraint_graph.hpp"

#include <algorithm>

namespace simreel {

static_assert(ConstraintGraph::kColours <= 32, "a body's colours are the bits of a uint32_t");

void ConstraintGraph::build(int bodies, int n, const int* a, const int* b) {
  member_.assign(bodies, 0);
  last_.assign(bodies, -1);
  colour_.resize(n);
  slot_.resize(n);
  at_.resize(n);
  start_.assign(kColours + 2, 0);
  for (int i = 0; i < n; ++i) {
    const int A = a[i], B = b[i];  // 0: the static body, which does not count
    const uint32_t free = ~((A != 0 ? member_[A] : 0u) | (B != 0 ? member_[B] : 0u));
    const int after = std::max(A != 0 ? (int)last_[A] : -1, B != 0 ? (int)last_[B] : -1) + 1;
    const uint32_t later = after < kColours ? free & (~0u << after) : 0u;
    // The first free colour after both bodies' last; past the end, the first free one at all.
    const int c = later != 0 ? __builtin_ctz(later) : (free != 0 ? __builtin_ctz(free) : kOverflow);
    if (c != kOverflow) {
      if (A != 0) member_[A] |= 1u << c, last_[A] = (int8_t)c;
      if (B != 0) member_[B] |= 1u << c, last_[B] = (int8_t)c;
    }
    colour_[i] = (uint8_t)c;
    ++start_[c + 1];
  }
  for (int c = 0; c <= kColours; ++c) start_[c + 1] += start_[c];
  // Slots: a stable counting sort by colour (start_ is the running cursor, then restored).
  for (int i = 0; i < n; ++i) slot_[i] = start_[colour_[i]]++;
  for (int i = 0; i < n; ++i) at_[slot_[i]] = i;
  for (int c = kColours; c > 0; --c) start_[c] = start_[c - 1];
  start_[0] = 0;
  used_.clear();
  for (int c = 0; c < kColours; ++c)
    if (end(c) > begin(c)) used_.push_back(c);
}

}  // namespace simreel
