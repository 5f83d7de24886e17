// The CSLAM tracker on real and rendered sequences, with the accuracy targets of issue 3 as
// thresholds (shortened sequences: the whole suite stays well under two minutes).
#include "cslam/cslam_tracker.h"

#include <cmath>
#include <map>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "core/sequence.h"
#include "datasets/synth_sequence.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

using test::TempDir;
using test::writeText;

struct RunStats {
  int frames = 0;
  std::map<std::string, int> status;  // frames.csv status column: source, initialising or lost
  std::vector<std::string> reasons;
  double ate_trans_rmse = 0;   // metres, no alignment
  double ate_rot_rmse_deg = 0;
  double max_trans = 0;
  double path_length = 0;      // of the ground truth over the posed frames
  SE3 last_error;              // T_gt^-1 T_est of the last posed frame
  int posed = 0;
  int late = 0;  // of them, posed late (FrameResult::late_poses)
  std::optional<CameraModel> camera;
  bool finish_refused = false;  // finish() threw InputError
};

// Runs the tracker on the first max_frames of a sequence and scores it against its ground truth.
RunStats runOn(const std::string& path, const std::string& mode, int max_frames, bool with_camera = true,
               CslamOptions options = {}, const std::string& only = "") {
  Sequence seq = openSequence(path);
  std::optional<CameraModel> camera;
  if (with_camera) camera = seq.camera;
  CslamTracker tracker(camera, *seq.target, seq.image_size, mode, options);
  RunStats s;
  Frame frame;
  double sum_t = 0, sum_r = 0;
  std::optional<Vec3> last_gt;
  std::map<int, double> timestamps;  // of the frames seen, for late poses
  const auto score = [&](double timestamp, const SE3& T_world_camera) {
    const SE3* gt = nullptr;
    for (const auto& p : *seq.groundtruth)
      if (std::abs(p.timestamp - timestamp) < 1e-4) gt = &p.T_world_camera;
    if (!gt) return;
    const SE3 err = gt->inverse() * T_world_camera;
    const double et = (gt->t() - T_world_camera.t()).norm();
    sum_t += et * et;
    sum_r += std::pow(rotationAngle(err.R()) * 180 / M_PI, 2);
    s.max_trans = std::max(s.max_trans, et);
    if (last_gt) s.path_length += (gt->t() - *last_gt).norm();
    last_gt = gt->t();
    s.last_error = err;
    ++s.posed;
  };
  while (s.frames < max_frames && seq.frames->next(&frame)) {
    const FrameResult r = tracker.track(frame);
    timestamps[frame.index] = frame.timestamp;
    ++s.frames;
    ++s.status[statusLabel(r.status, r.source)];
    if (!r.reason.empty()) s.reasons.push_back(r.reason);
    if (!seq.groundtruth) continue;
    for (const LatePose& late : r.late_poses) {
      EXPECT_LT(late.frame_index, frame.index);
      if (!timestamps.count(late.frame_index)) continue;
      score(timestamps[late.frame_index], late.T_world_camera);
      ++s.late;
    }
    if (!r.T_world_camera) continue;
    EXPECT_NE(r.status, TrackStatus::Lost);
    if (!only.empty() && r.source != only) continue;
    score(frame.timestamp, *r.T_world_camera);
  }
  if (s.posed) {
    s.ate_trans_rmse = std::sqrt(sum_t / s.posed);
    s.ate_rot_rmse_deg = std::sqrt(sum_r / s.posed);
  }
  s.camera = tracker.camera();
  try {
    tracker.finish();
  } catch (const InputError&) {
    s.finish_refused = true;
  }
  return s;
}

std::string render(const TempDir& dir, const std::string& preset, int frames) {
  SynthOptions options;
  options.preset = preset;
  options.frames = frames;
  const std::string out = dir.file(preset);
  writeSyntheticSequence(options, out);
  return out;
}

