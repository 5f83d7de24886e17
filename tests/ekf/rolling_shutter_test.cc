#include "ekf/rolling_shutter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "ekf/ekf_state.h"
#include "ekf/ekf_update.h"
#include "ekf/inverse_depth.h"
#include "tests/ekf/plane_render.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

constexpr double kReadout = 0.03;

// A camera turning 1.2 rad/s and moving 0.3 m/s, the state's constant velocities (motion_model.h:
// q(t + tau) = q(t) * quat(w tau), r(t + tau) = r(t) + v tau).
Eigen::VectorXd movingCamera(const Vec3& y_world) {
  Eigen::VectorXd x(16);
  x.segment<3>(EkfState::kR) = Vec3(0.1, -0.05, -0.9);
  x.segment<4>(EkfState::kQ) = quatVector(quatFromRotvec(Vec3(0.1, -0.15, 0.05)));
  x.segment<3>(EkfState::kV) = Vec3(0.2, -0.1, 0.2);
  x.segment<3>(EkfState::kW) = Vec3(0.4, -1.0, 0.5);
  x.segment<3>(13) = y_world;
  return x;
}

SE3 cameraAt(const Eigen::VectorXd& x, double tau) {
  return SE3(quatFromVector(x.segment<4>(EkfState::kQ)) * quatFromRotvec(x.segment<3>(EkfState::kW) * tau),
             Vec3(x.segment<3>(EkfState::kR) + x.segment<3>(EkfState::kV) * tau));
}

Vec2 rolledProjection(const CameraModel& camera, const Eigen::VectorXd& x, const Vec3& y_world) {
  return test::rollingShutterProjection(camera, kReadout, [&](double tau) { return cameraAt(x, tau); }, y_world);
}

TEST(RollingShutter, RowsAreReadAroundTheMiddleRowsTime) {
  const CameraModel camera = test::testCamera();
  EXPECT_NEAR(camera.rowTime(kReadout, 0), -0.5 * kReadout, 1e-15);
  EXPECT_NEAR(camera.rowTime(kReadout, camera.height - 1.0), 0.5 * kReadout, 1e-15);
  EXPECT_NEAR(camera.rowTime(kReadout, 0.5 * (camera.height - 1.0)), 0.0, 1e-15);
}

// The shift takes a feature from its frame-time projection to where the rolling shutter images it,
// for points over the whole image (several pixels at 1.2 rad/s).
TEST(RollingShutter, ShiftFindsWhereTheRowIsRead) {
  const CameraModel camera = test::testCamera();
  MapFeature point;
  point.offset = 13;
  double largest = 0;
  for (const Vec3& y : {Vec3(0.3, 0.1, 0.2), Vec3(-0.1, -0.3, 0.3), Vec3(0.2, 0.2, 0.1), Vec3(0.05, 0.15, 0.0)}) {
    const Eigen::VectorXd x = movingCamera(y);
    const Vec2 uv_frame_time = camera.project(cameraAt(x, 0).inverse() * y);
    ASSERT_TRUE(camera.inImage(uv_frame_time, 20)) << y.transpose();
    const Vec2 shift = rollingShutterShift(camera, kReadout, x, point, uv_frame_time);
    // Two fixed-point steps from the frame-time row: each shrinks the row's error by the row's
    // share of the shift (under 0.05 here), so 8 px become 0.02 px at most.
    EXPECT_LT((uv_frame_time + shift - rolledProjection(camera, x, y)).norm(), 0.02) << y.transpose();
    largest = std::max(largest, shift.norm());
    EXPECT_EQ(rollingShutterShift(camera, 0.0, x, point, uv_frame_time), Vec2::Zero());
  }
  EXPECT_GT(largest, 3.0);  // the test means something: the shutter moves these points pixels
}

// A new feature's pixel goes back to where the frame-time camera sees its ray: exact for a camera
// that only turns.
TEST(RollingShutter, PixelAtFrameTimeUndoesTheTurnOverTheRowsTime) {
  const CameraModel camera = test::testCamera();
  for (const Vec3& y : {Vec3(0.3, 0.1, 0.2), Vec3(-0.1, -0.3, 0.3), Vec3(0.5, 0.25, 0.1)}) {
    Eigen::VectorXd x = movingCamera(y);
    x.segment<3>(EkfState::kV).setZero();
    const Vec2 rolled = rolledProjection(camera, x, y);
    const Vec2 frame_time = camera.project(cameraAt(x, 0).inverse() * y);
    EXPECT_GT((rolled - frame_time).norm(), 1.0);
    EXPECT_LT((pixelAtFrameTime(camera, kReadout, x.segment<3>(EkfState::kW), rolled) - frame_time).norm(), 1e-6);
    EXPECT_EQ(pixelAtFrameTime(camera, 0.0, x.segment<3>(EkfState::kW), rolled), rolled);
  }
}

