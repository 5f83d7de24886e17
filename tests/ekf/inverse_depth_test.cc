// Inverse-depth features (Civera, Davison and Montiel 2008): the measurement, the new feature's
// covariance, the conversion to a point, each against numeric differences; the linearity index;
// the batch update with 6-value feature blocks against the dense textbook formulas.
#include "ekf/inverse_depth.h"

#include <cmath>
#include <limits>

#include <Eigen/LU>
#include <gtest/gtest.h>

#include "ekf/ekf_update.h"
#include "tests/ekf/plane_render.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

const Vec3 kR(0.1, -0.05, -0.9);
const Vec4 kQ = quatVector(quatFromRotvec(Vec3(0.15, -0.2, 0.1)));

Vec6 feature(double rho) {
  Vec6 y;
  y << 0.3, -0.2, -1.2, 0.2, -0.1, rho;  // first seen from (0.3, -0.2, -1.2)
  return y;
}

class InverseDepthMeasurement : public ::testing::TestWithParam<double> {};

TEST_P(InverseDepthMeasurement, JacobiansMatchNumericWithDistortion) {
  const CameraModel camera = test::testCamera();
  const Vec6 y = feature(GetParam());
  PointMeasurement m;
  ASSERT_TRUE(predictInverseDepthMeasurement(camera, kR, kQ, y, &m));
  ASSERT_EQ(m.H_y.cols(), 6);
  auto h = [&](const Vec3& r, const Vec4& q, const Vec6& y_) {
    PointMeasurement out;
    EXPECT_TRUE(predictInverseDepthMeasurement(camera, r, q, y_, &out));
    return Eigen::VectorXd(out.uv_distorted);
  };
  test::expectJacobianMatchesNumeric([&](const Eigen::VectorXd& x) { return h(x, kQ, y); }, kR, m.H_r, 1e-5);
  test::expectJacobianMatchesNumeric([&](const Eigen::VectorXd& x) { return h(kR, x, y); }, kQ, m.H_q, 1e-5);
  test::expectJacobianMatchesNumeric([&](const Eigen::VectorXd& x) { return h(kR, kQ, x); }, y, m.H_y, 1e-5);
  // For rho > 0 it is the projection of the point x0 + m / rho.
  if (GetParam() > 0) {
    const SE3 T_world_camera(quatFromVector(kQ), kR);
    EXPECT_LT((m.uv_distorted - camera.project(T_world_camera.inverse() * inverseDepthPoint(y))).norm(), 1e-9);
  }
}

// Near, far and at infinity (rho = 0: the point's direction alone).
INSTANTIATE_TEST_SUITE_P(Depths, InverseDepthMeasurement, ::testing::Values(2.0, 0.5, 0.05, 0.0));

TEST(InverseDepth, DirectionAndConversionJacobiansMatchNumeric) {
  Eigen::Matrix<double, 3, 2> J_m;
  const Vec3 m = inverseDepthDirection(0.4, -0.3, &J_m);
  EXPECT_NEAR(m.norm(), 1.0, 1e-12);
  test::expectJacobianMatchesNumeric(
      [](const Eigen::VectorXd& a) -> Eigen::VectorXd { return inverseDepthDirection(a(0), a(1)); }, Vec2(0.4, -0.3),
      J_m, 1e-7);
  const Vec6 y = feature(0.4);
  Eigen::Matrix<double, 3, 6> J;
  const Vec3 p = inverseDepthToPoint(y, &J);
  EXPECT_LT((p - inverseDepthPoint(y)).norm(), 1e-12);
  Eigen::Matrix<double, 3, 6> J_unused;
  test::expectJacobianMatchesNumeric(
      [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return inverseDepthToPoint(x, &J_unused); }, y, J, 1e-6);
}

