// Camera math shared by the renderer and its tests: a point's pixel is computed here exactly as
// the GL passes place it (up to the rasteriser's own rounding).
#pragma once
#include <Eigen/Core>

#include <simreel/math.hpp>

namespace simreel {

struct CameraView {
  Vec3 eye = Vec3(8, -8, 5), target = Vec3::Zero(), up = Vec3::UnitZ();  ///< m
  double fov_deg = 40;                                                   ///< vertical
};

Eigen::Matrix4f look_at(const Eigen::Vector3f& eye, const Eigen::Vector3f& target, const Eigen::Vector3f& up);
Eigen::Matrix4f perspective(float fovy_rad, float aspect, float near, float far);
Eigen::Matrix4f ortho(float half_size, float near, float far);

// The pixel position (x right, y down, pixel centres at +0.5) of world point p on a width x height
// frame, and its distance in front of the camera (m, negative behind it).
Eigen::Vector2d project_to_pixel(const CameraView& cam, int width, int height, const Vec3& p,
                                 double* depth = nullptr);

// The size of one pixel (m) at distance d in front of the camera.
double pixel_size_at(const CameraView& cam, int height, double d);

}  // namespace simreel
