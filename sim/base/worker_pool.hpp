// A small persistent pool of worker threads for the step's parallel stages (free-flight
// integration, the narrow phase, the contact solver). Made once with the world: no thread is
// created and nothing is allocated per step.
//
// run(f) calls f(worker, workers) once on every worker, worker 0 on the calling thread, and
// returns when all have finished. Inside it, barrier() holds every worker until all have arrived,
// and advance / await_progress let one worker wait for another's count of milestones (the
// contact solver's colours, sim/solver/worker_schedule.cpp). Work is split by the callers into fixed
// ranges by worker index, or claimed from a shared counter where results do not depend on who
// does which item, so no result depends on the thread count or on timing.
//
// Waiting spins (x86 pause) for up to kSpin and then blocks in atomic::wait, so an idle pool
// costs nothing. Waking a blocked thread took ~0.3 ms on this machine's VM, and several ms when
// its cores were busy: the large pyramid's serial parts between two runs (the colouring, the
// broad phase, the merge of the pairs) take a few ms, and with a 2 ms spin the worker fell asleep
// there and the waits made the pool back off for 896 of its 1844 runs in 20 steps (1.47x one
// thread); with 5 ms, 64 runs (1.54x). Not sched_yield while spinning: a yielded core went to
// another process for up to a scheduler tick (~20 stalls of 3-4 ms in those 20 steps).
//
// Back-off. Fine-grained work needs every worker on a core at once. When the machine is busier
// than its cores (other processes, or more threads than cores) a worker is often not running,
// and each barrier then waits for the scheduler (ms): the R3 pile with two threads on a machine
// at load 20 ran 75x slower than with one. So when two runs within kWindow runs have a wait
// longer than kSlow, the next runs go on the calling thread alone (f(0, 1)), 64 runs, doubling
// while it keeps happening (up to 4096), and then the pool is tried again. Callers split work by
// the `workers` they are given, and every split gives the same results, so this changes timing
// only, never a result.
#pragma once
#include <atomic>
#include <chrono>
#include <memory>
#include <thread>
#include <vector>

namespace simreel {

class WorkerPool {
 public:
  using Fn = void (*)(void* ctx, int worker, int workers);
  /// threads >= 2; worker 0 is the caller of run(). `backoff`: false never runs alone (tests).
  explicit WorkerPool(int threads, bool backoff = true);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int size() const { return n_; }
  // f(worker, workers) on every worker, or f(0, 1) on the caller alone while backing off.
  void run(Fn fn, void* ctx);
  template <typename F>
  void run(F& f) {
    run([](void* p, int w, int nw) { (*static_cast<F*>(p))(w, nw); }, &f);
  }
  // Called by every worker inside run(): returns once all of them have called it.
  void barrier();
  // Point-to-point progress (the contact solver's colours, sim/solver/worker_schedule.cpp): each worker
  // counts its own milestones, and another waits until that count reaches a target, instead of
  // every worker waiting for all at a barrier. advance(w): worker w's count + 1 (release: what w
  // wrote before is seen by whoever sees the count). await_progress(v, target): returns once
  // worker v's count has reached target (wrapping compare), in seconds waited (0 if at once).
  unsigned progress(int w) const { return progress_[w].count.load(std::memory_order_relaxed); }
  void advance(int w) {
    progress_[w].count.fetch_add(1, std::memory_order_release);
    progress_[w].count.notify_all();
  }
  double await_progress(int v, unsigned target);
  long runs() const { return runs_; }         ///< run() calls
  long alone_runs() const { return alone_; }  ///< of which on the caller alone (back-off)

  // Tells an SMT sibling that this thread is only waiting (x86 pause).
  static void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
  }

 private:
  using clock = std::chrono::steady_clock;
  static constexpr std::chrono::microseconds kSpin{5000}, kSlow{5000};
  static constexpr int kBackoffMin = 64, kBackoffMax = 4096, kWindow = 32;
  // Waits while `a` holds `seen` (pause, then atomic::wait); returns the new value.
  // `timed`: a wait inside a run (a barrier, the end of a run), where a long one means a worker
  // was not running; an idle worker's wait for the next run is not.
  template <typename T>
  T await_change(std::atomic<T>& a, T seen, bool timed = true) {
    const auto t0 = clock::now();
    for (int spins = 1;; ++spins) {
      const T v = a.load(std::memory_order_acquire);
      if (v != seen) {
        if (timed && spins > 64 && clock::now() - t0 > kSlow) slow_.store(true, std::memory_order_relaxed);
        return v;
      }
      if (spins % 64 != 0) {
        cpu_relax();
        continue;
      }
      const auto waited = clock::now() - t0;
      if (waited > kSpin) {
        if (timed) slow_.store(true, std::memory_order_relaxed);
        a.wait(seen, std::memory_order_acquire);
        return a.load(std::memory_order_acquire);
      }
    }
  }
  void worker_loop(int w);

  int n_;
  bool backoff_on_;
  // Each shared counter on its own cache line: the workers spin on them.
  alignas(64) std::atomic<unsigned> gen_{0};  ///< run() generation
  alignas(64) std::atomic<int> done_{0};      ///< workers finished with this run
  alignas(64) std::atomic<int> arrived_{0};   ///< workers at the barrier
  alignas(64) std::atomic<unsigned> barrier_gen_{0};
  alignas(64) std::atomic<bool> quit_{false};
  alignas(64) std::atomic<bool> slow_{false};  ///< a wait took longer than kSlow
  struct alignas(64) Progress {
    std::atomic<unsigned> count{0};
  };
  std::unique_ptr<Progress[]> progress_;  ///< per worker, one cache line each
  Fn fn_ = nullptr;
  void* ctx_ = nullptr;
  int backoff_ = 0, backoff_next_ = kBackoffMin;  ///< runs left alone; the next back-off's length
  int slow_in_window_ = 0, window_runs_ = 0;      ///< slow runs among the last window_runs_ runs
  long runs_ = 0, alone_ = 0;
  std::vector<std::thread> workers_;
};

// The contiguous share [begin, end) of n items that worker w of nw takes (fixed: the same items
// every call, so a worker's data stays in its core's cache from stage to stage and step to step).
inline void share(int n, int w, int nw, int& begin, int& end) {
  begin = (int)((long)n * w / nw);
  end = (int)((long)n * (w + 1) / nw);
}

}  // namespace simreel