// The new feature's block and cross covariances are J P J^T for y = g(r, q, uv, rho) with
// (uv, rho) independent of the state (pixel_sigma^2 I, rho_sigma^2), J by numeric differences.
TEST(InverseDepth, NewFeatureCovarianceFollowsFromTheCameraPixelAndPrior) {
  const CameraModel camera = test::testCamera();
  EkfState state;
  Eigen::Matrix<double, 13, 13> A = Eigen::Matrix<double, 13, 13>::Random() * 0.01;
  state.reset(SE3(quatFromVector(kQ), kR), A * A.transpose() + 1e-4 * Eigen::Matrix<double, 13, 13>::Identity());
  state.append(Vec3(0.2, 0.1, 0.5), Mat3::Identity() * 1e-3, Eigen::MatrixXd::Zero(3, 13));
  const Vec2 uv(100.5, 380.25);
  const double pixel_sigma = 1.5, rho0 = 0.5, rho_sigma = 0.4;
  const EkfState prior = state;
  const int offset = appendInverseDepthFeature(state, camera, uv, pixel_sigma, rho0, rho_sigma);
  ASSERT_EQ(offset, 16);
  ASSERT_EQ(state.size(), 22);
  // g(r, q, uv): the feature through its own definition, the pixel back-projected from the camera.
  auto g = [&](const Eigen::VectorXd& a) -> Eigen::VectorXd {  // a = (r, q, uv, rho)
    EkfState s;
    s.reset(SE3(quatFromVector(kQ), a.head<3>()), Eigen::Matrix<double, 13, 13>::Zero());
    s.x().segment<4>(EkfState::kQ) = a.segment<4>(3);
    const int o = appendInverseDepthFeature(s, camera, a.segment<2>(7), pixel_sigma, a(9), rho_sigma);
    return s.x().segment<6>(o);
  };
  Eigen::VectorXd a(10);
  a << kR, kQ, uv, rho0;
  const Eigen::MatrixXd J = test::numericJacobian(g, a, 1e-6);
  EXPECT_LT((g(a) - state.x().segment<6>(16)).norm(), 1e-12);
  Eigen::MatrixXd P_a = Eigen::MatrixXd::Zero(10, 10);
  P_a.topLeftCorner<7, 7>() = prior.P().topLeftCorner<7, 7>();
  P_a.block<2, 2>(7, 7) = Mat2::Identity() * pixel_sigma * pixel_sigma;
  P_a(9, 9) = rho_sigma * rho_sigma;
  EXPECT_LT((state.P().block<6, 6>(16, 16) - J * P_a * J.transpose()).norm(), 1e-8);
  // Cross covariances with the camera and the point already mapped.
  const Eigen::MatrixXd J_c = J.leftCols<7>();
  EXPECT_LT((state.P().block(16, 0, 6, 16) - J_c * prior.P().topRows<7>()).norm(), 1e-10);
  // The feature predicts its own pixel at any inverse depth.
  for (double rho : {0.0, 0.1, 2.0}) {
    Vec6 y = state.x().segment<6>(16);
    y(5) = rho;
    PointMeasurement m;
    ASSERT_TRUE(predictInverseDepthMeasurement(camera, state.r(), state.q(), y, &m));
    EXPECT_LT((m.uv_distorted - uv).norm(), 1e-8) << "rho " << rho;
  }
}

// Civera's L_d: large for a feature just initialised (depth unknown, no parallax), small once the
// camera has moved across it and rho is certain; converting keeps the point and its covariance.
TEST(InverseDepth, LinearityIndexAndConversion) {
  const CameraModel camera = test::testCamera();
  EkfState state;
  state.reset(SE3(), Eigen::Matrix<double, 13, 13>::Identity() * 1e-6);
  const int offset = appendInverseDepthFeature(state, camera, Vec2(300, 200), 1.0, 0.5, 0.5);
  EXPECT_GT(linearityIndex(state, offset), 1.0);
  // The camera 0.5 units across the ray (depth 2 units), with rho known to 1 %.
  state.x().segment<3>(EkfState::kR) = Vec3(0.5, 0, 0);
  state.P()(offset + 5, offset + 5) = std::pow(0.005, 2);
  const double L = linearityIndex(state, offset);
  EXPECT_LT(L, 0.1);
  const Vec3 p = inverseDepthPoint(state.x().segment<6>(offset));
  Eigen::Matrix<double, 3, 6> J;
  inverseDepthToPoint(state.x().segment<6>(offset), &J);
  const Mat3 P_expected = J * state.P().block<6, 6>(offset, offset) * J.transpose();
  const int point = convertToPoint(state, offset);
  EXPECT_EQ(point, 13);
  EXPECT_EQ(state.size(), 16);
  EXPECT_LT((state.x().segment<3>(point) - p).norm(), 1e-12);
  EXPECT_LT((state.P().block<3, 3>(point, point) - P_expected).norm(), 1e-15);
}

