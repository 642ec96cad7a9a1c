#include "render/camera.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace simreel {

using M4 = Eigen::Matrix4f;
using V3f = Eigen::Vector3f;

M4 look_at(const V3f& eye, const V3f& target, const V3f& up) {
  const V3f f = (target - eye).normalized(), s = f.cross(up).normalized(), u = s.cross(f);
  M4 m = M4::Identity();
  m.row(0) << s.transpose(), -s.dot(eye);
  m.row(1) << u.transpose(), -u.dot(eye);
  m.row(2) << -f.transpose(), f.dot(eye);
  return m;
}

M4 perspective(float fovy_rad, float aspect, float n, float f) {
  const float t = 1.0f / std::tan(fovy_rad / 2);
  M4 m = M4::Zero();
  m(0, 0) = t / aspect;
  m(1, 1) = t;
  m(2, 2) = (f + n) / (n - f);
  m(2, 3) = 2 * f * n / (n - f);
  m(3, 2) = -1;
  return m;
}

M4 ortho(float r, float n, float f) {
  M4 m = M4::Identity();
  m(0, 0) = 1 / r;
  m(1, 1) = 1 / r;
  m(2, 2) = -2 / (f - n);
  m(2, 3) = -(f + n) / (f - n);
  return m;
}

Eigen::Vector2d project_to_pixel(const CameraView& cam, int width, int height, const Vec3& p, double* depth) {
  const Eigen::Matrix4d view =
      look_at(cam.eye.cast<float>(), cam.target.cast<float>(), cam.up.cast<float>()).cast<double>();
  const Eigen::Vector4d v = view * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
  const double t = 1.0 / std::tan(cam.fov_deg * M_PI / 360.0), aspect = (double)width / height;
  const double d = -v.z();
  if (depth) *depth = d;
  const double nx = v.x() * t / aspect / d, ny = v.y() * t / d;  // normalised device coordinates
  return Eigen::Vector2d((nx + 1) * 0.5 * width, (1 - ny) * 0.5 * height);
}

double pixel_size_at(const CameraView& cam, int height, double d) {
  return 2 * d * std::tan(cam.fov_deg * M_PI / 360.0) / height;
}

}  // namespace simreel
