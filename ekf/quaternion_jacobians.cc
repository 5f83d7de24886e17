#include "ekf/quaternion_jacobians.h"

#include <cmath>

namespace slamcmp {

Vec4 quatVector(const Quat& q) { return Vec4(q.w(), q.x(), q.y(), q.z()); }

Quat quatFromVector(const Vec4& q) { return Quat(q(0), q(1), q(2), q(3)); }

Mat4 quatLeft(const Vec4& p) {
  Mat4 L;
  L << p(0), -p(1), -p(2), -p(3),
       p(1), p(0), -p(3), p(2),
       p(2), p(3), p(0), -p(1),
       p(3), -p(2), p(1), p(0);
  return L;
}

Mat4 quatRight(const Vec4& q) {
  Mat4 R;
  R << q(0), -q(1), -q(2), -q(3),
       q(1), q(0), q(3), -q(2),
       q(2), -q(3), q(0), q(1),
       q(3), q(2), -q(1), q(0);
  return R;
}

Vec4 quatMultiply(const Vec4& p, const Vec4& q) { return quatLeft(p) * q; }

Vec4 quatFromRotvecJ(const Vec3& theta, Mat43* J) {
  const double angle = theta.norm();
  Vec4 q;
  if (angle < 1e-8) {
    // Series: cos(a/2) = 1 - a^2/8, sin(a/2)/a = 1/2 - a^2/48; to first order the derivative is
    // (-theta^T / 4; I / 2).
    q << 1.0 - angle * angle / 8.0, theta * (0.5 - angle * angle / 48.0);
    if (J) {
      J->row(0) = -0.25 * theta.transpose();
      J->bottomRows<3>() = 0.5 * Mat3::Identity();
    }
    return q;
  }
  const double half = 0.5 * angle, s = std::sin(half), c = std::cos(half);
  const Vec3 axis = theta / angle;
  q << c, s * axis;
  if (J) {
    J->row(0) = -0.5 * s * axis.transpose();
    // d(s axis)/dtheta = (c/2) axis axis^T + (s / angle)(I - axis axis^T)
    J->bottomRows<3>() = 0.5 * c * axis * axis.transpose() +
                         (s / angle) * (Mat3::Identity() - axis * axis.transpose());
  }
  return q;
}

Vec4 normaliseQuat(const Vec4& q, Mat4* J) {
  const double norm = q.norm();
  const Vec4 n = q / norm;
  if (J) *J = (Mat4::Identity() - n * n.transpose()) / norm;
  return n;
}

Mat3 rotationFromQuat(const Vec4& q) {
  const double w = q(0);
  const Vec3 u = q.tail<3>();
  return (w * w - u.squaredNorm()) * Mat3::Identity() + 2.0 * u * u.transpose() + 2.0 * w * skew(u);
}

Vec3 rotateByQuat(const Vec4& q, const Vec3& v, Mat34* J_q) {
  const double w = q(0);
  const Vec3 u = q.tail<3>();
  if (J_q) {
    J_q->col(0) = 2.0 * w * v + 2.0 * u.cross(v);
    J_q->rightCols<3>() = -2.0 * v * u.transpose() + 2.0 * u.dot(v) * Mat3::Identity() +
                          2.0 * u * v.transpose() - 2.0 * w * skew(v);
  }
  return (w * w - u.squaredNorm()) * v + 2.0 * u * u.dot(v) + 2.0 * w * u.cross(v);
}

Vec3 rotateByQuatInverse(const Vec4& q, const Vec3& v, Mat34* J_q) {
  const double w = q(0);
  const Vec3 u = q.tail<3>();
  if (J_q) {
    J_q->col(0) = 2.0 * w * v - 2.0 * u.cross(v);
    J_q->rightCols<3>() = -2.0 * v * u.transpose() + 2.0 * u.dot(v) * Mat3::Identity() +
                          2.0 * u * v.transpose() + 2.0 * w * skew(v);
  }
  return (w * w - u.squaredNorm()) * v + 2.0 * u * u.dot(v) - 2.0 * w * u.cross(v);
}

}  // namespace slamcmp