// Where the parametrisation is undefined nothing is made up. The camera pitched down 90 degrees (an
// exact quaternion): the principal point's ray runs along the world's vertical axis, where the
// azimuth's Jacobian is 1 / 0 (a NaN covariance the filter then called divergence), and a pixel
// 0.1 px from it has an azimuth 10 radians uncertain: neither is added, the state left as it was.
// 40 px off (0.03 rad) it is added as usual. The camera centre on a feature's point gives an
// infinite linearity index (0 / 0 was NaN, which the conversion test let through).
TEST(InverseDepth, UndefinedGeometryAddsNothingAndConvertsNothing) {
  const CameraModel camera = test::testCamera();
  EkfState state;
  state.reset(SE3(quatFromVector(Vec4(0.5, -0.5, -0.5, -0.5)), Vec3::Zero()),
              Eigen::Matrix<double, 13, 13>::Identity() * 1e-6);
  ASSERT_EQ(state.T_world_camera().R() * Vec3::UnitZ(), Vec3(0, 1, 0));
  const EkfState before = state;
  const Vec2 centre(camera.cx, camera.cy);  // undistorted where it is distorted
  for (const Vec2& uv : {centre, Vec2(centre + Vec2(0.1, 0))}) {
    EXPECT_EQ(appendInverseDepthFeature(state, camera, uv, 1.0, 0.5, 0.5), -1) << uv.transpose();
    EXPECT_EQ(state.size(), before.size());
    EXPECT_EQ(state.P(), before.P());
  }
  EXPECT_EQ(appendInverseDepthFeature(state, camera, centre + Vec2(40, 0), 1.0, 0.5, 0.5), 13);
  EXPECT_TRUE(state.P().allFinite());

  EkfState at_point;
  at_point.reset(SE3(), Eigen::Matrix<double, 13, 13>::Identity() * 1e-6);
  const int offset = appendInverseDepthFeature(at_point, camera, Vec2(300, 200), 1.0, 0.5, 0.5);
  at_point.x().segment<3>(EkfState::kR) = inverseDepthPoint(at_point.x().segment<6>(offset));
  EXPECT_EQ(linearityIndex(at_point, offset), std::numeric_limits<double>::infinity());
}

// Civera's eq. 15 written out here, L_d = 4 (sigma_rho / rho^2) / d1 |cos alpha|, for a camera
// well off the feature's ray (the line of sight 60 degrees from m: |cos alpha| = 0.5, d1 = 2):
// L_d = 0.04, to 1e-12 relative (a few roundings). Without the |cos alpha| it would be 0.08.
TEST(InverseDepth, LinearityIndexIsCiveraEquation15FromASideView) {
  const double theta = 0.2, phi = -0.1, rho = 0.5, sigma_rho = 0.01, d1 = 2.0;
  const Vec3 x0(0.3, -0.2, -1.2);
  const Vec3 m(std::cos(phi) * std::sin(theta), -std::sin(phi), std::cos(phi) * std::cos(theta));
  const Vec3 p_world = x0 + m / rho;
  // The camera at distance d1 from the point, its line of sight at 60 degrees to m.
  const Vec3 across = m.cross(Vec3(0, 1, 0)).normalized();
  const Vec3 sight = 0.5 * m + std::sqrt(0.75) * across;  // unit, from the camera to the point
  const Vec3 r = p_world - d1 * sight;
  EkfState state;
  state.reset(SE3(Mat3::Identity(), r), Eigen::Matrix<double, 13, 13>::Identity() * 1e-4);
  Vec6 y;
  y << x0, theta, phi, rho;
  Eigen::Matrix<double, 6, 6> P_y = Eigen::Matrix<double, 6, 6>::Identity() * 1e-4;
  P_y(5, 5) = sigma_rho * sigma_rho;
  const int offset = state.append(y, P_y, Eigen::MatrixXd::Zero(6, 13));

  const Vec3 h = p_world - r;  // the line of sight, in the world frame
  const double cos_alpha = m.dot(h) / h.norm();
  ASSERT_NEAR(cos_alpha, 0.5, 1e-12);
  ASSERT_NEAR(h.norm(), d1, 1e-12);
  const double expected = 4 * (sigma_rho / (rho * rho)) / h.norm() * std::abs(cos_alpha);
  EXPECT_NEAR(linearityIndex(state, offset), expected, 1e-12 * expected);
  EXPECT_NEAR(expected, 0.04, 1e-12);
}

