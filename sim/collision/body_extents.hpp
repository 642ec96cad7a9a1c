// Per-body and per-shape sizes that several stages read, computed once from the shape table when
// the world is built (Box2D's b2BodySim extents): which shapes each body has, how far each shape
// reaches from its body's centre of mass (a point of it moves at most |v| + reach |w|), and how
// thin it is (continuous collision sweeps what moves more than half its width in a step).
#pragma once
#include <limits>
#include <vector>

#include "sim/collision/shape_table.hpp"

namespace simreel {

// m, how far a shape's broad-phase box reaches past it: the speculative distance plus the farthest
// any of its points can move in a step, (|v| + reach |w|) dt (v in m/s, w in rad/s, reach in m).
inline double box_margin(double speculative, double v, double reach, double w, double dt) {
  return speculative + (v + reach * w) * dt;
}

struct BodyExtents {
  // Builds the table for `bodies` bodies from the shape table (which lists shapes body by body).
  void build(const ShapeTable& shapes, int bodies);

  std::vector<int>
      shape_begin;  ///< per body and one past: body b's shapes are [shape_begin[b], shape_begin[b+1])
  std::vector<int> shape_body;  ///< per shape: its body (the shape table's, compact for the hot loops)
  std::vector<double>
      shape_reach;  ///< per shape: m, |p_PC| + bounding radius: its farthest point from the centre of mass
  /// per shape: m, its smallest width; infinite for what is never swept: planes, static meshes and
  /// shapes that touch nothing (group or mask 0)
  std::vector<double> shape_width;
  std::vector<double> reach;        ///< per body: m, the largest reach of its shapes
  std::vector<double> swept_reach;  ///< per body: m, the largest reach of its shapes of finite width
  std::vector<double> width;        ///< per body: m, the smallest width of its shapes (infinite: none)

  /// m, shape k's reach where it can be swept, 0 where it cannot (continuous collision's lever arm).
  double sweep_reach(int k) const { return shape_width[k] < kInfinity ? shape_reach[k] : 0.0; }

  static constexpr double kInfinity = std::numeric_limits<double>::infinity();
};

}  // namespace simreel
