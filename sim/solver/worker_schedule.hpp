// The colour schedule: how the workers share each colour of the constraint graph in the contact
// solver's sweeps (ContactSolver::by_colour), and which of each share they solve first so that the
// others wait only where they share bodies (worker_schedule.cpp has the reasoning and the model).
// Owns the split in use and the one tried against it, the items' bodies as the split reads them,
// the per-worker fractions and busy times it follows, and its scratch; reads the solver's layout of
// the step (the colouring, the wide lanes, the scalar entries) through a Layout record. Which
// worker solves an item never changes a result: the split may follow timings.
#pragma once
#include <cstdint>
#include <vector>

#include "sim/solver/constraint_graph.hpp"

namespace simreel {

class WorkerSchedule {
 public:
  // Per colour: group 0 its scalar_ entries, 1 its bundles resting, 2 its bundles apart.
  static constexpr int kGroups = 3;
  // One worker's part of one colour's group: it solves [lo, a) and [b, hi) (the items touching a
  // body that another worker's items touch), then tells the others it has
  // (WorkerPool::advance), then [a, b).
  struct WorkRange {
    int lo = 0, a = 0, b = 0, hi = 0;
  };

  // What the split reads of the solver's step (ContactSolver's arrays).
  struct Layout {
    const ConstraintGraph* graph = nullptr;
    const std::vector<int>* lane_slot = nullptr;  ///< per lane (4 bundle + lane): its slot, or -1
    const std::vector<int>* edge_a = nullptr;     ///< per constraint: its solver bodies
    const std::vector<int>* edge_b = nullptr;
    const std::vector<int>* scalar = nullptr;        ///< slots on the scalar path, colour by colour
    const std::vector<int>* scalar_start = nullptr;  ///< kColours + 2 entries: colour c's in scalar
    const std::vector<int>* bundle_start = nullptr;  ///< kColours + 2 entries: colour c's bundles
    const std::vector<int>* bundle_split = nullptr;  ///< per colour: its first bundle of manifolds apart
    int bodies = 0;                                  ///< solver bodies (with the static body, 0)
    int workers = 1;
    // Colour c's group g: its items [group_begin, group_end).
    int group_begin(int c, int g) const {
      return g == 0 ? (*scalar_start)[c] : (g == 1 ? (*bundle_start)[c] : (*bundle_split)[c]);
    }
    int group_end(int c, int g) const {
      return g == 0 ? (*scalar_start)[c + 1] : (g == 1 ? (*bundle_split)[c] : (*bundle_start)[c + 1]);
    }
  };

  // The step's split among in.workers (two or more), after the fractions are rebalanced from the
  // last step's busy times (prepare).
  void split(const Layout& in);
  // Worker w's ranges of colour c, one per group g at [g * workers] (split's workers).
  const WorkRange* ranges(int c, int w, int workers) const {
    return &range_[(size_t)c * kGroups * workers + w];
  }
  // Worker w's time in the sweeps, less its waits (s): the next split's fractions follow it.
  void add_busy(int w, double seconds) { worker_time_[w].busy += seconds; }
  /// The split chosen last: fractions of each colour, else spans of bodies.
  bool by_fractions() const { return split_by_fraction_; }

 private:
  struct BodyPair {
    int a, b;  ///< solver bodies
  };
  void split_by_spans(const Layout& in, std::vector<WorkRange>& range);
  void split_by_fractions(const Layout& in, std::vector<WorkRange>& range) const;
  // a and b of each range, from the shared bodies; returns the split's modelled time.
  double finish_split(const Layout& in, std::vector<WorkRange>& range);

  // Per colour c, group g and worker w, range_[(c * kGroups + g) * workers + w].
  std::vector<WorkRange> range_, range_alt_;       ///< the split used; the other one tried
  std::vector<BodyPair> lane_body_, scalar_body_;  ///< per lane, per scalar entry (split)
  std::vector<uint32_t> body_workers_;   ///< per solver body: bit w set if worker w's items touch it
  std::vector<double> key_weight_;       ///< per solver body: the work of the items keyed by it
  std::vector<double> worker_fraction_;  ///< per worker: its fraction of the weighted items
  std::vector<int> threshold_;           ///< workers + 1 entries: worker w takes keys [t_w, t_w+1)
  std::vector<int> worker_count_;        ///< per worker: scratch (split_by_spans)
  std::vector<double> model_start_, model_publish_;  ///< per worker: scratch (finish_split)
  long split_steps_ = 0;                             ///< steps split among workers
  bool split_by_fraction_ = false;  ///< the last choice: split_by_fractions, else split_by_spans
  struct alignas(64) WorkerTime {   // per worker, its own cache line
    double busy = 0;                ///< s in by_colour this step, not waiting
  };
  std::vector<WorkerTime> worker_time_;
};

}  // namespace simreel
