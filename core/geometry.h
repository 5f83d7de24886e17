#pragma once
// Rotations (rotation vector, matrix, unit quaternion; thesis eqs. 3.38 to 3.41) and rigid poses.
#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

namespace slamcmp {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using Mat23 = Eigen::Matrix<double, 2, 3>;
using Quat = Eigen::Quaterniond;

// [v]x with [v]x w = v x w.
Mat3 skew(const Vec3& v);

// d (x / z, y / z) / d p at p = (x, y, z), z > 0: the pinhole projection's Jacobian.
inline Mat23 pinholeJacobian(const Vec3& p) {
  const double iz = 1.0 / p.z();
  Mat23 J;
  J << iz, 0, -p.x() * iz * iz, 0, iz, -p.y() * iz * iz;
  return J;
}

// Rodrigues: R = I + sin(theta)/theta [r]x + (1 - cos(theta))/theta^2 [r]x^2, exact near theta = 0.
Mat3 rotationFromRotvec(const Vec3& rotvec);
// The inverse, stable at theta = 0 and near theta = pi; theta in [0, pi].
Vec3 rotvecFromRotation(const Mat3& R);
Quat quatFromRotvec(const Vec3& rotvec);
Vec3 rotvecFromQuat(const Quat& q);

// The largest standard deviation of a covariance: the square root of its largest eigenvalue (the
// longest semi-axis of its ellipsoid); 0 where rounding left that eigenvalue negative.
template <class Derived>
double largestStd(const Eigen::MatrixBase<Derived>& P) {
  using Plain = typename Derived::PlainObject;
  const Plain P_plain = P;
  return std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Plain>(P_plain, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff()));
}

// The rotation closest in Frobenius norm to M (U V^T of its SVD, det +1).
Mat3 nearestRotation(const Mat3& M);
// Angle of a rotation in radians, in [0, pi].
double rotationAngle(const Mat3& R);

// A rigid transform T_a_b: maps a point in frame b to frame a, p_a = R * p_b + t.
class SE3 {
 public:
  SE3() : R_(Mat3::Identity()), t_(Vec3::Zero()) {}
  SE3(const Mat3& R, const Vec3& t) : R_(R), t_(t) {}
  SE3(const Quat& q, const Vec3& t) : R_(q.normalized().toRotationMatrix()), t_(t) {}
  static SE3 fromRotvec(const Vec3& rotvec, const Vec3& t) { return SE3(rotationFromRotvec(rotvec), t); }

  const Mat3& R() const { return R_; }
  const Vec3& t() const { return t_; }
  Quat quat() const { return Quat(R_).normalized(); }
  Vec3 rotvec() const { return rotvecFromRotation(R_); }

  SE3 inverse() const { return SE3(R_.transpose(), -(R_.transpose() * t_)); }
  SE3 operator*(const SE3& o) const { return SE3(R_ * o.R_, R_ * o.t_ + t_); }
  Vec3 operator*(const Vec3& p) const { return R_ * p + t_; }
  Eigen::Matrix4d matrix() const;
  bool isFinite() const { return R_.allFinite() && t_.allFinite(); }

 private:
  Mat3 R_;
  Vec3 t_;
};

}  // namespace slamcmp