// The scale gauge: after the pseudo-measurement the mean inverse depth of the first frame's
// features has the gauge's variance (from rho_sigma^2 / n), its ratios (differences) keep theirs,
// the state does not move, and the result is the dense Kalman update with H = [.. 1/n ..].
TEST(InverseDepth, ScaleGaugeConstrainsTheMeanInverseDepthOnly) {
  const CameraModel camera = test::testCamera();
  EkfState state;
  state.reset(SE3(), Eigen::Matrix<double, 13, 13>::Identity() * 1e-6);
  const double rho0 = 0.5, rho_sigma = 0.5, gauge = 0.001;
  std::vector<int> offsets;
  for (const Vec2& uv : {Vec2(100, 80), Vec2(300, 200), Vec2(500, 400), Vec2(420, 90)})
    offsets.push_back(appendInverseDepthFeature(state, camera, uv, 1.0, rho0, rho_sigma));
  const double n = static_cast<double>(offsets.size());
  Eigen::RowVectorXd H = Eigen::RowVectorXd::Zero(state.size());
  for (int o : offsets) H(o + 5) = 1 / n;
  Eigen::RowVectorXd D = Eigen::RowVectorXd::Zero(state.size());  // rho_0 - rho_1
  D(offsets[0] + 5) = 1, D(offsets[1] + 5) = -1;
  const Eigen::MatrixXd P0 = state.P();
  const Eigen::VectorXd x0 = state.x();
  EXPECT_NEAR((H * P0 * H.transpose())(0, 0), rho_sigma * rho_sigma / n, 1e-12);
  const double difference_variance = (D * P0 * D.transpose())(0, 0);

  ASSERT_TRUE(constrainMeanInverseDepth(state, offsets, rho0, gauge));
  const double mean_variance = (H * state.P() * H.transpose())(0, 0);
  EXPECT_GT(mean_variance, 0.99 * gauge * gauge);
  EXPECT_LT(mean_variance, gauge * gauge);
  EXPECT_NEAR((D * state.P() * D.transpose())(0, 0), difference_variance, 1e-12);
  EXPECT_LT((state.x() - x0).norm(), 1e-15);
  const Eigen::VectorXd K = P0 * H.transpose() / ((H * P0 * H.transpose())(0, 0) + gauge * gauge);
  const Eigen::MatrixXd expected = P0 - K * H * P0;
  const int m = state.size() - 13;  // the map's block (kalmanUpdate also renormalises q, with its Jacobian on P)
  EXPECT_LT((state.P().bottomRightCorner(m, m) - expected.bottomRightCorner(m, m)).norm(), 1e-12);

  // Features that moved off rho0 are pulled back together: their mean becomes rho0 (within the
  // gauge), the spread between them stays.
  EkfState moved;
  moved.reset(SE3(), Eigen::Matrix<double, 13, 13>::Identity() * 1e-6);
  for (int k = 0; k < 2; ++k) appendInverseDepthFeature(moved, camera, Vec2(200 + 200 * k, 240), 1.0, rho0, rho_sigma);
  moved.x()(13 + 5) = 0.7, moved.x()(19 + 5) = 0.5;  // mean 0.6, 0.2 apart
  ASSERT_TRUE(constrainMeanInverseDepth(moved, {13, 19}, rho0, gauge));
  EXPECT_NEAR(0.5 * (moved.x()(18) + moved.x()(24)), rho0, 1e-5);
  EXPECT_NEAR(moved.x()(18) - moved.x()(24), 0.2, 1e-9);
  EXPECT_FALSE(constrainMeanInverseDepth(moved, {}, rho0, gauge));
}

