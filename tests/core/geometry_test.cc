#include "core/geometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <random>

namespace slamcmp {
namespace {

Vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Vec3(n(rng), n(rng), n(rng)).normalized();
}

Mat3 cvRodrigues(const Vec3& r) {
  cv::Mat R;
  cv::Rodrigues(cv::Vec3d(r.x(), r.y(), r.z()), R);
  Mat3 out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out(i, j) = R.at<double>(i, j);
  return out;
}

// Near pi, r and -r are the same rotation.
double rotvecDistance(const Vec3& a, const Vec3& b) {
  const double d = (a - b).norm();
  return a.norm() > M_PI - 1e-3 ? std::min(d, (a + b).norm()) : d;
}

TEST(Geometry, SkewIsTheCrossProduct) {
  std::mt19937 rng(1);
  for (int k = 0; k < 20; ++k) {
    const Vec3 v = 3.0 * randomUnit(rng), w = 2.0 * randomUnit(rng);
    EXPECT_LT((skew(v) * w - v.cross(w)).norm(), 1e-15);
    EXPECT_LT((skew(v) + skew(v).transpose()).norm(), 1e-15);
  }
}

// Rodrigues against OpenCV over random axes, for angles in a band [lo, hi].
class RodriguesVsOpenCV : public ::testing::TestWithParam<std::pair<double, double>> {};

TEST_P(RodriguesVsOpenCV, MatchesCvRodrigues) {
  const auto [lo, hi] = GetParam();
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> angle(lo, hi);
  for (int k = 0; k < 300; ++k) {
    const Vec3 r = angle(rng) * randomUnit(rng);
    const Mat3 R = rotationFromRotvec(r);
    EXPECT_LT((R - cvRodrigues(r)).cwiseAbs().maxCoeff(), 1e-12) << "r = " << r.transpose();
    EXPECT_LT((R.transpose() * R - Mat3::Identity()).norm(), 1e-14);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-14);
  }
}

INSTANTIATE_TEST_SUITE_P(AngleBands, RodriguesVsOpenCV,
                         ::testing::Values(std::make_pair(0.0, 1e-7), std::make_pair(1e-7, 1e-3),
                                           std::make_pair(1e-3, 1.0), std::make_pair(1.0, 3.0),
                                           std::make_pair(3.0, M_PI)));

// rotvec <-> quaternion <-> matrix round trips at the edge cases of the conversions.
class RotationRoundTrip : public ::testing::TestWithParam<double> {};

TEST_P(RotationRoundTrip, RotvecQuatMatrix) {
  const double angle = GetParam();
  std::mt19937 rng(7);
  for (int k = 0; k < 50; ++k) {
    const Vec3 r = angle * randomUnit(rng);
    const Quat q = quatFromRotvec(r);
    EXPECT_NEAR(q.norm(), 1.0, 1e-15);
    // Through the quaternion the angle keeps full relative precision, even at 1e-9 rad.
    EXPECT_LE(rotvecDistance(rotvecFromQuat(q), r), 1e-14 * angle);
    // Quaternion and Rodrigues agree on the matrix.
    const Mat3 R = rotationFromRotvec(r);
    EXPECT_LT((q.toRotationMatrix() - R).cwiseAbs().maxCoeff(), 1e-14);
    // Through the matrix the absolute error stays at rounding level, also at and near pi.
    EXPECT_LT(rotvecDistance(rotvecFromRotation(R), r), 1e-9);
    EXPECT_NEAR(rotationAngle(R), angle, 1e-9);
    // SE3 stores the matrix; its quaternion and rotation vector are the same rotation.
    const SE3 T = SE3::fromRotvec(r, Vec3::Zero());
    EXPECT_LT(rotvecDistance(T.rotvec(), r), 1e-9);
    EXPECT_NEAR(std::abs(T.quat().dot(q)), 1.0, 1e-14);
  }
}

INSTANTIATE_TEST_SUITE_P(EdgeAngles, RotationRoundTrip,
                         ::testing::Values(0.0, 1e-9, 1e-5, 1.0, M_PI - 1e-6, M_PI - 1e-9, M_PI));

