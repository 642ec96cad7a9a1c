// Colouring of the contact constraints, so that threads can solve them in parallel with a result
// that does not depend on the thread count (Box2D v3 / Box3D's constraint graph, after
// Smelyanskiy et al., "High-performance physical simulations on next-generation architecture with
// many cores", Intel Technology Journal 13(4), 2009).
//
// Each constraint joins two solver bodies. A colour is a set of constraints of which no two share
// a moving body (dynamic or kinematic; the static body, solver body 0, is never written and does
// not count): the constraints of one colour can be solved in any order, or at once, with the same
// result. The solver takes the colours one after the other (a barrier between them) and splits
// each colour among the threads; the overflow set (constraints that found no free colour: a body
// touching more than kColours others) comes last, solved by one thread in its order.
//
// Which colours. Gauss-Seidel's result depends on the order in which each body receives its
// impulses, and the sequential order (the contact list's, sorted by shape pair) is what the
// contact tests were tuned on: a stack solved bottom-up in one sweep carries the ground's push up
// the whole column. Box2D's greedy colouring (each constraint the first colour free for both of
// its bodies) reorders a column into alternate contacts, and a stack of ten boxes that rests below
// 1 mm/s in the sequential order rocked at 8 mm/s with it (measured). So each constraint, taken in
// the list's order, gets the first free colour after the last colour either of its bodies has
// used: while no body needs more than kColours, colour c holds exactly the constraints at depth c
// of the sequential order's dependency chains (the wavefront or level schedule), and solving the
// colours in turn gives each body the same impulses in the same order as the sequential sweep:
// the same bits. A chain longer than kColours (the 100-cube rows of the large pyramid) wraps
// round to the first colour free for both bodies, a fixed order of its own (5% of the pyramid's
// constraints). The colouring is recomputed every step from the constraint list alone, so a
// resumed run and any thread count get the same colours and the same order within each colour.
#pragma once
#include <cstdint>
#include <vector>

namespace simreel {

class ConstraintGraph {
 public:
  static constexpr int kColours = 32;         ///< colours proper (one bit each in a body's mask)
  static constexpr int kOverflow = kColours;  ///< colour index of the overflow set

  // Colours n constraints, constraint i joining solver bodies a[i] and b[i] (0: the static body)
  // out of `bodies` solver bodies. Afterwards slot(i) is constraint i's position in the solve
  // order (colour by colour, ascending i within a colour) and colour c holds the slots
  // [begin(c), end(c)). Reuses its storage: no allocation once it has seen the largest step.
  void build(int bodies, int n, const int* a, const int* b);

  int slot(int i) const { return slot_[i]; }
  int constraint_at(int slot) const { return at_[slot]; }  ///< slot's inverse
  int colour_of(int i) const { return colour_[i]; }
  int begin(int c) const { return start_[c]; }
  int end(int c) const { return start_[c + 1]; }
  // Colours with at least one constraint, in solve order (the overflow set not included).
  const std::vector<int>& used() const { return used_; }
  int overflow_count() const { return end(kOverflow) - begin(kOverflow); }

 private:
  std::vector<uint32_t> member_;  ///< per body: bit c set if it has a constraint in colour c
  std::vector<int8_t> last_;      ///< per body: the colour of its latest constraint, or -1
  std::vector<uint8_t> colour_;   ///< per constraint
  std::vector<int> slot_;         ///< per constraint
  std::vector<int> at_;           ///< per slot: its constraint
  std::vector<int> start_;        ///< kColours + 2 entries: the overflow set is colour kColours
  std::vector<int> used_;
};

}  // namespace simreel
