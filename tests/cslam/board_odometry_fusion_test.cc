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
  // A board pose 10 cm off: in its first frame it is taken for an outlier (the motion's pose
  // stands); off again in the next frame, it is the map that moved (e.g. after missed frames), and
  // the filter follows the board to within half its noise (measured: a fifth).
  const SE3 last_fused = fusion.update(board, MapMotion{map_prev, map});
  board.T_camera_world = SE3(Mat3::Identity(), Vec3(0.1, 0, 0.7));
  const SE3 held = fusion.update(board, MapMotion{map_prev, map});
  EXPECT_TRUE(fusion.heldLastBoard());
  EXPECT_LT((held.t() - last_fused.t()).norm(), 1e-9);
  const SE3 jumped = fusion.update(board, MapMotion{map_prev, map});
  EXPECT_FALSE(fusion.heldLastBoard());
  EXPECT_LT((jumped.t() - board.T_camera_world.t()).norm(), 0.5 * sigma_t);
}

// A map 3 % too large (a young map's scale: its points triangulated at little parallax) makes
// every frame's motion 3 % too long, an error of the same sign in every frame. Trusted as it comes,
// the motion drags the fused pose ahead of the board along the path; with the map's scale
// uncertain by motion_scale_sigma, the board holds it, and the fused error stays under the board's
// own error alone.
TEST(BoardOdometryFusion, ABiasedMapScaleDoesNotDragThePose) {
  const double sigma_t = 0.001, sigma_r = 0.001;
  const auto run = [&](double motion_scale_sigma) {
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0, 1);
    PoseWithCovariance board, map, map_prev;
    board.covariance = Mat6::Zero();
    board.covariance.diagonal() << Vec3::Constant(sigma_r * sigma_r), Vec3::Constant(sigma_t * sigma_t);
    map.covariance = 1e-3 * board.covariance;
    BoardOdometryFusionOptions options;
    options.motion_scale_sigma = motion_scale_sigma;
    BoardOdometryFusion fusion(options);
    double sum = 0, board_sum = 0;
    int n = 0;
    for (int k = 0; k < 150; ++k) {
      const SE3 T_camera_world(Mat3::Identity(), Vec3(-0.003 * k, 0, 0.7));
      Vec6 d;
      d << sigma_r * noise(rng), sigma_r * noise(rng), sigma_r * noise(rng), sigma_t * noise(rng),
          sigma_t * noise(rng), sigma_t * noise(rng);
      board.T_camera_world = applyPoseDelta(T_camera_world, d);
      map.T_camera_world = SE3(T_camera_world.R(), 1.03 * T_camera_world.t());
      const SE3 fused = fusion.update(board, k ? std::optional<MapMotion>(MapMotion{map_prev, map}) : std::nullopt);
      map_prev = map;
      if (k < 30) continue;
      sum += (fused.t() - T_camera_world.t()).squaredNorm();
      board_sum += (board.T_camera_world.t() - T_camera_world.t()).squaredNorm();
      ++n;
    }
    return std::make_pair(std::sqrt(sum / n), std::sqrt(board_sum / n));  // RMS: fused, the board's alone
  };
  const auto [trusted, board] = run(0.0);
  const double uncertain = run(BoardOdometryFusionOptions{}.motion_scale_sigma).first;
  // Measured: 3.9 mm trusted, 1.35 mm uncertain, the board's own 1.7 mm.
  EXPECT_GT(trusted, 1.5 * board) << "the biased motion should drag a filter that trusts it";
  EXPECT_LT(uncertain, board) << uncertain << " m against " << trusted << " m trusted";
}

}  // namespace
}  // namespace slamcmp