// vamr_checkerboard's reference poses come from the board itself: combined mode must pose >= 98 %
// of the frames and stay within 2 mm RMSE of them (issue 3 target).
TEST(CslamTracker, VamrCombinedMatchesBoardReference) {
  SLAMCMP_REQUIRE_SHARED(shared);
  const RunStats s = runOn(shared + "/vamr_checkerboard", "combined", 100);
  EXPECT_GE(s.posed, 98);
  EXPECT_FALSE(s.finish_refused);
  EXPECT_LT(s.ate_trans_rmse, 0.002);
  EXPECT_LT(s.ate_rot_rmse_deg, 0.2);
}

TEST(CslamTracker, VamrSelfCalibratesThenTracks) {
  SLAMCMP_REQUIRE_SHARED(shared);
  const RunStats s = runOn(shared + "/vamr_checkerboard", "calibration", 200, false);
  ASSERT_TRUE(s.camera);
  const CameraModel reference = readCameraYaml(shared + "/vamr_checkerboard/camera.yaml");
  // The first 150 frames of a slow handheld clip span few tilts: 2 % of the focal length and 10 px
  // of the centre (measured: 0.1 % and 3 px).
  EXPECT_NEAR(s.camera->fx, reference.fx, 0.02 * reference.fx);
  EXPECT_NEAR(s.camera->cx, reference.cx, 10);
  EXPECT_NEAR(s.camera->cy, reference.cy, 10);
  EXPECT_GT(s.status.count("initialising") ? s.status.at("initialising") : 0, 0);
  // The frames that gathered the views are posed once the camera is known (late poses).
  EXPECT_GT(s.late, 100);
  EXPECT_GE(s.posed, 195);
  EXPECT_LT(s.ate_trans_rmse, 0.005);
}

// A sequence that never shows the board: every frame waits for it (initialising: the world frame
// is not set), with the reason "no board" in calibration mode; never a crash or an invented pose.
TEST(CslamTracker, NoBoardIsLostWithAReason) {
  TempDir dir;
  writeText(dir.file("rgb.txt"), "");
  std::string list;
  cv::Mat image(480, 640, CV_8UC1);
  cv::RNG rng(4);
  for (int i = 0; i < 6; ++i) {
    rng.fill(image, cv::RNG::UNIFORM, 0, 255);
    const std::string name = "f" + std::to_string(i) + ".png";
    cv::imwrite(dir.file(name), image);
    list += std::to_string(i * 0.1) + " " + name + "\n";
  }
  writeText(dir.file("rgb.txt"), list);
  writeText(dir.file("target.yaml"),
            "%YAML:1.0\n---\ntype: chessboard\ninner_corners_cols: 9\ninner_corners_rows: 6\nsquare_size: 0.04\n");
  writeText(dir.file("camera.yaml"),
            "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\ncamera_matrix: !!opencv-matrix\n   rows: 3\n"
            "   cols: 3\n   dt: d\n   data: [ 500., 0., 320., 0., 500., 240., 0., 0., 1. ]\n"
            "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ 0., 0., 0., 0., 0. ]\n");
  for (const std::string mode : {"calibration", "combined", "two_view"}) {
    const RunStats s = runOn(dir.path(), mode, 6);
    EXPECT_EQ(s.status.at("initialising"), 6) << mode;
    EXPECT_EQ(s.status.count("lost"), 0u) << mode;
    ASSERT_EQ(s.reasons.size(), 6u) << mode;
    EXPECT_TRUE(s.finish_refused) << mode;  // the run fails (exit 2): no mode can set the world frame
    if (mode == "calibration") {
      EXPECT_EQ(s.reasons.front(), "no board");
    }
  }
}

TEST(CslamTracker, RejectsAnUnknownModeAndMissingTarget) {
  TrackerContext context;
  const CslamOptions options;
  EXPECT_THROW(cslamBackend().make(context, TypedBackendOptions<CslamOptions>()), InputError);
  context.target = ChessboardTarget{9, 6, 0.04};
  EXPECT_THROW(CslamTracker(std::nullopt, *context.target, {640, 480}, "fast", options), InputError);
}

// Rendered tv1 (first 60 frames), combined: every frame from the board fused with the features'
// motion, ATE under 0.9 mm and 0.07 deg (issue target 1 mm and 0.1 deg; measured 0.75 mm and
// 0.054 deg, the board alone 0.78 mm).
TEST(CslamTracker, Tv1CombinedUnderOneMillimetre) {
  TempDir dir;
  const RunStats s = runOn(render(dir, "tv1", 60), "combined", 60);
  EXPECT_EQ(s.posed, 60);
  EXPECT_LT(s.ate_trans_rmse, 0.0009);
  EXPECT_LT(s.ate_rot_rmse_deg, 0.07);
}

