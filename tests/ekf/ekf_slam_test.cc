// EkfSlam's bookkeeping of its state: a feature whose block changes size inside the state (a ray
// promoted to a point, an inverse-depth feature converted to one) leaves every later feature's
// offset reading back its own values and covariance, and a relocation resets the camera's block
// and its correlations with the map without touching the map.
#include "ekf/ekf_slam.h"

#include <vector>

#include <gtest/gtest.h>

#include "ekf/frame_measurement.h"
#include "ekf/inverse_depth.h"
#include "tests/ekf/plane_render.h"

namespace slamcmp {
namespace {

// The plane z = 0 seen from 1.6 m, and 0.15 m to the side (plane_render.h).
using test::kT_world_camera0;
using test::kT_world_camera1;

// A block's values and covariance as the state held them: read at the offsets of one moment,
// compared with those of another.
struct Snapshot {
  Eigen::VectorXd x;
  Eigen::MatrixXd P;
};

// Two known points after the features already in the map, with covariance among themselves (a
// known point has none, but a zero block would not show a block read at the wrong offset), and a
// tail block after them (a back-end's cloned pose or tracked point).
void addPointsAndTail(EkfSlam& slam, const cv::Mat& grey, const CameraModel& camera) {
  const Vec2 uv[2] = {Vec2(160, 120), Vec2(480, 360)};
  for (const Vec2& pixel : uv) {
    const Vec2 xy = camera.undistortPixel(pixel);
    const Vec3 p_world = kT_world_camera0.t() + 1.6 * Vec3(xy.x(), xy.y(), 1.0);  // on the plane z = 0
    ASSERT_TRUE(slam.addKnownPoint(grey, pixel, p_world, Vec3(0, 0, -1)));
  }
  EkfState& state = slam.state();
  const int first = state.size() - 6;
  Eigen::Matrix<double, 6, 6> B;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) B(i, j) = 1e-3 * ((i + 1) * (j + 2) % 7 - 3) + (i == j ? 1e-2 : 0.0);
  state.P().block<6, 6>(first, first) = B * B.transpose();  // positive definite, every entry distinct
  Eigen::Matrix3d P_tail = Eigen::Matrix3d::Identity() * 4e-4;
  P_tail(0, 1) = P_tail(1, 0) = 1e-4;
  state.appendToTail(Vec3(7, 8, 9), P_tail, Eigen::MatrixXd::Zero(3, state.size()));
}

// Every feature's block (its values, its covariance, its cross covariances with the camera and
// with every other feature) and the tail's, exactly as they were, the features but `changed`
// read at their offsets now, `before_offsets` then.
void expectBlocksUnmoved(const Snapshot& before, const std::vector<int>& before_offsets, const EkfSlam& slam,
                         size_t changed) {
  const EkfState& state = slam.state();
  const std::vector<MapFeature>& features = slam.features();
  ASSERT_EQ(before_offsets.size(), features.size());
  for (size_t i = 0; i < features.size(); ++i) {
    if (i == changed) continue;
    const MapFeature& f = features[i];
    const int now = f.offset, then = before_offsets[i], dim = f.dim();
    ASSERT_LE(now + dim, state.size() - state.tailSize()) << f.id;
    EXPECT_EQ(state.x().segment(now, dim), before.x.segment(then, dim)) << f.id;
    EXPECT_EQ(state.P().block(now, 0, dim, 13), before.P.block(then, 0, dim, 13)) << f.id;
    for (size_t j = 0; j < features.size(); ++j) {
      if (j == changed) continue;
      const MapFeature& g = features[j];
      EXPECT_EQ(state.P().block(now, g.offset, dim, g.dim()), before.P.block(then, before_offsets[j], dim, g.dim()))
          << f.id << " " << g.id;
    }
  }
  ASSERT_EQ(state.tailSize(), 3);
  EXPECT_EQ(state.x().tail<3>(), before.x.tail<3>());
  EXPECT_EQ((state.P().bottomRightCorner<3, 3>()), (before.P.bottomRightCorner<3, 3>()));
}

// The filter's options but for the corners it takes: the plane's smooth texture has Shi-Tomasi
// eigenvalues up to 0.0017, under the default threshold (0.002, set for real images).
EkfSlamOptions planeOptions() {
  EkfSlamOptions options;
  options.feature_init.min_corner_eigenvalue = 2e-4;
  return options;
}

std::vector<int> offsetsOf(const std::vector<MapFeature>& features) {
  std::vector<int> offsets;
  for (const MapFeature& f : features) offsets.push_back(f.offset);
  return offsets;
}

// A ray (the first feature, its 6 values at offset 13) ahead of two points and a tail, promoted by
// updateMap once its depth particles converge after a sideways move: the points' offsets move up
// by 6 and read back their own values and covariance blocks exactly (nothing but indices moved,
// so the comparison is exact); the new point is the last map block and lies on the ray (1e-9 m:
// r0 + d h rounded). Updating no offset reads the promoted point where the first point was.
TEST(EkfSlam, PromotingARayKeepsTheLaterFeaturesBlocks) {
  const CameraModel camera = test::testCamera();
  EkfSlam slam(camera, planeOptions());  // with a board: new features are rays
  slam.reset(kT_world_camera0, Eigen::Matrix<double, 13, 13>::Identity() * 1e-8);
  const cv::Mat& grey0 = test::planeView0();
  slam.updateMap(grey0, 0);
  ASSERT_EQ(slam.features().size(), 1u);
  ASSERT_TRUE(slam.features()[0].is_ray);
  ASSERT_EQ(slam.features()[0].offset, 13);
  addPointsAndTail(slam, grey0, camera);
  ASSERT_EQ(slam.state().size(), 13 + 6 + 3 + 3 + 3);
  const Snapshot before{slam.state().x(), slam.state().P()};
  const std::vector<int> before_offsets = offsetsOf(slam.features());
  const Vec3 r0 = before.x.segment<3>(13), h = before.x.segment<3>(16);

  // The camera moved exactly (known motion); `visible` high enough that no feature is added.
  slam.state().x().head<3>() = kT_world_camera1.t();
  const cv::Mat& grey1 = test::planeView1();
  for (int frame = 0; frame < 5 && slam.features()[0].is_ray; ++frame) slam.updateMap(grey1, 1000);
  ASSERT_EQ(slam.features().size(), 3u);
  ASSERT_FALSE(slam.features()[0].is_ray) << "the ray did not converge in 5 frames";
  EXPECT_EQ(slam.state().size(), 13 + 3 + 3 + 3 + 3);

  const MapFeature& promoted = slam.features()[0];
  EXPECT_EQ(promoted.offset, 13 + 3 + 3);
  EXPECT_LT((slam.state().x().segment<3>(promoted.offset) - r0).cross(h).norm(), 1e-9);
  expectBlocksUnmoved(before, before_offsets, slam, 0);
}

// Board-free: the first frame's six inverse-depth features (6 values each, correlated with the
// camera and, through the scale gauge, with each other), two points and a tail. The first feature
// made linear (its inverse depth's row and column scaled by 1e-3: L_d about 4e-3, the others about
// 3, threshold 0.1) is converted by updateMap: the five inverse-depth features and the points
// after it read back their own values and covariance blocks exactly, and the converted one its own
// point (1e-12 m: x0 + m / rho rounded). Updating no offset reads every later block 6 values off.
TEST(EkfSlam, ConvertingAnInverseDepthFeatureKeepsTheLaterFeaturesBlocks) {
  const CameraModel camera = test::testCamera();
  EkfSlam slam(camera, planeOptions(), /*board_free=*/true);
  slam.reset(kT_world_camera0, cameraCovariance(1e-3, 1e-3, 1e-2, 1e-2));
  const cv::Mat& grey0 = test::planeView0();
  slam.updateMap(grey0, 0);
  ASSERT_EQ(slam.features().size(), 6u);
  for (const MapFeature& f : slam.features()) ASSERT_TRUE(f.inverse_depth);
  ASSERT_EQ(slam.features()[0].offset, 13);
  addPointsAndTail(slam, grey0, camera);
  const int rho = 13 + 5;
  slam.state().P().row(rho) *= 1e-3;
  slam.state().P().col(rho) *= 1e-3;
  ASSERT_LT(linearityIndex(slam.state(), 13), 0.01);
  for (size_t i = 1; i < 6; ++i) ASSERT_GT(linearityIndex(slam.state(), slam.features()[i].offset), 1.0);
  const Snapshot before{slam.state().x(), slam.state().P()};
  const std::vector<int> before_offsets = offsetsOf(slam.features());
  const Vec3 p_world = inverseDepthPoint(before.x.segment<6>(13));

  slam.updateMap(grey0, 1000);
  ASSERT_EQ(slam.features().size(), 8u);
  const MapFeature& converted = slam.features()[0];
  ASSERT_FALSE(converted.inverse_depth);
  for (size_t i = 1; i < 6; ++i) EXPECT_TRUE(slam.features()[i].inverse_depth) << i;
  EXPECT_EQ(slam.state().size(), 13 + 5 * 6 + 3 + 3 + 3 + 3);  // five inverse-depth, two points, the new one, the tail
  EXPECT_EQ(converted.offset, 13 + 5 * 6 + 3 + 3);
  EXPECT_LT((featurePoint(slam.state().x(), converted) - p_world).norm(), 1e-12);
  expectBlocksUnmoved(before, before_offsets, slam, 0);
}

// relocate() with every feature kept but the last two: the camera's values are the given pose at
// rest, P is exactly symmetric, its camera block exactly the given covariance, the camera-map
// blocks exactly zero (both of them: the rows and the columns are reset) and the kept features'
// block exactly as it was (a relocation moves no feature).
TEST(EkfSlam, RelocateResetsTheCameraAndItsCorrelationsOnly) {
  const CameraModel camera = test::testCamera();
  EkfSlam slam(camera, planeOptions(), /*board_free=*/true);
  slam.reset(kT_world_camera0, cameraCovariance(1e-2, 1e-2, 0.1, 0.1));
  slam.updateMap(test::planeView0(), 0);
  ASSERT_EQ(slam.features().size(), 6u);
  slam.predict(0.1);  // the features' correlations with r and q reach v and w
  const int kept = 13 + 4 * 6;
  const Eigen::MatrixXd P_map = slam.state().P().block(13, 13, kept - 13, kept - 13);
  ASSERT_GT(slam.state().P().block(0, 13, 13, kept - 13).cwiseAbs().maxCoeff(), 1e-6);  // correlated

  const SE3 T_world_camera = SE3::fromRotvec(Vec3(0.1, -0.2, 0.05), Vec3(0.3, -0.1, -1.2));
  Eigen::Matrix<double, 13, 13> P_camera = cameraCovariance(0.02, 0.003, 0.05, 0.04);
  P_camera(0, 4) = P_camera(4, 0) = 1e-5;  // one correlation, to see the block copied whole
  slam.relocate(T_world_camera, P_camera, slam.features()[4].id);
  const EkfState& state = slam.state();
  ASSERT_EQ(slam.features().size(), 4u);
  ASSERT_EQ(state.size(), kept);
  EXPECT_LT((state.T_world_camera().t() - T_world_camera.t()).norm(), 1e-15);
  EXPECT_LT((state.T_world_camera().R() - T_world_camera.R()).norm(), 1e-15);
  EXPECT_EQ(state.v(), Vec3::Zero());
  EXPECT_EQ(state.w(), Vec3::Zero());
  EXPECT_EQ(state.P(), state.P().transpose());
  EXPECT_EQ((state.P().topLeftCorner<13, 13>()), P_camera);
  EXPECT_EQ(state.P().block(0, 13, 13, kept - 13), Eigen::MatrixXd::Zero(13, kept - 13));
  EXPECT_EQ(state.P().block(13, 0, kept - 13, 13), Eigen::MatrixXd::Zero(kept - 13, 13));
  EXPECT_EQ(state.P().bottomRightCorner(kept - 13, kept - 13), P_map);
}

}  // namespace
}  // namespace slamcmp
