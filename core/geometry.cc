#include "core/geometry.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace slamcmp {

Mat3 skew(const Vec3& v) {
  Mat3 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Mat3 rotationFromRotvec(const Vec3& rotvec) {
  const double theta2 = rotvec.squaredNorm();
  const Mat3 K = skew(rotvec);
  double a, b;  // sin(theta)/theta and (1 - cos(theta))/theta^2
  if (theta2 < 1e-12) {
    // Taylor series: the closed form divides 0 by 0 here.
    a = 1.0 - theta2 / 6.0;
    b = 0.5 - theta2 / 24.0;
  } else {
    const double theta = std::sqrt(theta2);
    a = std::sin(theta) / theta;
    b = (1.0 - std::cos(theta)) / theta2;
  }
  return Mat3::Identity() + a * K + b * K * K;
}

Vec3 rotvecFromRotation(const Mat3& R) {
  // Through the quaternion: atan2 of its vector and scalar parts is accurate over [0, pi],
  // where acos((trace - 1) / 2) loses all precision near 0 and pi.
  return rotvecFromQuat(Quat(R));
}

Quat quatFromRotvec(const Vec3& rotvec) {
  const double theta = rotvec.norm();
  const double half = 0.5 * theta;
  // sin(theta/2)/theta, by its series near 0.
  const double k = theta < 1e-8 ? 0.5 - theta * theta / 48.0 : std::sin(half) / theta;
  return Quat(std::cos(half), k * rotvec.x(), k * rotvec.y(), k * rotvec.z());
}

Vec3 rotvecFromQuat(const Quat& q_in) {
  Quat q = q_in.normalized();
  if (q.w() < 0) q.coeffs() = -q.coeffs();  // same rotation, angle in [0, pi]
  const Vec3 v = q.vec();
  const double s = v.norm();
  if (s < 1e-12) return 2.0 * v / q.w();  // first order; q.w() ~ 1 here
  const double theta = 2.0 * std::atan2(s, q.w());
  return v * (theta / s);
}

Mat3 nearestRotation(const Mat3& M) {
  Eigen::JacobiSVD<Mat3> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

double rotationAngle(const Mat3& R) { return rotvecFromRotation(R).norm(); }

Eigen::Matrix4d SE3::matrix() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = R_;
  m.topRightCorner<3, 1>() = t_;
  return m;
}

}  // namespace slamcmp
