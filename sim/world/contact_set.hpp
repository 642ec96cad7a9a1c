// The contact set as a subsystem (Box2D v3's contact array, Rapier's NarrowPhase): the broad
// phase's candidate pairs, the narrow phase on them (the `collide` stage), and the records kept
// from step to step (their manifolds, caches and impulses: the warm start and part of the saved
// state). Owns the candidate pairs, the records that may act this step and those of resting
// pairs, the per-pair jobs and per-thread maxima of the narrow phase (scratch), which bodies are
// in contact this step, and the contact statistics. Reads the world through a Step record; wakes
// the islands of sleeping bodies that something awake comes within reach of.
//
// Files: contact_set.cpp (the stage and the convex pairs), mesh_pairs.cpp (pairs with a static
// triangle mesh), continuous.cpp (fast pairs: their manifolds taken ahead, fast_pair and
// collide_ahead).
#pragma once
#include <cstdint>
#include <vector>

#include <simreel/profile.hpp>

#include "sim/collision/body_extents.hpp"
#include "sim/collision/contact.hpp"
#include "sim/collision/shape_table.hpp"
#include "sim/dynamics/state.hpp"
#include "sim/world/continuous.hpp"
#include "sim/world/islands.hpp"

namespace simreel {

class WorkerPool;

class ContactSet {
 public:
  // No records, no body in contact, for `bodies` bodies.
  void init(int bodies) { in_contact_.assign(bodies, 0); }

  /// This step's candidate pairs with a shape of an awake body (pair_key of shapes a < b), in key
  /// order: the broad phase writes them here (BroadPhase::update); Step::dormant has the others.
  std::vector<uint64_t>& pairs() { return pairs_; }
  /// Nothing close and nothing was: the collide stage has no work (and no bodies are in contact).
  bool idle() const { return pairs_.empty() && contacts_.empty() && resting_.empty(); }

  // What the narrow phase reads of the world this step (arrays owned by World).
  struct Step {
    const ShapeTable* shapes = nullptr;
    const BodyExtents* extents = nullptr;
    const BodyModel* model = nullptr;          ///< per body
    const MotionState* state = nullptr;        ///< per body
    const ContinuousCollision* ccd = nullptr;  ///< fast pairs: whether on, which bodies are bullets
    const char* shape_moving = nullptr;        ///< per shape: its body is not static
    // Per shape: its world pose this step, made by the broad phase where pose_step[k] ==
    // broad_step (the moving shapes of live pairs); pose() makes any other from the state.
    const Pose* poses = nullptr;
    const long* pose_step = nullptr;
    long broad_step = 0;
    Pose pose(int k, const ShapeRecord& r) const {
      return pose_step[k] == broad_step ? poses[k] : ShapeTable::world_pose(r, state[r.body]);
    }
    const Aabb* boxes = nullptr;      ///< per shape: box this step (broad phase)
    double dt = 0;                    ///< s
    Vec3 gravity = Vec3::Zero();      ///< m/s^2
    double speculative_distance = 0;  ///< m
    double linear_slop = 0;           ///< m
    bool timing = false;              ///< time each pair's narrow phase (Profile::narrow_seconds)
    int threads = 1;
    WorkerPool* pool = nullptr;  ///< threads for the pairs (null: the calling thread alone)
    // The broad phase's dormant pairs (no shape of an awake body; BroadPhase::dormant_pairs), key
    // order, and whether that list changed this step. pairs() holds the others.
    const std::vector<uint64_t>* dormant = nullptr;
    bool dormant_changed = true;
  };
  // The collide stage (contact_set.cpp): every candidate pair collided, or its records kept, into
  // the new lists; the islands of sleeping bodies touched by something awake woken; the bodies in
  // contact found. Adds the step's contact points to profile.contact_points. (Inside the class the
  // narrow phase's collide() of two shapes is called as simreel::collide.)
  void collide(const Step& in, Islands& islands, Profile& profile);

  /// The records that may act this step (at least one side awake, or kinematic), by (shape a,
  /// shape b); a pair with a static triangle mesh may have several, consecutive.
  const std::vector<Contact>& active() const { return contacts_; }
  /// The same, for the solver to store its impulses in (the next step's warm start).
  std::vector<Contact>& active() { return contacts_; }
  /// The records of pairs whose two sides are asleep or static, by (shape a, shape b): kept as
  /// they were when the pair fell asleep, untouched until a side wakes (collide).
  const std::vector<Contact>& resting() const { return resting_; }
  size_t size() const { return contacts_.size() + resting_.size(); }  ///< records in both lists
  /// f(const Contact&) for the records of both lists, merged in key order (the one list the
  /// sequential pass keeps; what a saved state holds).
  template <class F>
  void for_each(F&& f) const {
    for (size_t i = 0, r = 0; i < contacts_.size() || r < resting_.size();)
      f(r == resting_.size() || (i < contacts_.size() && contacts_[i].key() < resting_[r].key())
            ? contacts_[i++]
            : resting_[r++]);
  }

