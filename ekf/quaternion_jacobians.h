#pragma once
// Quaternion algebra of the EKF state, stored as a 4-vector (w, x, y, z), with analytic Jacobians.
// The rotation matrix is the homogeneous quadratic form
//   R(q) = (w^2 - u.u) I + 2 u u^T + 2 w [u]x,   u = (x, y, z),
// a rotation for unit q; its derivatives are those of this polynomial (as in SceneLib).
#include <Eigen/Core>

#include "core/geometry.h"

namespace slamcmp {

using Vec4 = Eigen::Vector4d;
using Mat4 = Eigen::Matrix4d;
using Mat34 = Eigen::Matrix<double, 3, 4>;
using Mat43 = Eigen::Matrix<double, 4, 3>;

Vec4 quatVector(const Quat& q);  // (w, x, y, z)
Quat quatFromVector(const Vec4& q);

// p * q = quatLeft(p) q = quatRight(q) p.
Mat4 quatLeft(const Vec4& p);
Mat4 quatRight(const Vec4& q);
Vec4 quatMultiply(const Vec4& p, const Vec4& q);

// quat(theta): the rotation by the rotation vector theta; J = d quat / d theta (4x3).
Vec4 quatFromRotvecJ(const Vec3& theta, Mat43* J = nullptr);

// q / |q|; J = d(q / |q|)/dq = (I - n n^T) / |q|.
Vec4 normaliseQuat(const Vec4& q, Mat4* J = nullptr);

Mat3 rotationFromQuat(const Vec4& q);
// R(q) v and R(q)^T v with their derivatives with respect to q (3x4).
Vec3 rotateByQuat(const Vec4& q, const Vec3& v, Mat34* J_q = nullptr);
Vec3 rotateByQuatInverse(const Vec4& q, const Vec3& v, Mat34* J_q = nullptr);

}  // namespace slamcmp
