// How the workers share the colours of the constraint graph (ContactSolver::by_colour), and how
// little they wait for each other.
//
// Within a colour no two constraints share a moving body, so the workers may solve a colour's
// items (scalar constraints, bundles of four) in any split and any order: the result is that of
// one thread, bit for bit. Between colours they must wait: a body's impulses come in colour order.
// A barrier per colour makes every worker wait for the slowest at every colour; the large pyramid
// has 32 colours of some 500 constraints, phases of ~17 us, and the faster of two workers waited
// there about a tenth of the sweeps' time (session 14).
//
// But a worker only has to wait for the items of the others that touch the bodies its own items
// touch. So the split follows the bodies: each item gets a key (the higher solver body of its
// first constraint; bodies are numbered in the world's order, which for a stack or a pile is
// mostly by place), worker w takes the keys [t_w, t_w+1), the same spans in every colour, and
// then only the bodies near the spans' borders are touched by two workers (the large pyramid: a
// few rows of cubes). Per colour, a worker first solves its items that touch such a shared body,
// then says so (WorkerPool::advance, a count per worker), then solves the rest. Before a colour, a
// worker waits until every other has said so for the colour before (WorkerPool::await_progress).
//
// Why that is enough. Take worker w's item of colour c + 1 touching body B. If no other worker's
// item touches B, w's own order is the colour order. If worker v's items touch B too, B is
// shared, and v's items on B in colours <= c were solved before v's count reached c + 1 (its
// shared items first in each colour), which w waited for; v's items on B in colours >= c + 2
// come after v has waited for w's count to reach c + 2, after w's shared items of colour c + 1,
// this one among them; colour c + 1 has no other item on B. Release on the count and acquire on
// the wait carry the velocities. So a worker may run up to almost a colour ahead of another (the
// rest of that colour), and waits only for the others' shared items, which each does first.
//
// The spans are set from each worker's busy time in the sweeps of the last step (time in
// by_colour, less its waits): fractions of the weighted items, moved halfway toward equal times
// each step. Which worker solves an item never changes a result, so the split may follow timings.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "sim/contact_solver.hpp"

