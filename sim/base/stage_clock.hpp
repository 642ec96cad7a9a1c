// The step's bookkeeping of its stages (Box2D's b2Profile): each stage's wall time, taken only
// when profiling is on (a clock read costs about 20 ns, a stage as little as 50 ns in small
// scenes), and the steps in which it ran or had nothing to do, always counted.
#pragma once
#include <chrono>
#include <type_traits>

#include <simreel/profile.hpp>

namespace simreel {

class StageClock {
 public:
  explicit StageClock(Profile& profile) : profile_(profile) {}
  void set_timing(bool on) { on_ = on; }
  bool timing() const { return on_; }

  // Adds the time until it is destroyed to stage s's seconds (when timing).
  class Scope {
   public:
    Scope(StageClock& c, Stage s) : acc_(c.on_ ? &c.profile_.seconds[(int)s] : nullptr) {
      if (acc_) t0_ = std::chrono::steady_clock::now();
    }
    ~Scope() {
      if (acc_) *acc_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    double* acc_;
    std::chrono::steady_clock::time_point t0_;
  };

  // Times f() into stage s and returns what it returns (counts nothing).
  template <class F>
  auto time(Stage s, F&& f) {
    Scope t(*this, s);
    return f();
  }
  // Times f() into stage s and counts a run; f returning bool says whether the stage had work
  // (false: counted as skipped).
  template <class F>
  void run(Stage s, F&& f) {
    if constexpr (std::is_void_v<decltype(f())>) {
      time(s, f);
      ran(s);
    } else {
      done(s, time(s, f));
    }
  }
  void ran(Stage s) { profile_.runs[(int)s]++; }
  void skipped(Stage s) { profile_.skipped[(int)s]++; }
  void done(Stage s, bool had_work) { had_work ? ran(s) : skipped(s); }
  void add_seconds(Stage s, double seconds) { profile_.seconds[(int)s] += seconds; }

 private:
  Profile& profile_;
  bool on_ = false;
};

}  // namespace simreel
