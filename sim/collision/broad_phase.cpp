// The dynamic bounding-volume tree of the broad phase (sim/collision/broad_phase.hpp). The algorithm is
// Box2D's b2DynamicTree (Catto; v2.4 insertion cost and AVL balance), written here for 3D boxes
// with the surface area as the cost.
#include "sim/collision/broad_phase.hpp"

#include <cmath>

namespace simreel {

namespace {

Aabb merge(const Aabb& a, const Aabb& b) {
  return Aabb{a.lo.cwiseMin(b.lo), a.hi.cwiseMax(b.hi)};
}

// Half the surface area: the expected cost of visiting a node is proportional to it.
double area(const Aabb& b) {
  const Vec3 d = b.hi - b.lo;
  return d.x() * d.y() + d.y() * d.z() + d.z() * d.x();
}

bool encloses(const Aabb& outer, const Aabb& inner) {
  return contains(outer, inner);
}

}  // namespace

int AabbTree::allocate() {
  if (free_ < 0) {
    nodes_.emplace_back();
    return (int)nodes_.size() - 1;
  }
  const int i = free_;
  free_ = nodes_[i].user;
  nodes_[i] = Node{};
  return i;
}

void AabbTree::release(int node) {
  nodes_[node] = Node{};
  nodes_[node].height = -1;
  nodes_[node].user = free_;
  free_ = node;
}

void AabbTree::clear() {
  nodes_.clear();
  root_ = free_ = -1;
  leaves_ = 0;
}

int AabbTree::insert(const Aabb& box, int user) {
  const int leaf = allocate();
  nodes_[leaf].box = box;
  nodes_[leaf].user = user;
  insert_leaf(leaf);
  ++leaves_;
  return leaf;
}

void AabbTree::remove(int leaf) {
  remove_leaf(leaf);
  release(leaf);
  --leaves_;
}

void AabbTree::move(int leaf, const Aabb& box) {
  remove_leaf(leaf);
  nodes_[leaf].box = box;
  insert_leaf(leaf);
}

// Descends from the root toward the sibling whose union with the leaf costs least (the new
// parent's area plus the growth inherited by every ancestor), then puts a new parent above it.
void AabbTree::insert_leaf(int leaf) {
  if (root_ < 0) {
    root_ = leaf;
    nodes_[leaf].parent = -1;
    return;
  }
  const Aabb box = nodes_[leaf].box;
  int index = root_;
  while (nodes_[index].child1 >= 0) {
    const Node& n = nodes_[index];
    const double a = area(n.box);
    const double combined = area(merge(n.box, box));
    const double cost = 2.0 * combined;               // a new parent of this node and the leaf
    const double inheritance = 2.0 * (combined - a);  // growth every ancestor below would pay
    auto descend_cost = [&](int c) {
      const Aabb u = merge(box, nodes_[c].box);
      return nodes_[c].child1 < 0 ? area(u) + inheritance : area(u) - area(nodes_[c].box) + inheritance;
    };
    const double cost1 = descend_cost(n.child1), cost2 = descend_cost(n.child2);
    if (cost < cost1 && cost < cost2) break;
    index = cost1 <= cost2 ? n.child1 : n.child2;
  }
  const int sibling = index;
  const int old_parent = nodes_[sibling].parent;
  const int parent = allocate();
  Node& p = nodes_[parent];
  p.parent = old_parent;
  p.box = merge(box, nodes_[sibling].box);
  p.height = nodes_[sibling].height + 1;
  p.child1 = sibling;
  p.child2 = leaf;
  nodes_[sibling].parent = parent;
  nodes_[leaf].parent = parent;
  if (old_parent >= 0) {
    if (nodes_[old_parent].child1 == sibling)
      nodes_[old_parent].child1 = parent;
    else
      nodes_[old_parent].child2 = parent;
  } else {
    root_ = parent;
  }
  refit(nodes_[leaf].parent);
}

void AabbTree::remove_leaf(int leaf) {
  if (leaf == root_) {
    root_ = -1;
    return;
  }
  const int parent = nodes_[leaf].parent;
  const int grand = nodes_[parent].parent;
  const int sibling = nodes_[parent].child1 == leaf ? nodes_[parent].child2 : nodes_[parent].child1;
  if (grand >= 0) {
    if (nodes_[grand].child1 == parent)
      nodes_[grand].child1 = sibling;
    else
      nodes_[grand].child2 = sibling;
    nodes_[sibling].parent = grand;
    release(parent);
    refit(grand);
  } else {
    root_ = sibling;
    nodes_[sibling].parent = -1;
    release(parent);
  }
  nodes_[leaf].parent = -1;
}

void AabbTree::refit(int index) {
  while (index >= 0) {
    index = balance(index);
    Node& n = nodes_[index];
    const Node& c1 = nodes_[n.child1];
    const Node& c2 = nodes_[n.child2];
    n.height = 1 + std::max(c1.height, c2.height);
    n.box = merge(c1.box, c2.box);
    index = n.parent;
  }
}

// AVL rotation at A if its subtrees' heights differ by more than one: the taller child C takes
// A's place, and A takes C's shorter child. Returns the node now at A's place.
int AabbTree::balance(int iA) {
  Node& A = nodes_[iA];
  if (A.child1 < 0 || A.height < 2) return iA;
  const int iB = A.child1, iC = A.child2;
  const int diff = nodes_[iC].height - nodes_[iB].height;
  if (diff > 1 || diff < -1) {
    // Rotate the taller child up (iUp), its own taller child (iF) stays under it, the shorter
    // (iG) goes to A.
    const int iUp = diff > 1 ? iC : iB;
    const int iKeep = diff > 1 ? iB : iC;  // A's other child, stays under A
    Node& U = nodes_[iUp];
    const int iF = U.child1, iG = U.child2;
    U.child1 = iA;
    U.parent = A.parent;
    A.parent = iUp;
    if (U.parent >= 0) {
      if (nodes_[U.parent].child1 == iA)
        nodes_[U.parent].child1 = iUp;
      else
        nodes_[U.parent].child2 = iUp;
    } else {
      root_ = iUp;
    }
    const bool f_taller = nodes_[iF].height > nodes_[iG].height;
    const int iTall = f_taller ? iF : iG, iShort = f_taller ? iG : iF;
    U.child2 = iTall;
    if (diff > 1)
      A.child2 = iShort;
    else
      A.child1 = iShort;
    nodes_[iShort].parent = iA;
    A.box = merge(nodes_[iKeep].box, nodes_[iShort].box);
    A.height = 1 + std::max(nodes_[iKeep].height, nodes_[iShort].height);
    U.box = merge(A.box, nodes_[iTall].box);
    U.height = 1 + std::max(A.height, nodes_[iTall].height);
    return iUp;
  }
  return iA;
}

bool AabbTree::valid(int index, int parent) const {
  const Node& n = nodes_[index];
  if (n.parent != parent) return false;
  if (n.child1 < 0) return n.child2 < 0 && n.height == 0;
  const Node& c1 = nodes_[n.child1];
  const Node& c2 = nodes_[n.child2];
  if (n.height != 1 + std::max(c1.height, c2.height)) return false;
  if (std::abs(c1.height - c2.height) > 1) return false;
  if (!encloses(n.box, c1.box) || !encloses(n.box, c2.box)) return false;
  return valid(n.child1, index) && valid(n.child2, index);
}

bool AabbTree::valid() const {
  if (root_ < 0) return leaves_ == 0;
  int count = 0;
  for (const Node& n : nodes_) count += n.height == 0;
  return count == leaves_ && valid(root_, -1);
}

}  // namespace simreel
