#include "ekf/quaternion_jacobians.h"

#include <gtest/gtest.h>

#include "tests/test_util.h"

namespace slamcmp {
namespace {

using test::expectJacobianMatchesNumeric;

TEST(QuaternionJacobians, ProductMatricesAgreeWithEigen) {
  const Vec4 p = quatVector(quatFromRotvec(Vec3(0.3, -0.2, 0.9)));
  const Vec4 q = quatVector(quatFromRotvec(Vec3(-1.1, 0.4, 0.2)));
  const Vec4 expected = quatVector(quatFromVector(p) * quatFromVector(q));
  EXPECT_LT((quatLeft(p) * q - expected).norm(), 1e-14);
  EXPECT_LT((quatRight(q) * p - expected).norm(), 1e-14);
}

TEST(QuaternionJacobians, RotationMatchesEigenForUnitQuaternions) {
  const Quat q = quatFromRotvec(Vec3(0.7, -0.5, 1.3));
  EXPECT_LT((rotationFromQuat(quatVector(q)) - q.toRotationMatrix()).norm(), 1e-14);
  const Vec3 v(0.3, -2.0, 1.5);
  EXPECT_LT((rotateByQuat(quatVector(q), v) - q * v).norm(), 1e-14);
  EXPECT_LT((rotateByQuatInverse(quatVector(q), v) - q.conjugate() * v).norm(), 1e-14);
}

TEST(QuaternionJacobians, QuatFromRotvec) {
  for (const Vec3& theta : {Vec3(0.3, -0.4, 0.8), Vec3(1e-10, -2e-10, 0.0), Vec3(2.5, 0.1, -0.3)}) {
    Mat43 J;
    const Vec4 q = quatFromRotvecJ(theta, &J);
    EXPECT_LT((q - quatVector(quatFromRotvec(theta))).norm(), 1e-14);
    expectJacobianMatchesNumeric([](const Eigen::VectorXd& x) -> Eigen::VectorXd { return quatFromRotvecJ(x); },
                                 theta, J, 1e-7);
  }
}

TEST(QuaternionJacobians, Normalisation) {
  const Vec4 q(0.9, -0.3, 0.5, 0.2);  // not unit
  Mat4 J;
  normaliseQuat(q, &J);
  expectJacobianMatchesNumeric([](const Eigen::VectorXd& x) -> Eigen::VectorXd { return normaliseQuat(x); }, q, J);
}

TEST(QuaternionJacobians, RotateAndInverseRotate) {
  const Vec4 q(0.8, 0.3, -0.45, 0.25);  // not unit: the polynomial's own derivatives
  const Vec3 v(0.4, -1.2, 2.1);
  Mat34 J;
  rotateByQuat(q, v, &J);
  expectJacobianMatchesNumeric([&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return rotateByQuat(x, v); }, q, J);
  rotateByQuatInverse(q, v, &J);
  expectJacobianMatchesNumeric(
      [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return rotateByQuatInverse(x, v); }, q, J);
}

}  // namespace
}  // namespace slamcmp
