// Self-calibration against a known camera: rendered views of a board whose outer squares are cut
// at half a square, as on OpenCV's opencv_left board (its bottom row). Sub-pixel windows that reach
// the cut edge pull the corners next to it; OpenCV's calibration sample (11x11 windows) is biased
// this way, which is why its published fx for opencv_left is 0.6 % above ours.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/chessboard.h"
#include "core/self_calibration.h"
#include "datasets/camera_motion.h"
#include "datasets/room_scene.h"
#include "datasets/scene_renderer.h"

namespace slamcmp {
namespace {

// Close to opencv_left's camera: strong barrel distortion, 640x480.
CameraModel trueCamera() {
  CameraModel c;
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = 536.0;
  c.cx = 342.0;
  c.cy = 235.5;
  c.num_distortion = 5;
  c.distortion = {-0.27, -0.04, 0.0018, -0.0003, 0.24, 0.0, 0.0, 0.0};
  return c;
}

Scene cutBoardScene(const ChessboardTarget& target) {
  Scene scene = buildRoomScene(1);
  scene.target = target;
  scene.boxes.clear();
  scene.board_margin = -0.5 * target.square_size;  // the outer squares end half way
  cv::Mat& wall = scene.surfaces[scene.boardWall()].albedo;
  wall = cv::Mat(wall.size(), CV_8U, cv::Scalar(scene.board_white));  // white paper beyond the cut
  return scene;
}

// Eight views from 0.33 to 0.39 m, the camera up to 29 degrees off the board's axis to each side
// and 20 degrees above and below, aimed off the centre and rolled.
std::vector<cv::Mat> renderViews(const ChessboardTarget& target) {
  const Scene scene = cutBoardScene(target);  // the renderer keeps a reference
  const SceneRenderer renderer(trueCamera(), scene, 3);
  const Vec3 centre(0.1, 0.0625, 0.0);
  std::vector<cv::Mat> views;
  int k = 0;
  for (double yaw : {-0.5, -0.17, 0.17, 0.5})
    for (double pitch : {-0.35, 0.35}) {
      ++k;
      const double distance = 0.33 + 0.03 * (k % 3);
      const Vec3 p_world = centre + distance * Vec3(std::sin(yaw) * std::cos(pitch), std::sin(pitch),
                                                    -std::cos(yaw) * std::cos(pitch));
      const Vec3 aim = centre + Vec3(k % 2 ? 0.04 : -0.04, 0.03 * (k % 3 - 1), 0.0);
      const SE3 T_world_camera = lookAt(p_world, aim, 0.3 * (k % 4) - 0.45);
      views.push_back(renderer.renderFrame([&](double) { return T_world_camera; }, 0.0, 0.1, FrameEffects{}, 1, k));
    }
  return views;
}

TEST(SelfCalibration, RecoversARenderedCameraWhereLargeWindowsAreBiased) {
  const ChessboardTarget target{9, 6, 0.025};
  const std::vector<cv::Mat> views = renderViews(target);
  SelfCalibrationOptions options;
  options.min_view_change = 0;
  SelfCalibrator calibrator(target, cv::Size(640, 480), options);
  std::vector<std::vector<cv::Point2f>> uv_window11;
  for (const cv::Mat& grey : views) {
    std::vector<cv::Point2f> uv;
    ASSERT_TRUE(detectChessboard(grey, target, &uv));
    ASSERT_TRUE(calibrator.addView(uv));
    // OpenCV's calibration sample: cornerSubPix with 11x11 half-windows (23x23 pixels).
    cv::cornerSubPix(grey, uv, cv::Size(11, 11), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.1));
    uv_window11.push_back(uv);
  }
  const auto result = calibrator.calibrate();
  ASSERT_TRUE(result);
  const CameraModel truth = trueCamera();
  // Measured: fx, fy +0.01 %, principal point within 0.1 px, rms 0.03 px.
  EXPECT_NEAR(result->camera.fx, truth.fx, 0.001 * truth.fx);
  EXPECT_NEAR(result->camera.fy, truth.fy, 0.001 * truth.fy);
  EXPECT_NEAR(result->camera.cx, truth.cx, 0.5);
  EXPECT_NEAR(result->camera.cy, truth.cy, 0.5);
  EXPECT_LT(result->rms_px, 0.1);

