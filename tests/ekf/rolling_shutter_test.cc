#include "ekf/rolling_shutter.h"

#include <gtest/gtest.h>

#include "ekf/ekf_state.h"
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

}  // namespace
}  // namespace slamcmp
