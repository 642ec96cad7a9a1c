// A small persistent pool of worker threads for the step's parallel stages (free-flight
// integration, the narrow phase, the contact solver). Made once with the world: no thread is
// created and nothing is allocated per step.
//
// run(f) calls f(worker, workers) once on every worker, worker 0 on the calling thread, and
// returns when all have finished. Inside it, barrier() holds every worker until all have arrived
// (the contact solver's colours: one barrier per colour). Work is split by the callers into fixed
// ranges by worker index, or claimed from a shared counter where results do not depend on who
// does which item, so no result depends on the thread count or on timing.
//
// Waiting spins first (a step's next piece of work arrives within microseconds) and then blocks
// in atomic::wait, so an idle pool costs nothing. Waking a blocked thread took ~0.3 ms on this
// machine's VM (futex wake + hypervisor scheduling), longer than a stage: with a 0.1 ms spin the
// worker fell asleep every step and 2 threads ran at 0.7x one thread. std::barrier's futex hand-off
// cost more than the work it split at N = 1000..10000 bodies (2 threads slower than 1).
#pragma once
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace simreel {

class WorkerPool {
 public:
  using Fn = void (*)(void* ctx, int worker, int workers);
  explicit WorkerPool(int threads);  ///< threads >= 2; worker 0 is the caller of run()
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int size() const { return n_; }
  void run(Fn fn, void* ctx);
  template <typename F>
  void run(F& f) {
    run([](void* p, int w, int nw) { (*static_cast<F*>(p))(w, nw); }, &f);
  }
  // Called by every worker inside run(): returns once all of them have called it.
  void barrier();

  // Tells an SMT sibling that this thread is only waiting (x86 pause).
  static void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
  }

 private:
  static constexpr std::chrono::microseconds kSpin{2000};
  // Spins for up to kSpin while `a` holds `seen`, then sleeps in atomic::wait; returns the new value.
  template <typename T>
  static T await_change(std::atomic<T>& a, T seen) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int spins = 1;; ++spins) {
      const T v = a.load(std::memory_order_acquire);
      if (v != seen) return v;
      cpu_relax();
      if (spins % 256 == 0 && std::chrono::steady_clock::now() - t0 > kSpin) {
        a.wait(seen, std::memory_order_acquire);
        return a.load(std::memory_order_acquire);
      }
    }
  }
  void worker_loop(int w);

  int n_;
  // Each shared counter on its own cache line: the workers spin on them.
  alignas(64) std::atomic<unsigned> gen_{0};  ///< run() generation
  alignas(64) std::atomic<int> done_{0};      ///< workers finished with this run
  alignas(64) std::atomic<int> arrived_{0};   ///< workers at the barrier
  alignas(64) std::atomic<unsigned> barrier_gen_{0};
  alignas(64) std::atomic<bool> quit_{false};
  Fn fn_ = nullptr;
  void* ctx_ = nullptr;
  std::vector<std::thread> workers_;
};

// The contiguous share [begin, end) of n items that worker w of nw takes (fixed: the same items
// every call, so a worker's data stays in its core's cache from stage to stage and step to step).
inline void share(int n, int w, int nw, int& begin, int& end) {
  begin = (int)((long)n * w / nw);
  end = (int)((long)n * (w + 1) / nw);
}

}  // namespace simreel
