#include "render/overlay.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace simreel {

void orthonormal_basis(const Vec3& d, Vec3& e1, Vec3& e2) {
  const Vec3 a = std::fabs(d.x()) < 0.6   ? Vec3::UnitX()
                 : std::fabs(d.y()) < 0.6 ? Vec3::UnitY()
                                          : Vec3::UnitZ();
  e1 = d.cross(a).normalized();
  e2 = d.cross(e1);
}

namespace {

// The unit cylinder or cone (radius 1 along +z, 0 to 1) from `from` along `axis`, radius r.
Eigen::Matrix4f along(const Vec3& from, const Vec3& axis, double r) {
  const double len = axis.norm();
  const Vec3 d = axis / len;
  Vec3 e1, e2;
  orthonormal_basis(d, e1, e2);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<3, 1>(0, 0) = e1 * r;
  m.block<3, 1>(0, 1) = e2 * r;
  m.block<3, 1>(0, 2) = axis;
  m.block<3, 1>(0, 3) = from;
  return m.cast<float>();
}

}  // namespace

void OverlayList::arrow(const Vec3& from, const Vec3& vec, double radius, const Rgba& color, float xray) {
  const double len = vec.norm();
  if (!(len > 0.1 * radius) || !std::isfinite(len)) return;
  const double head = std::min(6 * radius, 0.4 * len);
  const Vec3 d = vec / len;
  const Vec3 base = from + d * (len - head);
  instances[(int)OverlayShape::cylinder].push_back({along(from, base - from, radius), color, xray});
  instances[(int)OverlayShape::cone].push_back({along(base, from + vec - base, 2.5 * radius), color, xray});
}

void OverlayList::cone(const Vec3& apex, const Vec3& axis, double radius, const Rgba& color, float xray) {
  const double h = axis.norm();
  if (!(h > 0) || !std::isfinite(h) || !(radius >= 0)) return;
  Vec3 e1, e2;
  orthonormal_basis(axis / h, e1, e2);
  // The unit cone's base (z = 0) at apex + axis and its tip (z = 1) at the apex: columns e2, e1,
  // -axis keep the determinant positive (the winding, and with it back-face culling, unchanged).
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<3, 1>(0, 0) = e2 * radius;
  m.block<3, 1>(0, 1) = e1 * radius;
  m.block<3, 1>(0, 2) = -axis;
  m.block<3, 1>(0, 3) = apex + axis;
  instances[(int)OverlayShape::cone].push_back({m.cast<float>(), color, xray});
}

void OverlayList::rod(const Vec3& a, const Vec3& b, double radius, const Rgba& color, float xray) {
  const Vec3 ab = b - a;
  if (!(ab.norm() > 0) || !std::isfinite(ab.norm())) return;
  instances[(int)OverlayShape::cylinder].push_back({along(a, ab, radius), color, xray});
}

void OverlayList::ellipsoid(const Vec3& center, const Mat3& axes, const Vec3& semi_axes, const Rgba& color,
                            float xray) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<3, 3>(0, 0) = axes * semi_axes.asDiagonal();
  m.block<3, 1>(0, 3) = center;
  instances[(int)OverlayShape::sphere].push_back({m.cast<float>(), color, xray});
}

void OverlayList::quad(const Vec3& c, const Vec3& u, const Vec3& v, const Rgba& color) {
  const Vec3 p[4] = {c - u - v, c + u - v, c + u + v, c - u + v};
  for (int k : {0, 1, 2, 0, 2, 3}) {
    OverlayVertex x;
    for (int i = 0; i < 3; ++i) x.pos[i] = (float)p[k][i];
    for (int i = 0; i < 4; ++i) x.rgba[i] = color[i];
    ribbons.push_back(x);
  }
}

void OverlayList::ribbon(const Vec3* p, const Rgba* colors, int n, const Vec3& eye, double width) {
  if (n < 2) return;
  Vec3 prev_side = Vec3::Zero();
  auto side = [&](int i) {
    const Vec3 t = p[std::min(i + 1, n - 1)] - p[std::max(i - 1, 0)];
    Vec3 s = t.cross(eye - p[i]);
    const double sn = s.norm();
    if (sn > 1e-12) prev_side = s * (0.5 * width / sn);
    return prev_side;
  };
  auto vertex = [&](const Vec3& q, const Rgba& c) {
    OverlayVertex v;
    for (int k = 0; k < 3; ++k) v.pos[k] = (float)q[k];
    for (int k = 0; k < 4; ++k) v.rgba[k] = c[k];
    ribbons.push_back(v);
  };
  Vec3 s0 = side(0);
  for (int i = 0; i + 1 < n; ++i) {
    const Vec3 s1 = side(i + 1);
    const Vec3 a0 = p[i] - s0, a1 = p[i] + s0, b0 = p[i + 1] - s1, b1 = p[i + 1] + s1;
    vertex(a0, colors[i]), vertex(a1, colors[i]), vertex(b1, colors[i + 1]);
    vertex(a0, colors[i]), vertex(b1, colors[i + 1]), vertex(b0, colors[i + 1]);
    s0 = s1;
  }
}

}  // namespace simreel
