// Rendered chessboards against the ground truth: detected corners where the camera model puts
// them, the board frame convention at any roll, determinism.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <map>

#include <gtest/gtest.h>

#include "core/chessboard.h"
#include "datasets/camera_motion.h"
#include "datasets/room_scene.h"
#include "datasets/scene_renderer.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

// The scene and the renderer are costly to build (textures, 2.8 million rays): shared by all.
class Rendered : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = std::make_unique<Scene>(buildRoomScene(1));
    renderer_ = std::make_unique<SceneRenderer>(syntheticCamera(), *scene_, 3);
  }
  static void TearDownTestSuite() {
    renderer_.reset();
    scene_.reset();
  }
  static cv::Mat render(const SE3& T_world_camera, const FrameEffects& effects = {}, std::uint64_t seed = 1) {
    return renderer_->renderFrame([&](double) { return T_world_camera; }, 0.0, 0.1, effects, seed, 0);
  }
  // Pixel errors of the detected corners against the projections of the true corners.
  static std::vector<double> cornerErrors(const cv::Mat& image, const SE3& T_world_camera) {
    const ChessboardTarget target = syntheticTarget();
    std::vector<cv::Point2f> uv;
    if (!detectChessboard(image, target, &uv)) return {};
    std::vector<double> errors;
    const std::vector<Vec3> corners = target.cornersWorld();
    for (size_t k = 0; k < corners.size(); ++k) {
      const Vec2 uv_true = renderer_->camera().project(T_world_camera.inverse() * corners[k]);
      errors.push_back((uv_true - Vec2(uv[k].x, uv[k].y)).norm());
    }
    return errors;
  }
  static std::unique_ptr<Scene> scene_;
  static std::unique_ptr<SceneRenderer> renderer_;
};
std::unique_ptr<Scene> Rendered::scene_;
std::unique_ptr<SceneRenderer> Rendered::renderer_;

double rms(const std::vector<double>& v) {
  double sum = 0;
  for (double e : v) sum += e * e;
  return std::sqrt(sum / v.size());
}