// two_view mode on rendered tv4 (first 30 frames). Most features lie on the board's wall, so the
// essential matrix is near-degenerate (planar scene) and trades the lateral motion for a rotation:
// chaining it blindly lost every frame from frame 11 on. Every frame must be posed, by two-view
// motion checked against the map, with drift under 1 % of the path (measured: 0.77 %).
TEST(CslamTracker, Tv4TwoViewPosesEveryFrameOfAPlanarScene) {
  TempDir dir;
  const RunStats s = runOn(render(dir, "tv4", 30), "two_view", 30);
  EXPECT_EQ(s.posed, 30);
  EXPECT_GT(s.status.at("two_view"), 15);
  EXPECT_LT(s.last_error.t().norm(), 0.01 * s.path_length);
}

// The overlay of rendered frames: the board corners as detected lie within 0.5 px of the ground
// truth projection, the axes start at the board origin's projection, tracked features are drawn.
TEST(CslamTracker, OverlayBoardCornersMatchTheGroundTruth) {
  TempDir dir;
  Sequence seq = openSequence(render(dir, "tv1", 4));
  CslamTracker tracker(seq.camera, *seq.target, seq.image_size, "combined", {}, true);
  const std::vector<Vec3> corners = seq.target->cornersWorld();
  Frame frame;
  int frames = 0;
  while (seq.frames->next(&frame)) {
    const FrameResult r = tracker.track(frame);
    ASSERT_TRUE(r.overlay);
    const SE3 T_camera_world = (*seq.groundtruth)[frames++].T_world_camera.inverse();
    ASSERT_EQ(r.overlay->board_corners.size(), corners.size());
    for (size_t i = 0; i < corners.size(); ++i) {
      EXPECT_EQ(r.overlay->board_corners[i].id, static_cast<int>(i));
      EXPECT_LT((r.overlay->board_corners[i].uv - seq.camera->project(T_camera_world * corners[i])).norm(), 0.5) << i;
    }
    ASSERT_EQ(r.overlay->board_axes.size(), 4u);
    EXPECT_LT((r.overlay->board_axes[0] - seq.camera->project(T_camera_world * Vec3::Zero())).norm(), 0.5);
    // Features are detected after the first frame's overlay, tracked from the second on.
    if (frames > 1) {
      EXPECT_GT(r.overlay->features.size(), 50u);
    }
  }
  EXPECT_EQ(frames, 4);
  // Without want_overlay nothing is filled.
  Sequence again = openSequence(dir.file("tv1"));
  CslamTracker plain(again.camera, *again.target, again.image_size, "combined", {});
  ASSERT_TRUE(again.frames->next(&frame));
  EXPECT_FALSE(plain.track(frame).overlay);
}

// two_view mode on rendered tv3 (first 60 frames): chained two-view drift under 1 % of the path.
TEST(CslamTracker, Tv3TwoViewDriftUnderOnePercent) {
  TempDir dir;
  const RunStats s = runOn(render(dir, "tv3", 60), "two_view", 60);
  EXPECT_EQ(s.posed, 60);
  EXPECT_GT(s.status.at("two_view"), 40);
  EXPECT_LT(s.last_error.t().norm(), 0.01 * s.path_length);
}

// board_leaves (first 120 frames: the camera pans off the board from about frame 88): every frame
// is posed, those without the board by two-view motion within 3 mm of the truth (measured 1.3 mm).
TEST(CslamTracker, BoardLeavesTwoViewWithinThreeMillimetres) {
  TempDir dir;
  const RunStats s = runOn(render(dir, "board_leaves", 120), "combined", 120, true, {}, "two_view");
  ASSERT_GT(s.status.count("two_view") ? s.status.at("two_view") : 0, 10);
  EXPECT_EQ(s.status.count("lost"), 0u);
  EXPECT_LT(s.max_trans, 0.003);
}

}  // namespace
}  // namespace slamcmp
