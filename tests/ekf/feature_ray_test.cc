#include "ekf/feature_ray.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "ekf/measurement_model.h"
#include "ekf/patch_search.h"
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

using test::kT_world_camera0;
using test::kT_world_camera1;

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
  const SE3 T0 = kT_world_camera0, T1 = kT_world_camera1;  // the plane z = 0 is 1.6 m away
  const cv::Mat& image0 = test::planeView0();
  const cv::Mat& image1 = test::planeView1();
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

// One weighting against densities written out here: each particle's pixel projected from
// r0 + d h, its innovation covariance S_d = J P J^T + sigma^2 I with J the chain rule of that
// projection over (r, r0, h) (the camera's position uncertain to 5 mm independently of the ray, so
// S_d shrinks with depth: |S_d| spans two orders of magnitude from 0.5 m to 5 m), the match the
// search finds in the union of those ellipses, and the new weights the prior ones (unequal) times
// N(match; pixel, S_d) = exp(-nu^T S_d^-1 nu / 2) / (2 pi sqrt|S_d|), renormalised, nothing
// pruned. To 1e-9 relative (roundings in the exponents, some beyond 10; the weights span many
// decades, so each is compared to itself). Without the 1 / sqrt|S_d| the near particles, with the
// wider ellipses, would weigh several times more.
TEST(FeatureRay, ParticleWeightsAreThePriorTimesTheMatchsGaussianDensity) {
  const CameraModel camera = test::testCamera();
  const SE3 T0 = kT_world_camera0, T1 = kT_world_camera1;
  EkfState s = cameraState(T0, 0.0);
  const Vec2 uv(330, 250);
  const int ray = appendRay(s, camera, uv, 1.0);
  PatchSource source;
  cv::Mat templ;
  ASSERT_TRUE(makePatchSource(test::planeView0(), uv, 41, T0, &source));
  ASSERT_TRUE(sourceTemplate(source, 11, &templ));
  // The camera moved to T1, known to 5 mm.
  const double sigma_r = 0.005;
  s.x().head<3>() = T1.t();
  s.P().topLeftCorner<3, 3>() = Mat3::Identity() * sigma_r * sigma_r;
  const cv::Mat& image1 = test::planeView1();

  DepthParticles particles = uniformParticles(39, 0.5, 5.0);
  for (int i = 0; i < particles.size(); ++i) particles.weight[i] = (1 + i % 3) / 78.0;  // sums to 1
  const DepthParticles prior = particles;
  const ActiveSearchOptions search;
  ASSERT_TRUE(updateDepthParticles(s, ray, camera, image1, templ, search, /*prune_threshold=*/0.0, &particles));
  ASSERT_EQ(particles.size(), prior.size());

  // The blocks the pixel depends on: r (0..2), r0 and h (the ray's 6).
  const int idx[9] = {0, 1, 2, ray, ray + 1, ray + 2, ray + 3, ray + 4, ray + 5};
  Eigen::MatrixXd P_sub(9, 9);
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) P_sub(i, j) = s.P()(idx[i], idx[j]);
  Eigen::VectorXd a(9);
  a << s.r(), s.x().segment<6>(ray);
  const Mat3 R_camera_world = T1.R().transpose();
  std::vector<SearchEllipse> ellipses;
  for (int i = 0; i < prior.size(); ++i) {
    const double d = prior.depth[i];
    const Vec3 p_world = a.segment<3>(3) + d * a.segment<3>(6);
    Eigen::Matrix<double, 2, 3> J_p;  // d uv / d p_camera
    SearchEllipse e;
    e.centre = camera.project(R_camera_world * (p_world - a.head<3>()), &J_p);
    Eigen::Matrix<double, 2, 9> J;  // d uv / d(r, r0, h)
    J << -J_p * R_camera_world, J_p * R_camera_world, d * J_p * R_camera_world;
    e.S = J * P_sub * J.transpose() + Mat2::Identity() * search.pixel_sigma * search.pixel_sigma;
    ASSERT_TRUE(camera.inImage(e.centre)) << d;
    ellipses.push_back(e);
  }
  ASSERT_GT(ellipses.front().S.determinant(), 50 * ellipses.back().S.determinant());
  const std::vector<PatchMatch> matches = searchEllipses(image1, templ, ellipses, search.sigma_gate, search.min_ncc);
  ASSERT_FALSE(matches.empty());
  const Vec2 uv_match = matches.front().uv;

  std::vector<double> expected(prior.size());
  double total = 0;
  for (int i = 0; i < prior.size(); ++i) {
    const Mat2& S = ellipses[i].S;
    const Vec2 nu = uv_match - ellipses[i].centre;
    expected[i] = prior.weight[i] * std::exp(-0.5 * nu.dot(S.inverse() * nu)) / (2 * M_PI * std::sqrt(S.determinant()));
    total += expected[i];
  }
  for (int i = 0; i < prior.size(); ++i) {
    expected[i] /= total;
    EXPECT_EQ(particles.depth[i], prior.depth[i]);
    EXPECT_NEAR(particles.weight[i], expected[i], 1e-9 * expected[i]) << prior.depth[i];
  }
}

}  // namespace
}  // namespace slamcmp