double maxOf(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

// Detected corners agree with CameraModel::project of the true corners to 0.1 px RMS, 0.3 px at
// worst, on frames spread over every preset (near, far, oblique, image corners).
TEST_F(Rendered, DetectedCornersMatchGroundTruthProjection) {
  std::vector<double> all;
  for (const MotionPreset& preset : motionPresets()) {
    const CameraMotion motion(preset.name, 1);
    // Frames with the whole board in view: board_leaves is away from about 9 to 17 s, wall_turn
    // from 8 to 19 s; board_partial has all of it in view at the start of each half sweep.
    const std::map<std::string, std::vector<int>> board_in_view = {
        {"board_leaves", {0, 60, 240}}, {"wall_turn", {0, 40, 250}}, {"board_partial", {0, 60, 120}}};
    const auto listed = board_in_view.find(preset.name);
    const std::vector<int> frames = listed != board_in_view.end()
                                        ? listed->second
                                        : std::vector<int>{0, preset.frames / 5, preset.frames / 2 + 7};
    for (int frame : frames) {
      const SE3 T = motion.T_world_camera(frame / preset.fps);
      const std::vector<double> errors = cornerErrors(render(T), T);
      ASSERT_EQ(errors.size(), 54u) << preset.name << " frame " << frame << ": board not detected";
      EXPECT_LT(rms(errors), 0.1) << preset.name << " frame " << frame;
      EXPECT_LT(maxOf(errors), 0.3) << preset.name << " frame " << frame;
      std::printf("%s frame %d: rms %.4f px, max %.4f px\n", preset.name.c_str(), frame, rms(errors),
                  maxOf(errors));
      all.insert(all.end(), errors.begin(), errors.end());
    }
  }
  RecordProperty("corner_rms_px", std::to_string(rms(all)));
  RecordProperty("corner_max_px", std::to_string(maxOf(all)));
  std::printf("corner error over %zu corners: rms %.4f px, max %.4f px\n", all.size(), rms(all), maxOf(all));
}

// A distortion-free camera facing the board squarely: every pixel's footprint on the board is an
// axis-aligned square, and its rendered grey level must be the exact area average of the
// chessboard over it (squares and margin computed here independently), pixel (0, 0) being centred
// on the top-left pixel.
TEST_F(Rendered, PixelsAreExactAreaAveragesOfTheBoard) {
  CameraModel camera = syntheticCamera();
  camera.distortion = {};
  const SceneRenderer renderer(camera, *scene_, 3);
  const double depth = 0.6;
  const SE3 T(Mat3::Identity(), Vec3(0.1234, 0.0567, -depth));
  const cv::Mat image = renderer.radiance(T);
  const ChessboardTarget& target = scene_->target;
  const double s = target.square_size;
  const double shade = scene_->surfaces[scene_->boardWall()].shade;
  int checked = 0;
  for (int v = 0; v < camera.height; v += 3)
    for (int u = 0; u < camera.width; u += 3) {
      const double x0 = T.t().x() + (u - 0.5 - camera.cx) / camera.fx * depth;
      const double x1 = x0 + depth / camera.fx;
      const double y0 = T.t().y() + (v - 0.5 - camera.cy) / camera.fy * depth;
      const double y1 = y0 + depth / camera.fy;
      // Only pixels wholly on the printed board (squares and white margin).
      const double edge = s + scene_->board_margin;
      if (x0 < -edge || y0 < -edge || x1 > target.cols * s + scene_->board_margin ||
          y1 > target.rows * s + scene_->board_margin)
        continue;
      double black_area = 0;
      for (int b = 0; b <= target.rows; ++b)
        for (int a = 0; a <= target.cols; ++a) {
          if ((a + b) % 2 != 0) continue;  // square (a, b) spans [(a-1)s, a s] x [(b-1)s, b s]
          const double w = std::min(x1, a * s) - std::max(x0, (a - 1) * s);
          const double h = std::min(y1, b * s) - std::max(y0, (b - 1) * s);
          if (w > 0 && h > 0) black_area += w * h;
        }
      const double black = black_area / ((x1 - x0) * (y1 - y0));
      const double white = scene_->board_white, black_level = scene_->board_black;
      const double expected = shade * (white - (white - black_level) * black);
      ASSERT_NEAR(image.at<float>(v, u), expected, 1e-3) << "pixel " << u << ", " << v;
      ++checked;
    }
  EXPECT_GT(checked, 10000);
}

// With sensor noise and motion blur the corners stay accurate (a looser bound: noise moves them).
TEST_F(Rendered, CornersStayAccurateWithNoiseAndBlur) {
  const CameraMotion motion("tv1", 1);
  const auto pose_at = [&](double t) { return motion.T_world_camera(t); };
  const double t = 4.0;  // mid-sweep: the camera moves fastest
  FrameEffects effects;
  effects.noise_sigma = 2.0;
  effects.blur_px = 3.0;
  const cv::Mat image = renderer_->renderFrame(pose_at, t, 0.1, effects, 1, 40);
  const std::vector<double> errors = cornerErrors(image, pose_at(t));
  ASSERT_EQ(errors.size(), 54u);
  EXPECT_LT(rms(errors), 0.15);
  std::printf("noise 2, blur 3 px: rms %.4f px, max %.4f px\n", rms(errors), maxOf(errors));
}

// A rolling shutter (30 ms readout) on a camera panning 1 rad/s: each corner is where the camera of
// its row's time projects it (the row found by bisection), not where the frame's camera does.
TEST_F(Rendered, RollingShutterImagesEachRowFromItsOwnTime) {
  const Vec3 centre(0.16, 0.10, 0.0);
  const SE3 T0 = lookAt(centre + Vec3(0.02, -0.03, -0.8), centre);
  const auto pose_at = [&](double t) { return T0 * SE3::fromRotvec(Vec3(0.2, 1.0, 0.1) * t, Vec3(0.1, 0, 0) * t); };
  constexpr double kReadout = 0.03;
  FrameEffects effects;
  effects.rolling_shutter = kReadout;
  const cv::Mat image = renderer_->renderFrame(pose_at, 0.0, 1.0 / 30, effects, 1, 0);
  const ChessboardTarget target = syntheticTarget();
  std::vector<cv::Point2f> uv;
  ASSERT_TRUE(detectChessboard(image, target, &uv));
  const CameraModel& camera = renderer_->camera();
  std::vector<double> to_row_time, to_frame_time;
  const std::vector<Vec3> corners = target.cornersWorld();
  for (size_t k = 0; k < corners.size(); ++k) {
    const Vec2 detected(uv[k].x, uv[k].y);
    to_row_time.push_back((test::rollingShutterProjection(camera, kReadout, pose_at, corners[k]) - detected).norm());
    to_frame_time.push_back((camera.project(pose_at(0.0).inverse() * corners[k]) - detected).norm());
  }
  EXPECT_LT(rms(to_row_time), 0.1);
  EXPECT_GT(rms(to_frame_time), 1.0);  // 1.7 px: the board spans the middle third of the rows
  std::printf("rolling shutter: rms %.4f px from the rows' cameras, %.2f px from the frame's\n", rms(to_row_time),
              rms(to_frame_time));
}

// SPEC section 2: detected corner 0 is the world origin (next to the black corner square) and
// corner 8 is (8 s, 0, 0), whatever the camera's roll.
class RolledCamera : public Rendered, public ::testing::WithParamInterface<int> {};

TEST_P(RolledCamera, DetectedCornerZeroIsWorldOrigin) {
  const double roll = GetParam() * M_PI / 180.0;
  const Vec3 centre(0.16, 0.10, 0.0);
  // Slightly off-axis so that the views are not symmetric.
  const SE3 T = lookAt(centre + Vec3(0.08, -0.05, -0.75), centre + Vec3(0.02, 0.01, 0), roll);
  const cv::Mat image = render(T);
  const ChessboardTarget target = syntheticTarget();
  std::vector<cv::Point2f> uv;
  ASSERT_TRUE(detectChessboard(image, target, &uv)) << "roll " << GetParam();
  const CameraModel& camera = renderer_->camera();
  const Vec2 origin = camera.project(T.inverse() * target.cornerWorld(0, 0));
  const Vec2 x_end = camera.project(T.inverse() * target.cornerWorld(target.cols - 1, 0));
  const Vec2 y_end = camera.project(T.inverse() * target.cornerWorld(0, target.rows - 1));
  const auto detected = [&](int i, int j) {
    const cv::Point2f& p = uv[j * target.cols + i];
    return Vec2(p.x, p.y);
  };
  EXPECT_LT((origin - detected(0, 0)).norm(), 0.3);
  EXPECT_LT((x_end - detected(target.cols - 1, 0)).norm(), 0.3);
  EXPECT_LT((y_end - detected(0, target.rows - 1)).norm(), 0.3);
  EXPECT_LT(rms(cornerErrors(image, T)), 0.1);
}

INSTANTIATE_TEST_SUITE_P(Rolls, RolledCamera, ::testing::Values(0, 90, 180, 270));

TEST_F(Rendered, SameSeedSameImageOtherSeedDifferent) {
  const SE3 T = CameraMotion("tv2", 3).T_world_camera(1.0);
  FrameEffects noisy;
  noisy.noise_sigma = 1.5;
  const cv::Mat a = render(T, noisy, 3), b = render(T, noisy, 3), c = render(T, noisy, 4);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_L1) / a.total(), 0.5);  // grey levels per pixel
  // Another scene seed changes the textures, not the board.
  const Scene other = buildRoomScene(2);
  const SceneRenderer other_renderer(syntheticCamera(), other, 1);
  const SceneRenderer same_renderer(syntheticCamera(), *scene_, 1);
  const cv::Mat d = other_renderer.radiance(T), e = same_renderer.radiance(T);
  EXPECT_GT(cv::norm(d, e, cv::NORM_L1) / d.total(), 5.0);
}

// The noise has the requested standard deviation.
TEST_F(Rendered, NoiseHasRequestedSigma) {
  const SE3 T = CameraMotion("tv1", 1).T_world_camera(0.0);
  cv::Mat clean, noisy;
  render(T).convertTo(clean, CV_32F);
  FrameEffects effects;
  effects.noise_sigma = 4.0;
  render(T, effects).convertTo(noisy, CV_32F);
  cv::Scalar mean, sigma;
  cv::meanStdDev(noisy - clean, mean, sigma);
  EXPECT_NEAR(sigma[0], 4.0, 0.1);  // rounding to integers adds about 0.02
  EXPECT_NEAR(mean[0], 0.0, 0.05);
}

}  // namespace
}  // namespace slamcmp
