#include "ekf/feature_ray.h"

#include <gtest/gtest.h>

#include "ekf/measurement_model.h"
#include "ekf/patch_warp.h"
#include "tests/ekf/plane_render.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

EkfState cameraState(const SE3& T_world_camera, double sigma) {
  EkfState s;
  s.reset(T_world_camera, Eigen::Matrix<double, 13, 13>::Identity() * sigma * sigma);
  return s;
}

TEST(FeatureRay, RayCovarianceFollowsTheCameraAndThePixelNoise) {
  const CameraModel camera = test::testCamera();
  EkfState s = cameraState(SE3::fromRotvec(Vec3(0.1, -0.2, 0.05), Vec3(0.1, 0, -1)), 0.01);
  const Vec2 uv(300.5, 200.25);
  const int offset = appendRay(s, camera, uv, 1.0);
  ASSERT_EQ(offset, 13);
  EXPECT_LT((s.x().segment<3>(13) - s.r()).norm(), 1e-15);
  // Cross covariance of r0 with the camera: r0 = r.
  EXPECT_TRUE((s.P().block<3, 13>(13, 0).isApprox(s.P().block<3, 13>(0, 0))));
  // The direction's covariance: J_q P_qq J_q^T + J_uv J_uv^T (1 px).
  Mat34 J_q;
  Eigen::Matrix<double, 3, 2> J_uv;
  rayFromPixel(camera, s.q(), uv, &J_q, &J_uv);
  const Mat3 expected = J_q * s.P().block<4, 4>(3, 3) * J_q.transpose() + J_uv * J_uv.transpose();
  EXPECT_LT((s.P().block<3, 3>(16, 16) - expected).norm(), 1e-15);
}

TEST(FeatureRay, PromotionGivesThePointAndItsCovariance) {
  const CameraModel camera = test::testCamera();
  EkfState s = cameraState(SE3::fromRotvec(Vec3(0.1, -0.2, 0.05), Vec3(0.1, 0, -1)), 0.01);
  s.append(Vec3(1, 2, 3), Mat3::Identity() * 1e-4, Eigen::MatrixXd::Zero(3, 13));  // another feature first
  const int ray = appendRay(s, camera, Vec2(320, 240), 1.0);
  s.append(Vec3(4, 5, 6), Mat3::Identity() * 2e-4, Eigen::MatrixXd::Zero(3, s.size()));  // and one after
  const Eigen::MatrixXd P_before = s.P();
  const Vec3 r0 = s.x().segment<3>(ray), h = s.x().segment<3>(ray + 3);
  const int point = promoteRay(s, ray, 1.5, 0.04);
  ASSERT_EQ(s.size(), 13 + 3 + 3 + 3);
  EXPECT_EQ(point, 19);
  EXPECT_LT((s.x().segment<3>(point) - (r0 + 1.5 * h)).norm(), 1e-15);
  EXPECT_EQ(s.x().segment<3>(16), Vec3(4, 5, 6));  // the later feature moved up by 6
  Eigen::Matrix<double, 3, 6> J;
  J << Mat3::Identity(), 1.5 * Mat3::Identity();
  const Mat3 expected = J * P_before.block<6, 6>(ray, ray) * J.transpose() + 0.04 * h * h.transpose();
  EXPECT_LT((s.P().block<3, 3>(point, point) - expected).norm(), 1e-15);
  EXPECT_LT((s.P().block<3, 13>(point, 0) - J * P_before.block(ray, 0, 6, 13)).norm(), 1e-15);
}

TEST(FeatureRay, ParticlesConvergeOnTheTrueDepthAfterASidewaysMove) {
  const CameraModel camera = test::testCamera();
  const SE3 T0 = SE3::fromRotvec(Vec3::Zero(), Vec3(0, 0, -1.6));  // the plane z = 0 is 1.6 m away
  const SE3 T1 = SE3::fromRotvec(Vec3::Zero(), Vec3(0.15, 0.0, -1.6));
  const cv::Mat image0 = test::renderPlane(camera, T0, 0.0);
  const cv::Mat image1 = test::renderPlane(camera, T1, 0.0);
  EkfState s = cameraState(T0, 0.0);
  const Vec2 uv(330, 250);
  const int ray = appendRay(s, camera, uv, 1.0);
  PatchSource source;
  cv::Mat templ;
  ASSERT_TRUE(makePatchSource(image0, uv, 41, T0, &source));
  ASSERT_TRUE(sourceTemplate(source, 11, &templ));
  // Move the camera to T1 exactly (known motion): the particles' spread comes from the ray.
  s.x().head<3>() = T1.t();
  FeatureInitOptions init;
  DepthParticles particles = uniformParticles(init.particles, init.min_depth, init.max_depth);
  ASSERT_TRUE(updateDepthParticles(s, ray, camera, image1, templ, ActiveSearchOptions(), init.prune_threshold,
                                   &particles));
  const double true_depth = (Vec3(0, 0, 0) - T0.t()).norm() / s.x().segment<3>(ray + 3).z();
  EXPECT_NEAR(particles.mean(), true_depth, 0.05);
  EXPECT_LT(particles.stddev(), 0.3 * particles.mean());
  EXPECT_LT(particles.size(), init.particles);
}

}  // namespace
}  // namespace slamcmp
