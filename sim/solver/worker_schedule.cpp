// How the workers share the colours of the constraint graph (WorkerSchedule, worker_schedule.hpp;
// used by ContactSolver::by_colour), and how little they wait for each other.
//
// Within a colour no two constraints share a moving body, so the workers may solve a colour's
// items (scalar constraints, bundles of four) in any split and any order: the result is that of
// one thread, bit for bit. Between colours they must wait: a body's impulses come in colour order.
// A barrier per colour makes every worker wait for the slowest at every colour; the large pyramid
// has 32 colours of some 500 constraints, phases of ~17 us, and the faster of two workers waited
// there about a tenth of the sweeps' time.
//
// But a worker only has to wait for the items of the others that touch the bodies its own items
// touch. So, per colour, a worker first solves its items that touch a body another worker's items
// touch (a shared body), then says so (WorkerPool::advance, a count per worker), then solves the
// rest. Before a colour, a worker waits until every other has said so for the colour before
// (WorkerPool::await_progress).
//
// Why that is enough. Take worker w's item of colour c + 1 touching body B. If no other worker's
// item touches B, w's own order is the colour order. If worker v's items touch B too, B is
// shared, and v's items on B in colours <= c were solved before v's count reached c + 1 (its
// shared items first in each colour), which w waited for; v's items on B in colours >= c + 2
// come after v has waited for w's count to reach c + 2, after w's shared items of colour c + 1,
// this one among them; colour c + 1 has no other item on B. Release on the count and acquire on
// the wait carry the velocities. So a worker may run up to almost a colour ahead of another (the
// rest of that colour), and waits only for the others' shared items, which each does first.
// (tests/sim/solver/worker_schedule_test.cpp checks the split against this.)
//
// Which split. Few shared bodies and colours shared out evenly pull apart, and two ways serve
// different scenes (split_by_spans, split_by_fractions); a model of the schedule (finish_split)
// picks one every few steps. The large pyramid takes spans of bodies: 6% of its items shared,
// where fractions of each colour share a third of them and ran 8% slower; the R3 pile takes
// fractions: its colours are its layers, each in one span of bodies, and with spans the workers
// took the layers in turn (two threads at 1.13x one thread, against 1.32x with fractions).
//
// The fractions are set from each worker's busy time in the sweeps of the last step (time in
// by_colour, less its waits), moved halfway toward equal times each step. Which worker solves an
// item never changes a result, so the split may follow timings.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "sim/solver/contact_solver.hpp"
#include "sim/solver/worker_schedule.hpp"