  // The same views with the sample's windows: the cut edge pulls corners by pixels (measured: fx
  // +2.4 %, rms 0.57 px), so this scene does tell the refinements apart.
  std::vector<cv::Point3f> board;
  for (const Vec3& p : target.cornersWorld())
    board.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.f);
  cv::Mat K, dist;
  std::vector<cv::Mat> rvecs, tvecs;
  const double rms_window11 =
      cv::calibrateCamera(std::vector<std::vector<cv::Point3f>>(views.size(), board), uv_window11,
                          cv::Size(640, 480), K, dist, rvecs, tvecs);
  std::printf("ours: fx %+.3f %%, fy %+.3f %%, cx %+.2f px, cy %+.2f px, rms %.3f px; 11x11 windows: fx %+.2f %%, rms %.2f px\n",
              100 * (result->camera.fx / truth.fx - 1), 100 * (result->camera.fy / truth.fy - 1),
              result->camera.cx - truth.cx, result->camera.cy - truth.cy, result->rms_px,
              100 * (K.at<double>(0, 0) / truth.fx - 1), rms_window11);
  EXPECT_GT(std::abs(K.at<double>(0, 0) / truth.fx - 1.0), 0.005);
  EXPECT_GT(rms_window11, 0.2);
}

// Eight views facing the board square on, from 0.33 to 0.40 m, shifted and rolled: every board
// normal the same (the camera slides and rolls), which leaves the focal length undetermined
// (board_partial's frontal views fitted fx 950 for 525 at 0.05 px). Refused, saying why; without
// the check the fit is made, its focal length far off, at a tiny reprojection error.
TEST(SelfCalibration, ParallelViewsAreRefused) {
  const ChessboardTarget target{9, 6, 0.025};
  const Scene scene = cutBoardScene(target);
  const CameraModel camera = syntheticCamera("tv1");  // the presets' mild distortion: no fold to refuse
  const SceneRenderer renderer(camera, scene, 1);
  SelfCalibrationOptions options;
  options.min_view_change = 0;
  SelfCalibrator calibrator(target, cv::Size(640, 480), options);
  const Vec3 centre(0.1, 0.0625, 0.0);
  std::vector<std::vector<cv::Point2f>> views;
  for (int k = 0; k < 8; ++k) {
    const Vec3 p_world = centre + Vec3(0.02 * (k % 3 - 1), 0.015 * (k % 2), -0.33 - 0.01 * k);
    const SE3 T_world_camera = lookAt(p_world, p_world + Vec3(0, 0, 1), 0.2 * k - 0.7);
    const cv::Mat grey = renderer.renderFrame([&](double) { return T_world_camera; }, 0.0, 0.1, FrameEffects{}, 1, k);
    std::vector<cv::Point2f> uv;
    ASSERT_TRUE(detectChessboard(grey, target, &uv)) << k;
    ASSERT_TRUE(calibrator.addView(uv));
    views.push_back(uv);
  }
  std::string why;
  EXPECT_FALSE(calibrator.calibrate(&why));
  EXPECT_NE(why.find("parallel views do not determine the focal length"), std::string::npos) << why;
  options.min_view_spread_deg = 0;  // the check off: a fit is made, its focal length wrong
  SelfCalibrator unchecked(target, cv::Size(640, 480), options);
  for (const auto& uv : views) unchecked.addView(uv);
  std::string why_unchecked;
  const auto fit = unchecked.calibrate(&why_unchecked);
  ASSERT_TRUE(fit) << why_unchecked;
  std::printf("parallel views, unchecked: fx %.1f for %.1f, rms %.3f px\n", fit->camera.fx, camera.fx, fit->rms_px);
  EXPECT_GT(std::abs(fit->camera.fx / camera.fx - 1), 0.05);
}

}  // namespace
}  // namespace slamcmp
