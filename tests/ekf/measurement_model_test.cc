#include "ekf/measurement_model.h"

#include <gtest/gtest.h>

#include "tests/ekf/plane_render.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

TEST(MeasurementModel, JacobiansMatchNumericWithDistortion) {
  const CameraModel camera = test::testCamera();
  const Vec3 r(0.1, -0.05, -0.9);
  const Vec4 q = quatVector(quatFromRotvec(Vec3(0.15, -0.2, 0.1)));
  const Vec3 y(0.3, 0.1, 0.2);
  PointMeasurement m;
  ASSERT_TRUE(predictMeasurement(camera, r, q, y, &m));
  auto h = [&](const Vec3& r_, const Vec4& q_, const Vec3& y_) {
    PointMeasurement out;
    predictMeasurement(camera, r_, q_, y_, &out);
    return Eigen::VectorXd(out.uv_distorted);
  };
  test::expectJacobianMatchesNumeric([&](const Eigen::VectorXd& x) { return h(x, q, y); }, r, m.H_r, 1e-5);
  test::expectJacobianMatchesNumeric([&](const Eigen::VectorXd& x) { return h(r, x, y); }, q, m.H_q, 1e-5);
  test::expectJacobianMatchesNumeric([&](const Eigen::VectorXd& x) { return h(r, q, x); }, y, m.H_y, 1e-5);
  // The prediction is the camera model's projection of the point in the camera frame.
  const SE3 T_world_camera(quatFromVector(q), r);
  EXPECT_LT((m.uv_distorted - camera.project(T_world_camera.inverse() * y)).norm(), 1e-9);
}

TEST(MeasurementModel, PointsBehindTheCameraAreNotPredicted) {
  PointMeasurement m;
  EXPECT_FALSE(predictMeasurement(test::testCamera(), Vec3::Zero(), Vec4(1, 0, 0, 0), Vec3(0, 0, -1), &m));
}

TEST(MeasurementModel, RayFromPixelAndItsJacobians) {
  const CameraModel camera = test::testCamera();
  const Vec4 q = quatVector(quatFromRotvec(Vec3(-0.2, 0.3, 0.05)));
  const Vec2 uv(100.5, 400.25);
  Mat34 J_q;
  Eigen::Matrix<double, 3, 2> J_uv;
  const Vec3 ray = rayFromPixel(camera, q, uv, &J_q, &J_uv);
  EXPECT_NEAR(ray.norm(), 1.0, 1e-12);
  // A point on the ray projects back to uv.
  const SE3 T_world_camera(quatFromVector(q), Vec3(0.2, 0.1, -1));
  EXPECT_LT((camera.project(T_world_camera.inverse() * (T_world_camera.t() + 2.0 * ray)) - uv).norm(), 1e-8);
  test::expectJacobianMatchesNumeric(
      [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return rayFromPixel(camera, x, uv); }, q, J_q, 1e-6);
  test::expectJacobianMatchesNumeric(
      [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return rayFromPixel(camera, q, x); }, uv, J_uv, 1e-6, 1e-4);
}

}  // namespace
}  // namespace slamcmp
