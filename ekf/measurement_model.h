#pragma once
// The measurement of a 3D point (SPEC section 5): h = project(R(q)^T (y - r)) through the full
// camera model (distortion included), with its Jacobians with respect to r, q and y.
#include <Eigen/Core>

#include "core/camera.h"
#include "ekf/quaternion_jacobians.h"

namespace slamcmp {

using Mat24 = Eigen::Matrix<double, 2, 4>;
// d h / d y: 2x3 for a 3D point, 2x6 for an inverse-depth feature (inverse_depth.h); no heap.
using FeatureJacobian = Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, 6>;

struct PointMeasurement {
  Vec2 uv_distorted;
  Vec3 p_camera;
  Mat23 H_r;  // d h / d r
  Mat24 H_q;  // d h / d q
  FeatureJacobian H_y;  // d h / d y (its columns: the feature's state size)
  // Seen at its row's time by a rolling shutter (rolling_shutter.h: predictAtRowTime), h depends on
  // the velocities too: H_v = d h / d v, H_w = d h / d w, set (and read) only when row_timed.
  bool row_timed = false;
  Mat23 H_v;
  Mat23 H_w;
};

// False when the point is closer than min_depth in front of the camera (no projection).
bool predictMeasurement(const CameraModel& camera, const Vec3& r, const Vec4& q, const Vec3& y_world,
                        PointMeasurement* out, double min_depth = 1e-3);

// The unit ray, in the world frame, through the distorted pixel uv seen from a camera with
// orientation q; J_q = d ray / d q, J_uv = d ray / d uv.
Vec3 rayFromPixel(const CameraModel& camera, const Vec4& q, const Vec2& uv_distorted,
                  Mat34* J_q = nullptr, Eigen::Matrix<double, 3, 2>* J_uv = nullptr);

}  // namespace slamcmp
