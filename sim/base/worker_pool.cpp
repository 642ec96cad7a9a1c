#include "sim/base/worker_pool.hpp"

#include <algorithm>

namespace simreel {

WorkerPool::WorkerPool(int threads, bool backoff)
    : n_(threads), backoff_on_(backoff), progress_(new Progress[threads]) {
  for (int w = 1; w < n_; ++w) workers_.emplace_back([this, w] { worker_loop(w); });
}

WorkerPool::~WorkerPool() {
  quit_.store(true, std::memory_order_release);
  gen_.fetch_add(1, std::memory_order_acq_rel);
  gen_.notify_all();
  for (auto& t : workers_) t.join();
}

void WorkerPool::worker_loop(int w) {
  unsigned seen = 0;
  for (;;) {
    seen = await_change<unsigned>(gen_, seen, false);
    if (quit_.load(std::memory_order_acquire)) return;
    fn_(ctx_, w, n_);
    if (done_.fetch_add(1, std::memory_order_acq_rel) + 1 == n_ - 1) done_.notify_one();
  }
}

void WorkerPool::run(Fn fn, void* ctx) {
  ++runs_;
  if (backoff_ > 0) {
    --backoff_;
    ++alone_;
    fn(ctx, 0, 1);
    return;
  }
  fn_ = fn;
  ctx_ = ctx;
  done_.store(0, std::memory_order_relaxed);
  gen_.fetch_add(1, std::memory_order_acq_rel);
  gen_.notify_all();
  fn_(ctx_, 0, n_);
  for (int d = done_.load(std::memory_order_acquire); d != n_ - 1; d = done_.load(std::memory_order_acquire))
    await_change(done_, d);
  // Every worker has finished (done_ acquired): slow_ holds whatever they saw. One stall now and
  // then (a few ms, ~20 in 20 steps of the large pyramid even with this process's priority
  // raised) costs less than the runs it shares; a second within kWindow runs backs off.
  if (slow_.exchange(false, std::memory_order_relaxed) && backoff_on_ && ++slow_in_window_ >= 2) {
    backoff_ = backoff_next_;
    backoff_next_ = std::min(2 * backoff_next_, kBackoffMax);
    slow_in_window_ = window_runs_ = 0;
    return;
  }
  if (++window_runs_ >= kWindow) {
    if (slow_in_window_ == 0) backoff_next_ = kBackoffMin;
    slow_in_window_ = window_runs_ = 0;
  }
}

// A counting barrier with a generation: the last to arrive resets the count and advances the
// generation, which releases the others (they read the generation before arriving, so a fast
// worker reaching the next barrier cannot be confused with this one).
void WorkerPool::barrier() {
  const unsigned gen = barrier_gen_.load(std::memory_order_acquire);
  if (arrived_.fetch_add(1, std::memory_order_acq_rel) + 1 == n_) {
    arrived_.store(0, std::memory_order_relaxed);
    barrier_gen_.fetch_add(1, std::memory_order_acq_rel);
    barrier_gen_.notify_all();
    return;
  }
  await_change(barrier_gen_, gen);
}

double WorkerPool::await_progress(int v, unsigned target) {
  std::atomic<unsigned>& a = progress_[v].count;
  unsigned seen = a.load(std::memory_order_acquire);
  if ((int)(seen - target) >= 0) return 0;
  const auto t0 = clock::now();
  while ((int)(seen - target) < 0) seen = await_change(a, seen);
  return std::chrono::duration<double>(clock::now() - t0).count();
}

}  // namespace simreel