// A known point is predicted where the rolling shutter images it, to the fixed point's 1e-4 px.
TEST(RollingShutter, KnownPointIsPredictedWhereItsRowIsRead) {
  const CameraModel camera = test::testCamera();
  for (const Vec3& y : {Vec3(0.3, 0.1, 0.2), Vec3(-0.1, -0.3, 0.3), Vec3(0.2, 0.2, 0.1), Vec3(0.05, 0.15, 0.0)}) {
    const Eigen::VectorXd x = movingCamera(y);
    PointMeasurement h;
    ASSERT_TRUE(predictAtRowTime(camera, kReadout, x.head<13>(), y, &h, 1e-3));
    EXPECT_TRUE(h.row_timed);
    EXPECT_LT((h.uv_distorted - rolledProjection(camera, x, y)).norm(), 1e-3) << y.transpose();
    PointMeasurement frame_time;
    ASSERT_TRUE(predictAtRowTime(camera, 0.0, x.head<13>(), y, &frame_time, 1e-3));
    EXPECT_FALSE(frame_time.row_timed);
    EXPECT_LT((frame_time.uv_distorted - camera.project(cameraAt(x, 0).inverse() * y)).norm(), 1e-9);
  }
}

// d h / d (r, q, v, w) and d h / d y against central differences of the whole prediction, the
// row's own dependence on the state included.
TEST(RollingShutter, KnownPointJacobiansMatchNumericDifferences) {
  const CameraModel camera = test::testCamera();
  for (const Vec3& y : {Vec3(0.3, 0.1, 0.2), Vec3(-0.1, -0.3, 0.3), Vec3(0.2, 0.2, 0.1)}) {
    const Eigen::VectorXd x = movingCamera(y);  // the camera's 13 entries, then the point
    PointMeasurement h;
    ASSERT_TRUE(predictAtRowTime(camera, kReadout, x.head<13>(), y, &h, 1e-3));
    Eigen::Matrix<double, 2, 16> analytic;
    analytic << h.H_r, h.H_q, h.H_v, h.H_w, h.H_y;
    const auto predicted = [&](const Eigen::VectorXd& x_perturbed) -> Eigen::VectorXd {
      PointMeasurement p;
      EXPECT_TRUE(predictAtRowTime(camera, kReadout, x_perturbed.head<13>(), x_perturbed.segment<3>(13), &p, 1e-3));
      return p.uv_distorted;
    };
    test::expectJacobianMatchesNumeric(predicted, x, analytic, 1e-4);
    // The velocities matter: a pixel or more per m/s or rad/s at this readout.
    EXPECT_GT(h.H_w.norm(), 1.0);
  }
}

// Any point a pose predicts (here an inverse-depth one, as hybrid's tracked points) is predicted at
// its row's time as a known point is, and its Jacobians, H_y's six columns included, match central
// differences.
TEST(RollingShutter, InverseDepthPointIsPredictedWhereItsRowIsRead) {
  const CameraModel camera = test::testCamera();
  const Vec3 x0(0.05, -0.02, -1.0);  // the centre of the camera that first saw it
  for (const Vec3& p : {Vec3(0.3, 0.1, 0.2), Vec3(-0.1, -0.3, 0.3), Vec3(0.2, 0.2, 0.1)}) {
    const Vec3 d = p - x0;
    const Vec3 m = d.normalized();
    Vec6 y;
    y << x0, std::atan2(m.x(), m.z()), -std::asin(m.y()), 1.0 / d.norm();
    const Eigen::VectorXd x = movingCamera(p);
    const auto predict = [&](const Eigen::VectorXd& x_camera, const Vec6& y_point, PointMeasurement* h) {
      return predictAtRowTime(
          camera, kReadout, x_camera.head<13>(),
          [&](const Vec3& r, const Vec4& q, PointMeasurement* at) {
            return predictInverseDepthMeasurement(camera, r, q, y_point, at);
          },
          h);
    };
    PointMeasurement h;
    ASSERT_TRUE(predict(x, y, &h));
    EXPECT_TRUE(h.row_timed);
    EXPECT_LT((h.uv_distorted - rolledProjection(camera, x, p)).norm(), 1e-3) << p.transpose();
    Eigen::Matrix<double, 2, 19> analytic;
    analytic << h.H_r, h.H_q, h.H_v, h.H_w, h.H_y;
    Eigen::VectorXd xy(19);
    xy << x.head<13>(), y;
    const auto predicted = [&](const Eigen::VectorXd& at) -> Eigen::VectorXd {
      PointMeasurement p;
      EXPECT_TRUE(predict(at.head<13>(), at.tail<6>(), &p));
      return p.uv_distorted;
    };
    test::expectJacobianMatchesNumeric(predicted, xy, analytic, 1e-4);
  }
}

