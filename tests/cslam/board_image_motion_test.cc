// The board predicted by the image's motion (cslam/board_image_motion.h) on exact synthetic
// views: a camera turning on the spot in front of a 9x6 board and a textured wall of points
// 1.5 to 4 m away, through a distorting lens.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/target.h"
#include "cslam/board_image_motion.h"

namespace slamcmp {
namespace {

CameraModel lens() {
  CameraModel c;
  c.width = 640, c.height = 480;
  c.fx = c.fy = 500, c.cx = 320, c.cy = 240;
  c.distortion = {-0.25, 0.08, 0.001, -0.0005, 0, 0, 0, 0};
  return c;
}

struct Scene {
  CameraModel camera = lens();
  ChessboardTarget board{9, 6, 0.03};
  std::vector<Vec3> points;  // world frame, in front of the board's side of the world
  Scene() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0), depth(1.5, 4.0);
    for (int i = 0; i < 3000; ++i) {
      // All round the camera's vertical axis, so that some are seen whichever way it faces.
      const double angle = M_PI * u(rng), d = depth(rng);
      points.emplace_back(0.12 + d * std::sin(angle), 0.08 + 0.6 * u(rng), -0.6 + d * std::cos(angle));
    }
  }
  // The camera 0.6 m in front of the board's centre, turned `yaw` radians about its vertical axis.
  SE3 T_world_camera(double yaw) const {
    return SE3(rotationFromRotvec(Vec3(0, yaw, 0)), Vec3(0.12, 0.075, -0.6));
  }
  // The features seen from T_world_camera by id (undistorted normalised coordinates).
  std::unordered_map<int, Vec2> features(const SE3& T_world_camera) const {
    std::unordered_map<int, Vec2> xy;
    const SE3 T_camera_world = T_world_camera.inverse();
    for (int id = 0; id < static_cast<int>(points.size()); ++id) {
      const Vec3 p = T_camera_world * points[id];
      if (p.z() > 0.1 && camera.inImage(camera.project(p), 8)) xy.emplace(id, p.head<2>() / p.z());
    }
    return xy;
  }
};

// The whole board seen at yaw 0; the camera turns 2 degrees a frame.
BoardImageMotion seenAtStart(const Scene& s) {
  BoardImageMotion motion(BoardImageMotionOptions{}, s.camera.fx);
  const std::vector<Vec3> corners = s.board.cornersWorld();
  std::vector<Vec2> xy;
  const SE3 T_camera_world = s.T_world_camera(0).inverse();
  for (const Vec3& c : corners) {
    const Vec3 p = T_camera_world * c;
    xy.push_back(p.head<2>() / p.z());
  }
  motion.seen(corners, xy);
  return motion;
}

// A turn away (the board leaves the image) and back: a homography of a turning camera is exact,
// so the chain of 60 frame-to-frame homographies puts every corner within 0.05 px of its true
// projection while it is in the image, and the board out of the image while it is away.
TEST(BoardImageMotion, CarriesTheBoardThroughATurnAwayAndBack) {
  const Scene s;
  BoardImageMotion motion = seenAtStart(s);
  const std::vector<Vec3> corners = s.board.cornersWorld();
  const double step = 2.0 * M_PI / 180;
  std::vector<double> yaws;
  for (int k = 1; k <= 30; ++k) yaws.push_back(k * step);
  for (int k = 29; k >= 0; --k) yaws.push_back(k * step);
  std::unordered_map<int, Vec2> previous = s.features(s.T_world_camera(0));
  int away = 0, compared = 0;
  for (const double yaw : yaws) {
    const SE3 T_world_camera = s.T_world_camera(yaw);
    std::unordered_map<int, Vec2> current = s.features(T_world_camera);
    motion.advance(previous, current);
    previous = std::move(current);
    ASSERT_TRUE(motion.predicting()) << yaw;
    const std::vector<cv::Point2f> uv = motion.corners(s.camera, corners);
    ASSERT_EQ(uv.size(), corners.size());
    int in_image = 0;
    for (size_t i = 0; i < corners.size(); ++i) {
      const Vec3 p = T_world_camera.inverse() * corners[i];
      if (p.z() <= 0 || !s.camera.inImage(s.camera.project(p), 0)) continue;
      ++in_image;
      ++compared;
      EXPECT_LT((s.camera.project(p) - Vec2(uv[i].x, uv[i].y)).norm(), 0.05) << "yaw " << yaw << " corner " << i;
    }
    away += in_image == 0;
  }
  EXPECT_GT(away, 10);        // the board was out of view for a stretch
  EXPECT_GT(compared, 1500);  // and in view, wholly or in part, for many
}

// Too few features tracked from one frame to the next (a blurred turn, a blank wall): the
// prediction ends rather than carrying a guess on.
TEST(BoardImageMotion, EndsWhenTooFewFeaturesAreTracked) {
  const Scene s;
  BoardImageMotion motion = seenAtStart(s);
  std::unordered_map<int, Vec2> previous = s.features(s.T_world_camera(0));
  std::unordered_map<int, Vec2> current = s.features(s.T_world_camera(0.01));
  ASSERT_GT(current.size(), 100u);
  while (current.size() >= static_cast<size_t>(BoardImageMotionOptions{}.min_matches)) current.erase(current.begin());
  motion.advance(previous, current);
  EXPECT_FALSE(motion.predicting());
  EXPECT_TRUE(motion.corners(s.camera, s.board.cornersWorld()).empty());
}

}  // namespace
}  // namespace slamcmp