namespace simreel {

namespace {

// Rough relative costs of an item in a sweep, for the first step's split (the times then correct
// it): a bundle of four resting manifolds, a bundle apart at the step's start (mostly a look at
// its gaps, wide::solve), a scalar manifold.
constexpr double kRestingBundle = 4.0, kApartBundle = 1.0, kScalarItem = 2.0;

}  // namespace

void ContactSolver::split_colours() {
  const int nw = workers_;
  const int nb = (int)sb_.size();
  constexpr int kColours = ConstraintGraph::kColours;

  // The fractions, from the busy times of the last step's sweeps: a worker's time per unit of
  // fraction is its cost rate, and equal times want fractions in inverse proportion to it.
  if ((int)worker_fraction_.size() != nw) {
    worker_fraction_.assign(nw, 1.0 / nw);
    worker_time_.assign(nw, WorkerTime{});
    threshold_.assign(nw + 1, 0);
    worker_count_.assign(nw, 0);
  } else {
    bool timed = true;
    for (int w = 0; w < nw; ++w) timed = timed && worker_time_[w].busy > 0;
    if (timed) {
      double sum = 0;
      for (int w = 0; w < nw; ++w) sum += worker_fraction_[w] / worker_time_[w].busy;
      double norm = 0;
      for (int w = 0; w < nw; ++w) {
        const double want = worker_fraction_[w] / worker_time_[w].busy / sum;
        double& f = worker_fraction_[w];
        f = std::max(0.25 / nw, 0.5 * (f + want));
        norm += f;
      }
      for (int w = 0; w < nw; ++w) worker_fraction_[w] /= norm;
    }
    for (int w = 0; w < nw; ++w) worker_time_[w].busy = 0;
  }

  auto key = [&](int slot) {
    const int i = graph_.constraint_at(slot);
    return std::max(edge_a_[i], edge_b_[i]);
  };
  // An item's first constraint's slot: group 0 indexes scalar_, groups 1 and 2 the bundles.
  auto first_slot = [&](int g, int item) { return g == 0 ? scalar_[item] : lane_slot_[item * wide::kLanes]; };
  auto group_begin = [&](int c, int g) {
    return g == 0 ? scalar_start_[c] : (g == 1 ? bundle_start_[c] : bundle_split_[c]);
  };
  auto group_end = [&](int c, int g) {
    return g == 0 ? scalar_start_[c + 1] : (g == 1 ? bundle_split_[c] : bundle_start_[c + 1]);
  };
  constexpr double kWeight[kGroups] = {kScalarItem, kRestingBundle, kApartBundle};

  // Each key's work, and the spans of keys: worker w takes [threshold_[w], threshold_[w + 1]).
  key_weight_.assign(nb, 0.0);
  double total = 0;
  for (const int c : graph_.used())
    for (int g = 0; g < kGroups; ++g)
      for (int n = group_begin(c, g); n < group_end(c, g); ++n) {
        key_weight_[key(first_slot(g, n))] += kWeight[g];
        total += kWeight[g];
      }
  threshold_[0] = 0;
  {
    int w = 1;
    double sum = 0, goal = worker_fraction_[0] * total;
    for (int k = 0; k < nb && w < nw; ++k) {
      while (w < nw && sum >= goal) {
        threshold_[w] = k;
        goal += worker_fraction_[w] * total;
        ++w;
      }
      sum += key_weight_[k];
    }
    for (; w < nw; ++w) threshold_[w] = nb;
    threshold_[nw] = nb;
  }
  auto worker_of = [&](int k) {
    int w = nw - 1;
    while (w > 0 && k < threshold_[w]) --w;
    return w;
  };

  // In each colour's group, worker w takes as many items, in order, as have keys in its span.
  range_.assign((size_t)kColours * kGroups * nw, WorkRange{});
  for (const int c : graph_.used())
    for (int g = 0; g < kGroups; ++g) {
      const int lo = group_begin(c, g), hi = group_end(c, g);
      std::fill(worker_count_.begin(), worker_count_.end(), 0);
      for (int n = lo; n < hi; ++n) ++worker_count_[worker_of(key(first_slot(g, n)))];
      WorkRange* r = &range_[((size_t)c * kGroups + g) * nw];
      for (int w = 0, at = lo; w < nw; ++w) {
        r[w].lo = at;
        at += worker_count_[w];
        r[w].hi = at;
      }
    }

  // The bodies each worker's items touch (bit w; the static body is never written).
  body_workers_.assign(nb, 0);
  const bool every_item_shared = nw > 32;  // more workers than bits: wait as at a barrier
  auto for_each_constraint = [&](int g, int n, auto&& f) {
    if (g == 0) {
      f(graph_.constraint_at(scalar_[n]));
      return;
    }
    for (int l = 0; l < wide::kLanes; ++l) {
      const int slot = lane_slot_[n * wide::kLanes + l];
      if (slot >= 0) f(graph_.constraint_at(slot));
    }
  };
  if (!every_item_shared)
    for (const int c : graph_.used())
      for (int g = 0; g < kGroups; ++g) {
        const WorkRange* r = &range_[((size_t)c * kGroups + g) * nw];
        for (int w = 0; w < nw; ++w)
          for (int n = r[w].lo; n < r[w].hi; ++n)
            for_each_constraint(g, n, [&](int i) {
              body_workers_[edge_a_[i]] |= 1u << w;
              body_workers_[edge_b_[i]] |= 1u << w;
            });
      }
  body_workers_[0] = 0;
  auto shared = [&](int g, int n) {
    if (every_item_shared) return true;
    bool any = false;
    for_each_constraint(g, n, [&](int i) {
      const uint32_t ma = body_workers_[edge_a_[i]], mb = body_workers_[edge_b_[i]];
      any = any || (ma & (ma - 1)) != 0 || (mb & (mb - 1)) != 0;
    });
    return any;
  };

  // In each worker's range, the longest run of items touching no shared body, [a, b), is solved
  // after the others (those at either end, mostly: the spans' borders).
  for (const int c : graph_.used())
    for (int g = 0; g < kGroups; ++g)
      for (int w = 0; w < nw; ++w) {
        WorkRange& r = range_[((size_t)c * kGroups + g) * nw + w];
        r.a = r.b = r.lo;
        for (int n = r.lo, run = r.lo; n < r.hi; ++n) {
          if (shared(g, n)) {
            run = n + 1;
            continue;
          }
          if (n + 1 - run > r.b - r.a) r.a = run, r.b = n + 1;
        }
      }
}

int ContactSolver::split_faults(long* deferred, long* items) const {
  if (deferred) *deferred = 0;
  if (items) *items = 0;
  const int nw = workers_;
  if (nw < 2) return 0;
  int faults = 0;
  // Which workers touch each body, from the ranges alone.
  std::vector<uint64_t> touch(sb_.size(), 0);
  auto constraints = [&](int g, int n, auto&& f) {
    if (g == 0) return f(graph_.constraint_at(scalar_[n]));
    for (int l = 0; l < wide::kLanes; ++l)
      if (lane_slot_[n * wide::kLanes + l] >= 0) f(graph_.constraint_at(lane_slot_[n * wide::kLanes + l]));
  };
  for (const int c : graph_.used())
    for (int g = 0; g < kGroups; ++g) {
      const int lo = g == 0 ? scalar_start_[c] : (g == 1 ? bundle_start_[c] : bundle_split_[c]);
      const int hi = g == 0 ? scalar_start_[c + 1] : (g == 1 ? bundle_split_[c] : bundle_start_[c + 1]);
      int at = lo;
      for (int w = 0; w < nw; ++w) {
        const WorkRange& r = range_[((size_t)c * kGroups + g) * nw + w];
        if (r.lo != at || r.lo > r.a || r.a > r.b || r.b > r.hi) ++faults;
        at = r.hi;
        for (int n = r.lo; n < r.hi; ++n)
          constraints(g, n, [&](int i) {
            touch[edge_a_[i]] |= 1ull << (w % 64);
            touch[edge_b_[i]] |= 1ull << (w % 64);
          });
      }
      if (at != hi) ++faults;
    }
  touch[0] = 0;  // the static body is never written
  for (const int c : graph_.used())
    for (int g = 0; g < kGroups; ++g)
      for (int w = 0; w < nw; ++w) {
        const WorkRange& r = range_[((size_t)c * kGroups + g) * nw + w];
        if (deferred) *deferred += r.b - r.a;
        if (items) *items += r.hi - r.lo;
        for (int n = r.a; n < r.b; ++n)
          constraints(g, n, [&](int i) {
            for (const int body : {edge_a_[i], edge_b_[i]})
              if ((touch[body] & ~(1ull << (w % 64))) != 0) ++faults;
          });
      }
  return faults;
}

}  // namespace simreel
