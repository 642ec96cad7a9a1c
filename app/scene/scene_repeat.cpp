// `repeat:` on a body or a joint (scenes/README.md, "repeat"): the entry stands for `count` copies,
// named NAME_1 .. NAME_count, each `step` further than the one before. The copies are made in the
// YAML tree before the scene is read, as clones of the template that keep its lines and columns, so
// an error in any copy points at the template's text.
#include "app/scene/scene_repeat.hpp"

#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "app/scene/scene_yaml.hpp"

namespace simreel {

using scene_yaml::Ctx;

namespace {

constexpr long kMaxCopies = 10000;

struct Repeat {
  long count = 0;
  Vec3 step = Vec3::Zero();
};

Repeat read_repeat(const YAML::Node& r, const Ctx& c) {
  if (!r.IsMap()) c.fail(r, "expected { count: N, step: [dx, dy, dz] }, got " + scene_yaml::show(r));
  scene_yaml::check_keys(r, c, {"count", "step"});
  Repeat out;
  if (!r["count"]) c.fail(r, "missing key 'count' (how many copies)");
  const double n = scene_yaml::number(r["count"], c.child("count"));
  if (n != std::floor(n) || n < 1 || n > kMaxCopies)
    c.child("count").fail(r["count"], "expected a whole number of copies from 1 to " +
                                          std::to_string(kMaxCopies) + ", got " +
                                          scene_yaml::show(r["count"]));
  out.count = (long)n;
  if (r["step"]) out.step = scene_yaml::vec<3>(r["step"], c.child("step"));
  return out;
}

// A plain scalar, as the parser makes one from unquoted text (tag "?": the readers refuse other tags).
YAML::Node plain(const std::string& text) {
  YAML::Node n(text);
  n.SetTag("?");
  return n;
}

YAML::Node point(const Vec3& p) {
  YAML::Node n(YAML::NodeType::Sequence);
  char buf[40];
  for (int k = 0; k < 3; ++k) {
    std::snprintf(buf, sizeof buf, "%.17g", p[k]);  // round-trips: the copy is the template moved exactly
    n.push_back(plain(buf));
  }
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

// The template's point `key` (or, `list`, each of its points) moved by d, into the copy.
void shift(const YAML::Node& from, YAML::Node& m, const char* key, const Vec3& d, const Ctx& c, bool list) {
  const YAML::Node v = from[key];
  if (!v) return;
  if (!list) {
    m[key] = point(scene_yaml::vec<3>(v, c.child(key)) + d);
    return;
  }
  if (!v.IsSequence()) {  // the joint's own reader refuses it with its message
    m[key] = v;
    return;
  }
  YAML::Node out(YAML::NodeType::Sequence);
  for (size_t k = 0; k < v.size(); ++k)
    out.push_back(point(scene_yaml::vec<3>(v[k], c.child(key).index(k)) + d));
  out.SetStyle(YAML::EmitterStyle::Flow);
  m[key] = out;
}

// A copy of map `m` without the keys `skip`: its other values are the template's own nodes (shared,
// read only), so they keep their lines and columns for error messages. (YAML::Clone would make new
// nodes at line 1, column 1.)
YAML::Node shallow_copy(const YAML::Node& m, std::initializer_list<const char*> skip) {
  YAML::Node out(YAML::NodeType::Map);
  for (auto it = m.begin(); it != m.end(); ++it) {
    const std::string key = it->first.IsScalar() ? it->first.Scalar() : std::string();
    bool skipped = false;
    for (const char* k : skip) skipped = skipped || key == k;
    if (!skipped) out.force_insert(it->first, it->second);
  }
  return out;
}

std::string copy_name(const std::string& name, long k) {
  return name + "_" + std::to_string(k + 1);
}

// Each entry of root[key] with `repeat:` replaced by what copies(entry, ctx, repeat, out) appends;
// the list left as it is when no entry repeats.
template <class F>
void expand_list(YAML::Node& root, const char* key, const Ctx& top, F&& copies) {
  const YAML::Node list = root[key];
  if (!list || !list.IsSequence()) return;
  bool any = false;
  for (size_t i = 0; i < list.size() && !any; ++i) any = list[i].IsMap() && list[i]["repeat"];
  if (!any) return;
  YAML::Node out(YAML::NodeType::Sequence);
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node e = list[i];
    if (!e.IsMap() || !e["repeat"]) {
      out.push_back(e);
      continue;
    }
    const Ctx c = top.child(key).index(i);
    copies(e, c, read_repeat(e["repeat"], c.child("repeat")), out);
  }
  root[key] = out;
}

}  // namespace

void expand_repeats(YAML::Node& root, const std::string& path) {
  if (!root.IsMap()) return;
  const Ctx top(path, "");
  std::map<std::string, long> repeated;  // a body template's name -> its count
  long copies = 0;                       // bodies made, bounded as a scene's bodies are
  expand_list(root, "bodies", top, [&](const YAML::Node& b, const Ctx& c, const Repeat& r, YAML::Node& out) {
    copies += r.count;
    if (copies > kMaxCopies * 10)
      c.child("repeat").fail(b["repeat"], "the repeats make more than " + std::to_string(kMaxCopies * 10) +
                                              " bodies: a scene holds at most 100000");
    if (!b["name"]) c.fail(b, "a repeated body needs a 'name': its copies are NAME_1 .. NAME_N");
    const std::string name = scene_yaml::text(b["name"], c.child("name"));
    const Vec3 p0 = b["position"] ? scene_yaml::vec<3>(b["position"], c.child("position")) : Vec3::Zero();
    repeated[name] = r.count;
    for (long k = 0; k < r.count; ++k) {
      YAML::Node copy = shallow_copy(b, {"repeat", "name", "position"});
      copy["name"] = plain(copy_name(name, k));
      copy["position"] = point(p0 + (double)k * r.step);
      out.push_back(copy);
    }
  });
  expand_list(root, "joints", top, [&](const YAML::Node& j, const Ctx& c, const Repeat& r, YAML::Node& out) {
    const std::string name = j["name"] ? scene_yaml::text(j["name"], c.child("name")) : "joint";
    // The bodies it ties: a repeated body's name stands for its k-th copy.
    const YAML::Node bs = j["bodies"];
    std::vector<std::string> ends;
    bool follows = false;
    if (bs && bs.IsSequence())
      for (size_t e = 0; e < bs.size(); ++e) {
        ends.push_back(bs[e].IsScalar() ? bs[e].Scalar() : std::string());
        const auto it = repeated.find(ends.back());
        if (it == repeated.end()) continue;
        follows = true;
        if (it->second != r.count)
          c.child("repeat").child("count").fail(
              j["repeat"]["count"], "body '" + ends.back() + "' is repeated " + std::to_string(it->second) +
                                        " times: a joint repeated with it needs the same count, got " +
                                        std::to_string(r.count));
      }
    if (!follows)
      c.child("repeat").fail(j["repeat"],
                             "a repeated joint ties a repeated body (one with `repeat:`), "
                             "whose k-th copy each copy of the joint takes; neither of its "
                             "bodies is");
    for (long k = 0; k < r.count; ++k) {
      YAML::Node copy = shallow_copy(j, {"repeat", "name", "bodies", "anchor", "anchors", "pulley_anchors"});
      copy["name"] = plain(copy_name(name, k));
      YAML::Node nb(YAML::NodeType::Sequence);
      for (const std::string& e : ends) nb.push_back(plain(repeated.count(e) ? copy_name(e, k) : e));
      nb.SetStyle(YAML::EmitterStyle::Flow);
      copy["bodies"] = nb;
      const Vec3 d = (double)k * r.step;
      shift(j, copy, "anchor", d, c, false);
      shift(j, copy, "anchors", d, c, true);
      shift(j, copy, "pulley_anchors", d, c, true);
      out.push_back(copy);
    }
  });
}

}  // namespace simreel
