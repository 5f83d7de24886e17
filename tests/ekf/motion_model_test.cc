#include "ekf/motion_model.h"

#include <gtest/gtest.h>

#include "tests/test_util.h"

namespace slamcmp {
namespace {

CameraVector movingCamera() {
  CameraVector x;
  x << 0.1, -0.2, -0.8, quatVector(quatFromRotvec(Vec3(0.1, 0.3, -0.2))), 0.3, -0.1, 0.05, 0.4, -0.2, 0.6;
  return x;
}

TEST(MotionModel, JacobiansMatchNumeric) {
  const CameraVector x = movingCamera();
  const Eigen::Matrix<double, 6, 1> n = (Eigen::Matrix<double, 6, 1>() << 0.02, -0.01, 0.03, 0.1, -0.05, 0.02).finished();
  const double dt = 0.1;
  Mat13 F;
  Mat13x6 G;
  predictCamera(x, dt, n, &F, &G);
  test::expectJacobianMatchesNumeric(
      [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return predictCamera(v, dt, n); }, x, F);
  test::expectJacobianMatchesNumeric(
      [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return predictCamera(x, dt, v); }, n, G);
}

TEST(MotionModel, ConstantVelocityIsExact) {
  const CameraVector x = movingCamera();
  CameraVector y = x;
  for (int i = 0; i < 10; ++i) y = predictCamera(y, 0.05, Eigen::Matrix<double, 6, 1>::Zero());
  EXPECT_LT((y.head<3>() - (x.head<3>() + 0.5 * x.segment<3>(7))).norm(), 1e-12);
  const Quat expected = quatFromVector(x.segment<4>(3)) * quatFromRotvec(0.5 * x.segment<3>(10));
  EXPECT_LT(rotationAngle(quatFromVector(y.segment<4>(3)).toRotationMatrix().transpose() * expected.toRotationMatrix()), 1e-12);
  EXPECT_NEAR(y.segment<4>(3).norm(), 1.0, 1e-14);
}

// velocityBetween inverts the prediction: the velocities it gives take the first pose to the
// second through predictCamera, for a turn of 0.3 rad and a move of 4 cm in a tenth of a second.
TEST(MotionModel, VelocityBetweenTwoPosesIsWhatThePredictionTakes) {
  const SE3 from = SE3::fromRotvec(Vec3(0.1, 0.3, -0.2), Vec3(0.1, -0.2, -0.8));
  const SE3 to = SE3::fromRotvec(Vec3(0.25, 0.1, -0.1), Vec3(0.13, -0.18, -0.79));
  const double dt = 0.1;
  const CameraVelocity velocity = velocityBetween(from, to, dt);
  CameraVector x;
  x << from.t(), quatVector(from.quat()), velocity.v_world, velocity.w_camera;
  const CameraVector y = predictCamera(x, dt, Eigen::Matrix<double, 6, 1>::Zero());
  EXPECT_LT((y.head<3>() - to.t()).norm(), 1e-12);
  EXPECT_LT(rotationAngle(quatFromVector(y.segment<4>(3)).toRotationMatrix().transpose() * to.R()), 1e-12);
}

TEST(MotionModel, PredictionGrowsCameraCovarianceAndKeepsCrossTerms) {
  EkfState state;
  Eigen::Matrix<double, 13, 13> P0 = Eigen::Matrix<double, 13, 13>::Identity() * 1e-4;
  state.reset(SE3::fromRotvec(Vec3(0.1, 0.2, 0.0), Vec3(0, 0, -1)), P0);
  Eigen::MatrixXd cross = Eigen::MatrixXd::Zero(3, 13);
  cross(0, 0) = 5e-5;
  state.append(Vec3(0.1, 0.1, 0), Mat3::Identity() * 1e-4, cross);
  MotionModelOptions options;
  predict(state, 0.1, options);
  // Impulse std per the options: sigma_a * sqrt(dt / reference_rate) on the velocity.
  const double sv = options.sigma_a * std::sqrt(0.1 / options.reference_rate);
  EXPECT_NEAR(state.P()(7, 7), 1e-4 + sv * sv, 1e-12);
  EXPECT_NEAR(state.P()(13, 0), 5e-5, 1e-12);  // r' = r + v dt: cross term with r unchanged
  EXPECT_NEAR(state.P()(13, 13), 1e-4, 1e-15);  // features do not move
  EXPECT_LT((state.P() - state.P().transpose()).norm(), 1e-15);
}

}  // namespace
}  // namespace slamcmp