TEST(Geometry, RotvecOfTheIdentityIsExactlyZero) {
  EXPECT_EQ(rotvecFromRotation(Mat3::Identity()), Vec3::Zero());
  EXPECT_EQ(rotvecFromQuat(Quat::Identity()), Vec3::Zero());
  EXPECT_EQ(rotationFromRotvec(Vec3::Zero()), Mat3::Identity());
  // A negated quaternion is the same rotation; the angle comes back in [0, pi].
  const Vec3 r(0.3, -0.2, 0.1);
  Quat q = quatFromRotvec(r);
  q.coeffs() = -q.coeffs();
  EXPECT_LT((rotvecFromQuat(q) - r).norm(), 1e-15);
}

TEST(Geometry, NearestRotationOfAPerturbedRotation) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1e-3);
  for (int k = 0; k < 50; ++k) {
    const Mat3 R = rotationFromRotvec(2.5 * randomUnit(rng));
    Mat3 M = R;
    for (int i = 0; i < 9; ++i) M(i / 3, i % 3) += noise(rng);
    const Mat3 N = nearestRotation(M);
    EXPECT_LT((N.transpose() * N - Mat3::Identity()).norm(), 1e-13);
    EXPECT_NEAR(N.determinant(), 1.0, 1e-13);
    EXPECT_LT((N - R).norm(), (M - R).norm() + 1e-12);  // the projection removes noise
    // It is the closest rotation: no small turn of it comes nearer to M.
    for (int t = 0; t < 10; ++t) {
      const Mat3 other = N * rotationFromRotvec(1e-3 * randomUnit(rng));
      EXPECT_LE((M - N).norm(), (M - other).norm());
    }
    // A rotation is its own nearest rotation; a scaled one too.
    EXPECT_LT((nearestRotation(R) - R).norm(), 1e-14);
    EXPECT_LT((nearestRotation(3.0 * R) - R).norm(), 1e-14);
  }
  // A reflection is not returned: det stays +1.
  const Mat3 reflection = Eigen::Vector3d(1, 1, -1).asDiagonal();
  EXPECT_NEAR(nearestRotation(reflection).determinant(), 1.0, 1e-14);
}

TEST(Geometry, SE3ComposeAndInverse) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int k = 0; k < 50; ++k) {
    const SE3 A = SE3::fromRotvec(2.0 * randomUnit(rng), Vec3(u(rng), u(rng), u(rng)));
    const SE3 B = SE3::fromRotvec(3.0 * randomUnit(rng), Vec3(u(rng), u(rng), u(rng)));
    const Vec3 p(u(rng), u(rng), u(rng));
    EXPECT_LT(((A * B) * p - A * (B * p)).norm(), 1e-13);
    EXPECT_LT(((A * B).matrix() - A.matrix() * B.matrix()).norm(), 1e-13);
    EXPECT_LT((A.inverse().matrix() - A.matrix().inverse()).norm(), 1e-12);
    EXPECT_LT((A.inverse() * (A * p) - p).norm(), 1e-13);
    const SE3 I = A * A.inverse();
    EXPECT_LT((I.R() - Mat3::Identity()).norm(), 1e-14);
    EXPECT_LT(I.t().norm(), 1e-14);
    EXPECT_LT(((A * B).inverse().matrix() - (B.inverse() * A.inverse()).matrix()).norm(), 1e-13);
    // The quaternion constructor gives the same transform.
    const SE3 Aq(A.quat(), A.t());
    EXPECT_LT((Aq.matrix() - A.matrix()).norm(), 1e-14);
  }
  // p_a = R p_b + t, with t the origin of b in a.
  const SE3 T_world_camera(rotationFromRotvec(Vec3(0, 0, M_PI / 2)), Vec3(1, 2, 3));
  EXPECT_LT((T_world_camera * Vec3::Zero() - Vec3(1, 2, 3)).norm(), 1e-15);
  EXPECT_LT((T_world_camera * Vec3(1, 0, 0) - Vec3(1, 3, 3)).norm(), 1e-15);
}

}  // namespace
}  // namespace slamcmp