namespace simreel {

namespace {

// Rough relative costs of an item in a sweep (the split's model, and the first step's spans; the
// times then correct the fractions): a scalar manifold, a bundle of four resting manifolds, a
// bundle apart at the step's start (mostly a look at its gaps, wide::solve).
constexpr double kItemWeight[3] = {2.0, 4.0, 1.0};
// An item on a shared body costs more: the body's cache lines come from the other core. The
// large pyramid ran 8% slower on two threads with a third of its items shared (each colour split
// in fractions) than with 6% (spans), a cost of about 1.5 items each (measured, 2 x 2 runs).
constexpr double kSharedCost = 1.5;
constexpr int kChooseEvery = 8;

}  // namespace

void WorkerSchedule::split(const Layout& in) {
  const int nw = in.workers;
  const ConstraintGraph& graph = *in.graph;
  const std::vector<int>& lane_slot = *in.lane_slot;
  const std::vector<int>& scalar = *in.scalar;
  const std::vector<int>& edge_a = *in.edge_a;
  const std::vector<int>& edge_b = *in.edge_b;
  // The fractions, from the busy times of the last step's sweeps: a worker's time per unit of
  // fraction is its cost rate, and equal times want fractions in inverse proportion to it.
  if ((int)worker_fraction_.size() != nw) {
    worker_fraction_.assign(nw, 1.0 / nw);
    worker_time_.assign(nw, WorkerTime{});
    threshold_.assign(nw + 1, 0);
    worker_count_.assign(nw, 0);
    model_start_.assign(nw, 0.0);
    model_publish_.assign(nw, 0.0);
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
  // Each lane's and each scalar entry's two solver bodies (0: the static body, or a padding lane),
  // read in order by the passes below.
  lane_body_.resize(lane_slot.size());
  for (size_t l = 0; l < lane_slot.size(); ++l) {
    const int i = lane_slot[l] >= 0 ? graph.constraint_at(lane_slot[l]) : -1;
    lane_body_[l] = i >= 0 ? BodyPair{edge_a[i], edge_b[i]} : BodyPair{0, 0};
  }
  scalar_body_.resize(scalar.size());
  for (size_t n = 0; n < scalar.size(); ++n) {
    const int i = graph.constraint_at(scalar[n]);
    scalar_body_[n] = BodyPair{edge_a[i], edge_b[i]};
  }
  // Two ways to share the colours; the one the model says ends sooner, tried every kChooseEvery
  // steps (the way a scene suits changes slowly; each costs ~0.08 ms a step on the pyramid).
  if (split_steps_++ % kChooseEvery == 0) {
    split_by_spans(in, range_);
    const double spans = finish_split(in, range_);
    split_by_fractions(in, range_alt_);
    const double fractions = finish_split(in, range_alt_);
    split_by_fraction_ = fractions < spans;
    if (split_by_fraction_) range_.swap(range_alt_);
  } else {
    if (split_by_fraction_)
      split_by_fractions(in, range_);
    else
      split_by_spans(in, range_);
    finish_split(in, range_);
  }
}

// Spans of bodies: an item's key is the higher solver body of its first constraint, and worker w
// takes the keys [threshold_[w], threshold_[w + 1]), set so that each has its fraction of the
// weighted items; in each colour's group it takes as many items, in order, as have keys in its
// span. Few shared bodies where each colour spreads over the bodies (the large pyramid, whose
// rows wrap round the colours); a colour that lies in one span (a pile's layer, when its bodies
// are numbered layer by layer) is solved by one worker while the others wait.
void WorkerSchedule::split_by_spans(const Layout& in, std::vector<WorkRange>& range) {
  const int nw = in.workers;
  const int nb = in.bodies;
  const ConstraintGraph& graph = *in.graph;
  auto key = [&](int g, int n) {
    const BodyPair& p = g == 0 ? scalar_body_[n] : lane_body_[n * wide::kLanes];
    return std::max(p.a, p.b);
  };
  key_weight_.assign(nb, 0.0);
  double total = 0;
  for (const int c : graph.used())
    for (int g = 0; g < kGroups; ++g)
      for (int n = in.group_begin(c, g); n < in.group_end(c, g); ++n) {
        key_weight_[key(g, n)] += kItemWeight[g];
        total += kItemWeight[g];
      }
  threshold_[0] = 0;
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
  range.assign((size_t)ConstraintGraph::kColours * kGroups * nw, WorkRange{});
  for (const int c : graph.used())
    for (int g = 0; g < kGroups; ++g) {
      const int lo = in.group_begin(c, g), hi = in.group_end(c, g);
      std::fill(worker_count_.begin(), worker_count_.end(), 0);
      for (int n = lo; n < hi; ++n) {
        const int k = key(g, n);
        int v = nw - 1;
        while (v > 0 && k < threshold_[v]) --v;
        ++worker_count_[v];
      }
      WorkRange* r = &range[((size_t)c * kGroups + g) * nw];
      for (int v = 0, at = lo; v < nw; ++v) {
        r[v].lo = at;
        at += worker_count_[v];
        r[v].hi = at;
      }
    }
}

// Fractions of each colour: in each colour's group worker w takes the fraction
// worker_fraction_[w] of the items, in order. Every colour is shared out evenly, and where the
// colours' items are numbered alike (a pile's layers) the workers' parts line up from colour to
// colour; where a colour's items spread over all the bodies, the borders move from colour to
// colour and more bodies are shared.
void WorkerSchedule::split_by_fractions(const Layout& in, std::vector<WorkRange>& range) const {
  const int nw = in.workers;
  range.assign((size_t)ConstraintGraph::kColours * kGroups * nw, WorkRange{});
  for (const int c : in.graph->used())
    for (int g = 0; g < kGroups; ++g) {
      const int lo = in.group_begin(c, g), hi = in.group_end(c, g);
      WorkRange* r = &range[((size_t)c * kGroups + g) * nw];
      double upto = 0;
      for (int w = 0, at = lo; w < nw; ++w) {
        upto += worker_fraction_[w];
        r[w].lo = at;
        at = w + 1 == nw ? hi : std::min(hi, lo + (int)std::lround(upto * (hi - lo)));
        r[w].hi = at;
      }
    }
}

// The shared bodies of a split, each range's part to solve first (lo..a, b..hi) and last (a..b),
// and how long the split takes by a model: items weighted by kItemWeight, each worker solving a
// colour's first part, advancing, then its last part, and starting the next colour once its own
// work and the others' first parts of this colour are done. Returns the modelled time.
double WorkerSchedule::finish_split(const Layout& in, std::vector<WorkRange>& range) {
  const int nw = in.workers;
  const ConstraintGraph& graph = *in.graph;
  body_workers_.assign(in.bodies, 0);
  const bool every_item_shared = nw > 32;  // more workers than bits: wait as at a barrier
  // An item's body pairs: one for a scalar entry, four for a bundle.
  auto pairs = [&](int g, int n) {
    return g == 0
               ? std::make_pair(&scalar_body_[n], &scalar_body_[n] + 1)
               : std::make_pair(&lane_body_[n * wide::kLanes], &lane_body_[n * wide::kLanes] + wide::kLanes);
  };
  if (!every_item_shared)
    for (const int c : graph.used())
      for (int g = 0; g < kGroups; ++g) {
        const WorkRange* r = &range[((size_t)c * kGroups + g) * nw];
        for (int w = 0; w < nw; ++w)
          for (int n = r[w].lo; n < r[w].hi; ++n)
            for (auto [p, e] = pairs(g, n); p != e; ++p) {
              body_workers_[p->a] |= 1u << w;
              body_workers_[p->b] |= 1u << w;
            }
      }
  body_workers_[0] = 0;  // the static body is never written
  auto shared = [&](int g, int n) {
    if (every_item_shared) return true;
    for (auto [p, e] = pairs(g, n); p != e; ++p) {
      const uint32_t ma = body_workers_[p->a], mb = body_workers_[p->b];
      if ((ma & (ma - 1)) != 0 || (mb & (mb - 1)) != 0) return true;
    }
    return false;
  };
  // In each worker's range, the longest run of items touching no shared body, [a, b), is solved
  // after the others (those at either end, mostly: the borders).
  std::fill(model_start_.begin(), model_start_.end(), 0.0);
  for (const int c : graph.used()) {
    for (int w = 0; w < nw; ++w) {
      double first = 0, last = 0;
      for (int g = 0; g < kGroups; ++g) {
        WorkRange& r = range[((size_t)c * kGroups + g) * nw + w];
        r.a = r.b = r.lo;
        for (int n = r.lo, run = r.lo; n < r.hi; ++n) {
          if (shared(g, n)) {
            run = n + 1;
            continue;
          }
          if (n + 1 - run > r.b - r.a) r.a = run, r.b = n + 1;
        }
        last += kItemWeight[g] * (r.b - r.a);
        first += kSharedCost * kItemWeight[g] * (r.hi - r.lo - (r.b - r.a));
      }
      model_publish_[w] = model_start_[w] + first;
      model_start_[w] = model_publish_[w] + last;  // its end of this colour, for now
    }
    for (int w = 0; w < nw; ++w)
      for (int v = 0; v < nw; ++v) model_start_[w] = std::max(model_start_[w], model_publish_[v]);
  }
  return *std::max_element(model_start_.begin(), model_start_.end());
}

WorkerSchedule::Layout ContactSolver::schedule_layout() const {
  WorkerSchedule::Layout in;
  in.graph = &graph_;
  in.lane_slot = &lane_slot_;
  in.edge_a = &edge_a_;
  in.edge_b = &edge_b_;
  in.scalar = &scalar_;
  in.scalar_start = &scalar_start_;
  in.bundle_start = &bundle_start_;
  in.bundle_split = &bundle_split_;
  in.bodies = (int)sb_.size();
  in.workers = workers_;
  return in;
}

int ContactSolver::split_faults(long* deferred, long* items) const {
  if (deferred) *deferred = 0;
  if (items) *items = 0;
  const int nw = workers_;
  if (nw < 2) return 0;
  constexpr int kGroups = WorkerSchedule::kGroups;
  using WorkRange = WorkerSchedule::WorkRange;
  const WorkerSchedule::Layout layout = schedule_layout();
  int faults = 0;
  // Which workers touch each body, from the ranges alone.
  std::vector<uint64_t> touch(sb_.size(), 0);
  // An item's bodies as the sweeps read them (the records made after the split: an oracle
  // apart from the split's own copies).
  auto bodies = [&](int g, int n, auto&& f) {
    if (g == 0) return f(sweep_[scalar_[n]].a, sweep_[scalar_[n]].b);
    for (int l = 0; l < wide::kLanes; ++l) f(bundles_[n].a[l], bundles_[n].b[l]);
  };
  for (const int c : graph_.used())
    for (int g = 0; g < kGroups; ++g) {
      const int lo = layout.group_begin(c, g), hi = layout.group_end(c, g);
      int at = lo;
      for (int w = 0; w < nw; ++w) {
        const WorkRange& r = schedule_.ranges(c, w, nw)[g * nw];
        if (r.lo != at || r.lo > r.a || r.a > r.b || r.b > r.hi) ++faults;
        at = r.hi;
        for (int n = r.lo; n < r.hi; ++n)
          bodies(g, n, [&](int a, int b) {
            touch[a] |= 1ull << (w % 64);
            touch[b] |= 1ull << (w % 64);
          });
      }
      if (at != hi) ++faults;
    }
  touch[0] = 0;  // the static body is never written
  for (const int c : graph_.used())
    for (int g = 0; g < kGroups; ++g)
      for (int w = 0; w < nw; ++w) {
        const WorkRange& r = schedule_.ranges(c, w, nw)[g * nw];
        if (deferred) *deferred += r.b - r.a;
        if (items) *items += r.hi - r.lo;
        for (int n = r.a; n < r.b; ++n)
          bodies(g, n, [&](int a, int b) {
            for (const int body : {a, b})
              if ((touch[body] & ~(1ull << (w % 64))) != 0) ++faults;
          });
      }
  return faults;
}

}  // namespace simreel
