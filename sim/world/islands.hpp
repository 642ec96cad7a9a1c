// Islands and sleeping (docs/sleeping.md): groups of touching bodies that have all been still for
// a while stop being stepped until something wakes them. Box2D v3 and Jolt do the same with a
// speed threshold and a time; here only bodies the contact solver stepped count time (a body in
// free flight keeps its exact integrator and never stops on its own, however slow), and the speed
// is that of the body's fastest point, |v| + |w| r.
//
// Owns which bodies are awake (the list the broad phase and continuous collision walk), each
// body's still time and island (saved state), and the sleeping islands' member lists. A sleeping
// island is a list threaded through island_next_, from its id (its least body, itself a member) in
// ascending order: waking it visits its bodies only.
#pragma once
#include <string>
#include <vector>

#include "sim/collision/body_extents.hpp"
#include "sim/collision/contact.hpp"
#include "sim/dynamics/state.hpp"

namespace simreel {

class Islands {
 public:
  // Everyone awake; the bodies that move (not static) make the awake list. Sleeping stays off
  // until enable().
  void reset(const std::vector<BodyModel>& model);
  // Sleeping on, for the bodies whose may_sleep flag is set (dynamic, under no continuous force).
  void enable(std::vector<char> may_sleep);
  bool enabled() const { return enabled_; }
  bool may_sleep(int i) const { return enabled_ && may_sleep_[i]; }

  bool asleep(int i) const { return asleep_[i] >= 0; }
  int island(int i) const { return asleep_[i]; }  ///< -1 awake, else its island's id (its least body)
  double still_time(int i) const { return still_time_[i]; }  ///< s, slow and touching
  int sleeping() const { return sleeping_; }
  // Static, asleep, or kinematic at rest: neither moves nor wakes anything (asleep_ first: a
  // compact array).
  bool inert(int i, const BodyModel& m, const MotionState& s) const {
    return asleep_[i] >= 0 || m.is_static || (m.is_kinematic && s.v_W.isZero(0) && s.w_P.isZero(0));
  }

  // The awake bodies that move, ascending.
  const std::vector<int>& awake_bodies() {
    sort_awake();
    return awake_;
  }
  const std::vector<int>& awake_bodies_unsorted() const { return awake_; }
  void sort_awake();
  // Shapes of bodies that fell asleep (or were restored asleep) since the broad phase last took
  // them: each gets one box at rest there.
  std::vector<int>& pending_freeze() { return pending_freeze_; }

  // Wakes i's island, if it sleeps: its bodies join the awake list (sorted before its next use).
  void wake(int i);

  // The sleep stage. Still time: a body counts it while the solver stepped it (in_contact) and its
  // fastest point is slower than `speed` (m/s). Islands: union-find over the contacts between two
  // awake dynamic bodies and over the bonds. An island sleeps when its least still body has been still for
  // `sleep_time` (s): its bodies' velocities are zeroed, they leave in_contact and the awake list,
  // and their ids are appended to fell_asleep.
  struct Step {
    double dt = 0, speed = 0, sleep_time = 0;  ///< s, m/s, s
    const BodyModel* model = nullptr;
    MotionState* state = nullptr;
    char* in_contact = nullptr;
    const std::vector<Contact>* contacts = nullptr;  ///< the step's (resting pairs are not needed)
    const BodyExtents* extents = nullptr;
    const std::vector<char>* shape_moving = nullptr;
    // Bodies that sleep and wake together whether or not they touch (a mechanism's), as pairs.
    const std::vector<std::pair<int, int>>* bonds = nullptr;
  };
  void step(const Step& in, std::vector<int>& fell_asleep);

  // Saved state: each body's still time and island (each checked by the reader: may_sleep).
  // restore() rebuilds the awake list, the islands' lists (InputError naming a body when they are
  // inconsistent) and the sleeping bodies' frozen shapes.
  void restore(std::vector<double> still, std::vector<int> asleep, const std::vector<BodyModel>& model,
               const std::vector<std::string>& names, const BodyExtents& extents,
               const std::vector<char>& shape_moving);

 private:
  bool enabled_ = false;
  std::vector<char> may_sleep_;     ///< per body: dynamic and under no continuous force
  std::vector<double> still_time_;  ///< per body: s slow and touching (saved state)
  std::vector<int> asleep_;         ///< per body: -1 awake, else its island's id (saved state)
  std::vector<int> island_next_;    ///< per sleeping body: next body of its island, or -1
  std::vector<int> island_tail_;    ///< per island id: its list's last body (scratch)
  std::vector<int> awake_;          ///< dynamic and kinematic bodies awake (ascending when sorted)
  bool awake_sorted_ = true;        ///< false after a wake appended to awake_
  std::vector<int> pending_freeze_;
  int sleeping_ = 0;
  std::vector<int> uf_;             ///< union-find parents (scratch)
  std::vector<double> island_min_;  ///< per island root: least still_time_ (scratch)
};

}  // namespace simreel