// Corners of a plane under a turning camera's rolling shutter carry its angular velocity: the
// known-point update over (r, q, v, w) finds it, to the corners' noise, from a prior a fifth off.
TEST(RollingShutter, KnownPointsAtTheirRowsTimesMeasureTheAngularVelocity) {
  const CameraModel camera = test::testCamera();
  Eigen::VectorXd truth = movingCamera(Vec3::Zero()).head<13>();
  EkfState state;
  Eigen::Matrix<double, 13, 13> P0 = Eigen::Matrix<double, 13, 13>::Zero();
  P0.diagonal() << Vec3::Constant(1e-6), Vec4::Constant(1e-6), Vec3::Constant(0.01), Vec3::Constant(0.25);
  state.reset(SE3(quatFromVector(truth.segment<4>(EkfState::kQ)), Vec3(truth.segment<3>(EkfState::kR))), P0);
  state.x().segment<3>(EkfState::kV) = truth.segment<3>(EkfState::kV);
  state.x().segment<3>(EkfState::kW) = 0.8 * truth.segment<3>(EkfState::kW);
  std::vector<Vec3> corners;
  std::vector<PointObservation> observations;
  for (int j = -3; j <= 3; ++j)
    for (int i = -4; i <= 4; ++i) {
      const Vec3 p_world(0.1 * i, 0.08 * j, 0.1);
      PointObservation o;
      o.offset = kKnownPoint;
      o.z = rolledProjection(camera, truth, p_world);
      if (!camera.inImage(o.z, 5)) continue;
      ASSERT_TRUE(predictAtRowTime(camera, kReadout, state.x().head<13>(), p_world, &o.h, 1e-3));
      corners.push_back(p_world);
      observations.push_back(o);
    }
  ASSERT_GT(observations.size(), 30u);
  const Relinearise at = [&](const Eigen::VectorXd& x, std::vector<PointObservation>* obs) {
    for (size_t k = 0; k < obs->size(); ++k)
      if (!predictAtRowTime(camera, kReadout, x.head<13>(), corners[k], &(*obs)[k].h, 1e-3)) return false;
    return true;
  };
  ASSERT_TRUE(iteratedUpdate(state, &observations, 0.01, at));
  EXPECT_LT((state.w() - truth.segment<3>(EkfState::kW)).norm(), 0.01 * truth.segment<3>(EkfState::kW).norm());
  for (const PointObservation& o : observations) EXPECT_LT((o.z - o.h.uv_distorted).norm(), 0.01);
}

// The motion model's own turn over half the readout, seen through the focal length: about 0.3 px
// at sigma_alpha 3 rad/s^2 (30 Hz), 30 ms and this camera's focal length; as sigma_alpha, and as
// the readout to the power 1.5 (the turn's variance grows as its time cubed).
TEST(RollingShutter, PixelSigmaIsTheMotionNoisesTurnOverHalfTheReadout) {
  const CameraModel camera = test::testCamera();
  MotionModelOptions motion;
  motion.sigma_alpha = 3.0;
  motion.reference_rate = 30.0;
  const double at_30ms = rollingShutterPixelSigma(camera, kReadout, motion);
  EXPECT_NEAR(at_30ms, 0.5 * (camera.fx + camera.fy) * 5.81e-4, 0.01 * at_30ms);
  EXPECT_EQ(rollingShutterPixelSigma(camera, 0.0, motion), 0.0);
  EXPECT_NEAR(rollingShutterPixelSigma(camera, 4 * kReadout, motion), 8 * at_30ms, 1e-12);
  motion.sigma_alpha = 1.0;
  EXPECT_NEAR(rollingShutterPixelSigma(camera, kReadout, motion), at_30ms / 3, 1e-12);
}

}  // namespace
}  // namespace slamcmp