  /// Dynamic and kinematic bodies in contact this step, ascending (the solver's bodies).
  const std::vector<int>& bodies() const { return contact_bodies_; }
  /// Per body: in contact this step. The solver clears a body that received no impulse after
  /// all, the sleep stage one that fell asleep; the free-flight integrators skip the others.
  char* in_contact() { return in_contact_.data(); }
  const char* in_contact() const { return in_contact_.data(); }

  const ContactStats& stats() const { return stats_; }
  void clear_stats() { stats_ = ContactStats{}; }

  // A saved state's records (one list, key order) and statistics; the resting records move to
  // their list again in the next collide.
  void restore(std::vector<Contact> contacts, const ContactStats& stats) {
    stats_ = stats;
    contacts_ = std::move(contacts);
    resting_.clear();
    resting_keys_.clear();
  }

 private:
  // One candidate pair of collide: its records go to contacts_next_[slot, slot + count).
  struct CollideJob {
    uint64_t key;        ///< the shape pair
    int body_a, body_b;  ///< the shapes' bodies
    int prev;            ///< its first record in last step's contacts_ (resting_ if stored), or -1
    int prev_count;      ///< its records there (a pair with a static triangle mesh may have several)
    int slot;            ///< its first slot in contacts_next_
    int cap;             ///< slots reserved: 1, or kMaxMeshManifolds for a pair with a mesh
    int count;           ///< records written
    int points;          ///< contact points in them (0 for records kept as they were)
    bool keep;           ///< both sides inert: last step's records are kept as they are
    bool stored;         ///< last step's records are in resting_ (kept there, no slots, while keep)
    bool mesh;           ///< one side is a static triangle mesh (mesh_pairs.cpp)
    double seconds;      ///< its narrow phase's wall time (with Step::timing; !keep: it ran)
  };
  // A pair's narrow phase into its slots (records, points, deepest overlap in m); reads only the
  // state, the shapes, this step's poses and boxes, and last step's contact list: pairs run in
  // parallel.
  double collide_job(const Step& in, CollideJob& job);
  // collide's three passes (contact_set.cpp).
  bool build_jobs(const Step& in, Islands& islands, const std::vector<uint64_t>& keys, bool live_only);
  void run_jobs(const Step& in);
  void finish(const Step& in, Islands& islands, Profile& profile);
  const Contact* prev_record(const CollideJob& job) const {
    return job.prev < 0 ? nullptr : job.stored ? &resting_[job.prev] : &contacts_[job.prev];
  }
  double collide_pair(const Step& in, const CollideJob& job, Contact& c) const;
  // A pair with a static triangle mesh: its manifolds into out[0, kMaxMeshManifolds), each
  // warm-started from last step's records of the pair; returns how many (mesh_pairs.cpp).
  int collide_mesh_pair(const Step& in, const CollideJob& job, Contact* out, int& points,
                        double& deepest) const;
  // A fresh record in c for shapes a < b: bodies, mixed friction and restitution, and the impulses
  // warm-started from `prev` (last step's record of the same manifold) when there is one.
  static void new_contact(const ShapeTable& shapes, Contact& c, int a, int b, const Contact* prev);
  // Fast pairs (continuous.cpp, mesh_pairs.cpp): their manifolds taken where they will touch.
  static bool fast_pair(const Step& in, int a, int b, double closing);
  static int collide_ahead(const Step& in, int a, int b, const Pose& xa, const Pose& xb, double speculative,
                           double closing, PairCache& cache, Manifold& m, Vec3 offset[4]);
  static int collide_mesh_ahead(const Step& in, int c, int m, double speculative, Manifold out[],
                                Vec3 offset[][4]);

  struct alignas(64) Deepest {  // one cache line per thread
    double value = 0;
  };

  std::vector<uint64_t> pairs_, all_keys_;  ///< live pairs; with the dormant ones (collide)
  int busy_ = 0;                            ///< pass 1: pairs collided or copied
  bool packed_ = true, resting_moves_ = false;
  std::vector<Contact> contacts_, contacts_next_;
  // Records of pairs between sleeping or static bodies (a kinematic body at rest excluded: it may
  // move without being woken), key order: no work per step while they sleep (collide).
  std::vector<Contact> resting_, resting_next_;
  std::vector<uint64_t> resting_keys_, resting_keys_next_;  ///< resting_[i].key(), compact for the merge
  std::vector<CollideJob> collide_jobs_;                    ///< this step's pairs, in key order (collide)
  std::vector<Deepest> collide_sums_;                       ///< per thread: deepest overlap (collide)
  std::vector<char> in_contact_;                            ///< per body, this step
  std::vector<int> contact_bodies_;  ///< dynamic and kinematic bodies in contact, ascending
  ContactStats stats_;
};

}  // namespace simreel