// The update with 6-value blocks (an inverse-depth feature beside a point) equals the dense
// textbook formulas with the full H: S = H P H^T + R, K = P H^T S^-1, P - K S K^T.
TEST(InverseDepth, BatchUpdateWithInverseDepthBlocksEqualsTheDenseFormulas) {
  const CameraModel camera = test::testCamera();
  EkfState prior;
  prior.reset(SE3(quatFromVector(kQ), kR), Eigen::Matrix<double, 13, 13>::Identity() * 1e-4);
  prior.append(Vec3(0.2, 0.1, 0.5), Mat3::Identity() * 1e-3, Eigen::MatrixXd::Zero(3, 13));
  prior.append(feature(0.5), Eigen::Matrix<double, 6, 6>::Identity() * 1e-3, Eigen::MatrixXd::Zero(6, 16));
  Eigen::MatrixXd A = Eigen::MatrixXd::Random(prior.size(), prior.size()) * 0.01;
  prior.P() += A * A.transpose();
  std::vector<PointObservation> obs(2);
  obs[0].offset = 13;
  ASSERT_TRUE(predictMeasurement(camera, prior.r(), prior.q(), prior.x().segment<3>(13), &obs[0].h));
  obs[1].offset = 16;
  ASSERT_TRUE(predictInverseDepthMeasurement(camera, prior.r(), prior.q(), prior.x().segment<6>(16), &obs[1].h));
  obs[0].z = obs[0].h.uv_distorted + Vec2(1.0, -0.5);
  obs[1].z = obs[1].h.uv_distorted + Vec2(-0.5, 2.0);
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(4, prior.size());
  Eigen::VectorXd nu(4);
  for (int k = 0; k < 2; ++k) {
    H.block<2, 3>(2 * k, EkfState::kR) = obs[k].h.H_r;
    H.block<2, 4>(2 * k, EkfState::kQ) = obs[k].h.H_q;
    H.block(2 * k, obs[k].offset, 2, obs[k].h.H_y.cols()) = obs[k].h.H_y;
    nu.segment<2>(2 * k) = obs[k].z - obs[k].h.uv_distorted;
  }
  const Eigen::MatrixXd S = H * prior.P() * H.transpose() + Eigen::MatrixXd::Identity(4, 4);
  EXPECT_LT((innovationCovariance(prior, obs, 1.0) - S).norm(), 1e-12);
  EXPECT_LT((pointInnovationCovariance(prior, obs[1].h, 16, 1.0) - S.block<2, 2>(2, 2)).norm(), 1e-12);
  const Eigen::MatrixXd K = prior.P() * H.transpose() * S.inverse();
  EkfState updated = prior;
  ASSERT_TRUE(batchUpdate(updated, obs, 1.0));
  updated.x().segment<4>(EkfState::kQ) *= (prior.x() + K * nu).segment<4>(EkfState::kQ).norm();  // undo renormalisation
  Eigen::VectorXd expected = prior.x() + K * nu;
  EXPECT_LT((updated.x() - expected).norm(), 1e-9);
  // One observation's state-only correction is K nu of that observation alone.
  const Eigen::MatrixXd H1 = H.bottomRows<2>();
  const Eigen::MatrixXd K1 = prior.P() * H1.transpose() *
                             (H1 * prior.P() * H1.transpose() + Eigen::MatrixXd::Identity(2, 2)).inverse();
  EXPECT_LT((stateCorrection(prior, {obs[1]}, 1.0) - K1 * nu.tail<2>()).norm(), 1e-12);
}

}  // namespace
}  // namespace slamcmp
