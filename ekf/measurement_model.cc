#include "ekf/measurement_model.h"

#include <Eigen/LU>

namespace slamcmp {

bool predictMeasurement(const CameraModel& camera, const Vec3& r, const Vec4& q, const Vec3& y_world,
                        PointMeasurement* out, double min_depth) {
  Mat34 J_q;
  out->p_camera = rotateByQuatInverse(q, y_world - r, &J_q);
  if (!(out->p_camera.z() > min_depth)) return false;
  Mat23 J_p;
  out->uv_distorted = camera.project(out->p_camera, &J_p);
  // p_camera = R(q)^T (y - r): d/dy = R^T, d/dr = -R^T.
  const Mat23 H_y = J_p * rotationFromQuat(q).transpose();
  out->H_y = H_y;
  out->H_r = -H_y;
  out->H_q = J_p * J_q;
  out->row_timed = false;
  return true;
}

Vec3 rayFromPixel(const CameraModel& camera, const Vec4& q, const Vec2& uv_distorted, Mat34* J_q,
                  Eigen::Matrix<double, 3, 2>* J_uv) {
  const Vec2 xy = camera.undistortPixel(uv_distorted);
  const Vec3 m(xy.x(), xy.y(), 1.0);
  const double norm = m.norm();
  const Vec3 m_unit = m / norm;
  const Vec3 ray = rotateByQuat(q, m_unit, J_q);
  if (J_uv) {
    // d xy / d uv inverts d uv / d xy = K_2x2 * d distort / d xy at the undistorted point.
    Mat2 J_d;
    camera.distort(xy, &J_d);
    Mat2 J_k;
    J_k << camera.fx, camera.skew, 0, camera.fy;
    const Mat2 dxy_duv = (J_k * J_d).inverse();
    const Mat3 dunit_dm = (Mat3::Identity() - m_unit * m_unit.transpose()) / norm;
    *J_uv = rotationFromQuat(q) * dunit_dm.leftCols<2>() * dxy_duv;
  }
  return ray;
}

}  // namespace slamcmp
