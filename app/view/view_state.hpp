// What a view of a scene knows beyond the world's present state, saved so that a render split into
// chunks (`simreel plan --checkpoints`) can start a chunk mid-clip and draw the frames a straight
// render draws:
// - the whole-run pre-passes' products (arrow and contact scales, plot samples): PrepassStore,
//   recorded once by `plan` and replayed by each chunk instead of simulating the whole run again;
// - the history of steps before the chunk (trails, measured periods, a damped follow, the variants'
//   worlds): SceneFrames::save_history / restore_history (app/view/panes.hpp).
// Both are plain bytes in this machine's layout, read back by the same simreel build (a checkpoint's
// manifest names the version; another is refused before these are read).
#pragma once
#include <cstdint>
#include <istream>
#include <ostream>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <simreel/error.hpp>

namespace simreel {

template <class T>
void put(std::ostream& os, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  os.write(reinterpret_cast<const char*>(&v), sizeof v);
}
template <class T>
void get(std::istream& is, T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  is.read(reinterpret_cast<char*>(&v), sizeof v);
  if (!is) throw InputError("a checkpoint ends early: truncated, or written by another simreel build");
}
// Vectors of plain values (Eigen's fixed-size vectors included: their bytes are their values,
// though their user-written copy constructors keep them from being trivially copyable).
template <class T>
void put_vec(std::ostream& os, const std::vector<T>& v) {
  put(os, (uint64_t)v.size());
  os.write(reinterpret_cast<const char*>(v.data()), (std::streamsize)(v.size() * sizeof(T)));
}
template <class T>
void get_vec(std::istream& is, std::vector<T>& v) {
  uint64_t n = 0;
  get(is, n);
  if (n > (uint64_t)1 << 32)
    throw InputError("a checkpoint holds a list of " + std::to_string(n) + " entries");
  v.resize((size_t)n);
  is.read(reinterpret_cast<char*>(v.data()), (std::streamsize)(n * sizeof(T)));
  if (!is) throw InputError("a checkpoint ends early: truncated, or written by another simreel build");
}
inline void put_str(std::ostream& os, const std::string& s) {
  put(os, (uint64_t)s.size());
  os.write(s.data(), (std::streamsize)s.size());
}
inline void get_str(std::istream& is, std::string& s) {
  uint64_t n = 0;
  get(is, n);
  if (n > (uint64_t)1 << 34)
    throw InputError("a checkpoint holds a block of " + std::to_string(n) + " bytes");
  s.resize((size_t)n);
  is.read(s.data(), (std::streamsize)n);
  if (!is) throw InputError("a checkpoint ends early: truncated, or written by another simreel build");
}

// The pre-passes' products of every view of a scene, one block per SceneOverlays in the order the
// views are built (deterministic: the scene's panes in order). Recording: each view runs its
// pre-pass and appends what it found; replaying: each takes its block and runs none.
class PrepassStore {
 public:
  enum class Mode { record, replay };
  explicit PrepassStore(Mode m) : mode_(m) {}
  Mode mode() const { return mode_; }
  void add(std::string block) { blocks_.push_back(std::move(block)); }
  std::istringstream next() {
    if (next_ >= blocks_.size()) throw InputError("a checkpoint has fewer views' pre-passes than the scene");
    return std::istringstream(blocks_[next_++]);
  }
  void save(std::ostream& os) const {
    put(os, (uint64_t)blocks_.size());
    for (const std::string& b : blocks_) put_str(os, b);
  }
  void load(std::istream& is) {
    uint64_t n = 0;
    get(is, n);
    if (n > 4096) throw InputError("a checkpoint holds " + std::to_string(n) + " views");
    blocks_.assign((size_t)n, {});
    for (std::string& b : blocks_) get_str(is, b);
    next_ = 0;
  }

 private:
  Mode mode_;
  std::vector<std::string> blocks_;
  size_t next_ = 0;
};

}  // namespace simreel
