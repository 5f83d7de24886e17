// The Kalman fusion of board poses with frame-to-frame motion (combined mode).
#include "cslam/board_odometry_fusion.h"

#include <random>

#include <gtest/gtest.h>

namespace slamcmp {
namespace {

TEST(PoseDelta, DifferenceAndApplyAreInverse) {
  const SE3 a(rotationFromRotvec(Vec3(0.1, -0.2, 0.3)), Vec3(0.5, -0.1, 0.7));
  const SE3 b(rotationFromRotvec(Vec3(0.12, -0.17, 0.31)), Vec3(0.52, -0.08, 0.69));
  const SE3 back = applyPoseDelta(b, poseDifference(a, b));
  EXPECT_LT((back.R() - a.R()).norm(), 1e-12);
  EXPECT_LT((back.t() - a.t()).norm(), 1e-12);
}

// A camera moving along x: the board poses carry white noise, the map poses the exact motion
// plus a constant error (the map's). The fused poses must beat the board's error by a wide margin
// (white noise averaged over the motion), and a board pose far from the prediction is followed.
TEST(BoardOdometryFusion, AveragesBoardNoiseAndFollowsAJump) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 1);
  const double sigma_t = 0.002, sigma_r = 0.002;  // metres, radians
  const SE3 map_error(rotationFromRotvec(Vec3(0.01, 0, 0)), Vec3(0.01, 0.02, 0));
  PoseWithCovariance board, map, map_prev;
  board.covariance = Mat6::Zero();
  board.covariance.diagonal() << Vec3::Constant(sigma_r * sigma_r), Vec3::Constant(sigma_t * sigma_t);
  map.covariance = 1e-4 * board.covariance;
  BoardOdometryFusion fusion({});
  double board_sum = 0, fused_sum = 0;
  const int n = 200;
  for (int k = 0; k < n; ++k) {
    const SE3 T_camera_world(rotationFromRotvec(Vec3(0, 0.001 * k, 0)), Vec3(-0.003 * k, 0, 0.7));
    Vec6 d;
    d << sigma_r * noise(rng), sigma_r * noise(rng), sigma_r * noise(rng), sigma_t * noise(rng),
        sigma_t * noise(rng), sigma_t * noise(rng);
    board.T_camera_world = applyPoseDelta(T_camera_world, d);
    map.T_camera_world = map_error * T_camera_world;
    const SE3 fused = fusion.update(board, k ? std::optional<MapMotion>(MapMotion{map_prev, map}) : std::nullopt);
    map_prev = map;
    if (k < 20) continue;  // the filter settling
    board_sum += (board.T_camera_world.t() - T_camera_world.t()).squaredNorm();
    fused_sum += (fused.t() - T_camera_world.t()).squaredNorm();
  }
  EXPECT_LT(fused_sum, 0.1 * board_sum);
  // A board pose 10 cm off (e.g. after missed frames): the filter follows the board to within
  // half its noise (measured: a fifth).
  board.T_camera_world = SE3(Mat3::Identity(), Vec3(0.1, 0, 0.7));
  const SE3 jumped = fusion.update(board, MapMotion{map_prev, map});
  EXPECT_LT((jumped.t() - board.T_camera_world.t()).norm(), 0.5 * sigma_t);
}

}  // namespace
}  // namespace slamcmp
