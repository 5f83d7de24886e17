// Tracking regressions for the MonoSLAM back-end on shortened sequences. Thresholds are the issue's
// targets: synthetic tv1 and tv4 every frame tracked with ATE RMSE (no alignment) under 1 cm; the real
// vamr_checkerboard at least 95 % tracked with ATE RMSE under 3 cm.
#include "monoslam_ekf/monoslam_tracker.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "core/sequence.h"
#include "core/statistics.h"
#include "core/trajectory.h"
#include "datasets/synth_sequence.h"
#include "eval/metrics/associate.h"
#include "eval/metrics/board_visibility.h"
#include "eval/metrics/nees.h"
#include "eval/metrics/trajectory_metrics.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

struct RunResult {
  int frames = 0, tracked = 0;
  Trajectory estimate;          // the posed frames
  std::vector<double> error_m;  // per tracked frame: |t_gt - t_est|
  std::vector<FrameResult> results;
  std::vector<CovariantPose> covariant;  // the posed frames with their covariance (NEES)
  double ateRmse() const {
    double sum = 0;
    for (double e : error_m) sum += e * e;
    return error_m.empty() ? 1e9 : std::sqrt(sum / error_m.size());
  }
};

// Runs the tracker over the sequence; ground truth is matched by frame index (same timestamps).
RunResult runTracker(const std::string& path, InitSource init, const std::optional<SE3>& T_init,
                     int max_frames = -1, const MonoslamOptions& options = MonoslamOptions{}) {
  Sequence seq = openSequence(path);
  TrackerContext context;
  context.camera = seq.camera;
  context.target = seq.target;
  context.image_size = seq.image_size;
  context.init = init;
  context.T_world_camera_init = T_init;
  MonoslamTracker tracker(context, options);
  RunResult run;
  Frame frame;
  while ((max_frames < 0 || run.frames < max_frames) && seq.frames->next(&frame)) {
    const FrameResult r = tracker.track(frame);
    run.results.push_back(r);
    ++run.frames;
    if (!r.T_world_camera) continue;
    ++run.tracked;
    run.estimate.push_back({frame.timestamp, *r.T_world_camera});
    if (r.pose_covariance) run.covariant.push_back({frame.timestamp, *r.T_world_camera, *r.pose_covariance});
    if (seq.groundtruth)
      run.error_m.push_back((r.T_world_camera->t() - (*seq.groundtruth)[frame.index].T_world_camera.t()).norm());
  }
  return run;
}

// The README's hand-held options, and with them the orientation measured by two-view geometry.
const std::string kHandheldConfig = std::string(SLAMCMP_SOURCE_DIR) + "/configs/monoslam_handheld.yaml";

// The `monoslam:` section of an option file.
MonoslamOptions loadMonoslamOptions(const std::string& file) {
  const cv::FileStorage fs(file, cv::FileStorage::READ);
  MonoslamOptions options;
  loadOptions(fs["monoslam"], file, options);
  return options;
}

// The largest position error of the posed frames, metres.
double worstError(const RunResult& run) {
  double worst = 0;
  for (double e : run.error_m) worst = std::max(worst, e);
  return worst;
}

// ATE RMSE (m) after Sim(3) alignment onto the sequence's ground truth.
double sim3Ate(const std::string& path, const RunResult& run) {
  EvalOptions options;
  options.align = "sim3";
  return evaluateTrajectory(*openSequence(path).groundtruth, run.estimate, options).ate_trans_stats.rmse;
}

// The first `frames` of `preset` into `dir` (0: its own length), at one sample per pixel unless
// said (fast, still textured), the rows read over rolling_shutter seconds (0: a global shutter).
void renderFast(const std::string& preset, int frames, const std::string& dir, int seed = 1, int supersample = 1,
                double rolling_shutter = 0) {
  SynthOptions options;
  options.preset = preset;
  options.frames = frames;
  options.seed = seed;
  options.supersample = supersample;
  options.rolling_shutter = rolling_shutter;
  writeSyntheticSequence(options, dir);
}

// 70 frames of tv1 rendered once for the suite (one sample per pixel: fast, still textured).
class MonoslamOnTv1 : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    renderFast("tv1", 70, dir_->path());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static SE3 groundTruthStart() { return openSequence(dir_->path()).groundtruth->front().T_world_camera; }
  static test::TempDir* dir_;
};
test::TempDir* MonoslamOnTv1::dir_ = nullptr;

TEST_F(MonoslamOnTv1, BoardStartTracksEveryFrameUnderOneCentimetre) {
  const RunResult run = runTracker(dir_->path(), InitSource::Board, std::nullopt);
  EXPECT_EQ(run.tracked, run.frames);
  EXPECT_LT(run.ateRmse(), 0.01);
  for (const FrameResult& r : run.results) EXPECT_LE(r.measured, 12);
  EXPECT_GT(run.results.back().measured, 5);
  // frames.csv's status is the pose's source: the board's in the start frame, the filter's after.
  EXPECT_EQ(run.results.front().source, "board");
  EXPECT_EQ(run.results[1].source, "ekf");
}

// A board-free run whose lens is covered for 15 frames (a burst of blur, a hand over it): the
// frames it cannot see are lost, and it is posed again against the map it made before, not
// against features mapped while lost, through the rest of the run. Without relocalisation it
// stays lost to the end (its map is all that could anchor it).
TEST_F(MonoslamOnTv1, BoardFreeRunRelocalisesAfterABlackout) {
  test::TempDir dir;
  std::filesystem::copy(dir_->path(), dir.path(), std::filesystem::copy_options::recursive |
                                                      std::filesystem::copy_options::overwrite_existing);
  const int dark_from = 30, dark_to = 45;
  for (int i = dark_from; i < dark_to; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "rgb/%06d.png", i);
    ASSERT_TRUE(cv::imwrite(dir.file(name), cv::Mat::zeros(480, 640, CV_8UC3)));
  }
  const RunResult run = runTracker(dir.path(), InitSource::None, std::nullopt);
  ASSERT_EQ(run.frames, 70);
  for (int i = 0; i < dark_from; ++i) EXPECT_TRUE(run.results[i].T_world_camera) << "frame " << i;
  // Black frames: lost (they measure nothing: their poses would be the motion model's), each saying why.
  for (int i = dark_from; i < dark_to; ++i) {
    EXPECT_FALSE(run.results[i].reason.empty()) << "frame " << i;
    EXPECT_FALSE(run.results[i].T_world_camera) << "frame " << i;
  }
  int back = -1;
  for (int i = dark_to; i < run.frames && back < 0; ++i)
    if (run.results[i].reason.find("relocalised against the map") != std::string::npos) back = i;
  ASSERT_GE(back, dark_to);
  // An attempt in every lost frame: the first frame with the map in view, or the next (since new
  // features avoid look-alikes, feature_init.distinct, too few of the map's agree in the first; 8 in
  // the next, 6 needed).
  EXPECT_LE(back, dark_to + 1);
  for (int i = back; i < run.frames; ++i) EXPECT_TRUE(run.results[i].T_world_camera) << "frame " << i;
  // One Sim(3) fits the poses before and after: the same map, at the same scale.
  EXPECT_LT(sim3Ate(dir.path(), run), 0.005);

  MonoslamOptions no_relocalisation;
  no_relocalisation.relocalisation.enabled = false;
  const RunResult stays_lost = runTracker(dir.path(), InitSource::None, std::nullopt, -1, no_relocalisation);
  EXPECT_EQ(stays_lost.tracked, dark_from);
  for (int i = dark_to; i < stays_lost.frames; ++i) EXPECT_FALSE(stays_lost.results[i].T_world_camera);
}

// A board-free run whose first frames show nothing (a lens cap, a grey wall): the map is started
// from the first frame with texture, not from an empty one (which posed three frames at the first
// camera's pose and then, never restarting, lost the rest of the run).
TEST_F(MonoslamOnTv1, BoardFreeStartWaitsForTexture) {
  test::TempDir dir;
  std::filesystem::copy(dir_->path(), dir.path(), std::filesystem::copy_options::recursive |
                                                      std::filesystem::copy_options::overwrite_existing);
  const int grey_to = 10;
  for (int i = 0; i < grey_to; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "rgb/%06d.png", i);
    ASSERT_TRUE(cv::imwrite(dir.file(name), cv::Mat(480, 640, CV_8UC3, cv::Scalar(128, 128, 128))));
  }
  const RunResult run = runTracker(dir.path(), InitSource::None, std::nullopt);
  for (int i = 0; i < grey_to; ++i) {
    EXPECT_EQ(run.results[i].status, TrackStatus::Initialising) << "frame " << i;
    EXPECT_NE(run.results[i].reason.find("waiting for texture to start the map"), std::string::npos)
        << run.results[i].reason;
  }
  for (int i = grey_to; i < run.frames; ++i) EXPECT_TRUE(run.results[i].T_world_camera) << "frame " << i;
  EXPECT_LT(sim3Ate(dir.path(), run), 0.005);
}

// The noise measured on the presets (configs/synthetic_presets.yaml, README "Consistency"): the
// defaults, made for a hand-held camera, leave the filter far underconfident on a render; the
// measured noise brings its NEES towards the 6 dof and its error down. SceneLib's settings are
// one file away (configs/scenelib.yaml).
TEST_F(MonoslamOnTv1, PresetNoiseFileBringsTheNeesTowardsItsDof) {
  const MonoslamOptions scenelib = loadMonoslamOptions("configs/scenelib.yaml");
  EXPECT_EQ(scenelib.filter.motion.sigma_a, 4.0);
  EXPECT_EQ(scenelib.filter.motion.sigma_alpha, 6.0);
  EXPECT_EQ(scenelib.filter.feature_init.promote_ratio, 0.3);

  const Trajectory truth = *openSequence(dir_->path()).groundtruth;
  const RunResult defaults = runTracker(dir_->path(), InitSource::Board, std::nullopt);
  const RunResult measured =
      runTracker(dir_->path(), InitSource::Board, std::nullopt, -1,
                 loadMonoslamOptions("configs/synthetic_presets.yaml"));
  const auto nees_defaults = poseNees(truth, defaults.covariant, 0.01);
  const auto nees_measured = poseNees(truth, measured.covariant, 0.01);
  ASSERT_TRUE(nees_defaults && nees_measured);
  // 70 frames, one sample a pixel: 0.07 with the defaults, 0.78 with the measured noise (2.1 and
  // 0.9 mm ATE); the rest of the way to 6 is README's "Still not inside the bounds".
  EXPECT_LT(nees_defaults->mean, 0.5);
  EXPECT_GT(nees_measured->mean, 5 * nees_defaults->mean);
  EXPECT_LT(nees_measured->mean, nees_measured->upper);
  EXPECT_EQ(measured.tracked, measured.frames);
  EXPECT_LT(measured.ateRmse(), defaults.ateRmse());
}

TEST_F(MonoslamOnTv1, GroundTruthStartTracksEveryFrameUnderOneCentimetre) {
  const RunResult run = runTracker(dir_->path(), InitSource::GroundTruth, groundTruthStart());
  EXPECT_EQ(run.tracked, run.frames);
  EXPECT_LT(run.ateRmse(), 0.01);
}

// A hand-measured start off by 1 cm and 1 degree: the board corners pull the estimate back; the
// error stays bounded (under 3 cm at any frame) and has settled under 1.5 cm over the last 20 frames.
TEST_F(MonoslamOnTv1, SmallManualStartErrorStaysBounded) {
  const SE3 perturbation = SE3::fromRotvec(Vec3(1.0, 0.0, 0.0) * M_PI / 180.0, Vec3(0.01, 0.0, 0.0));
  const RunResult run = runTracker(dir_->path(), InitSource::Manual, groundTruthStart() * perturbation);
  ASSERT_EQ(run.tracked, run.frames);
  double late = 0;
  for (size_t i = 0; i < run.error_m.size(); ++i) {
    EXPECT_LT(run.error_m[i], 0.03) << "frame " << i;
    if (i + 20 >= run.error_m.size()) late = std::max(late, run.error_m[i]);
  }
  EXPECT_LT(late, 0.015);
}

// Issue 18: started without the board (inverse depth, 1-point RANSAC, an arbitrary scale), every
// frame is posed and the Sim(3)-aligned ATE is within 2x the board-started run's.
TEST_F(MonoslamOnTv1, BoardFreeStartWithinTwiceTheBoardStartedSim3Error) {
  const RunResult board = runTracker(dir_->path(), InitSource::Board, std::nullopt);
  const RunResult none = runTracker(dir_->path(), InitSource::None, std::nullopt);
  EXPECT_EQ(none.tracked, none.frames);
  EXPECT_LT(sim3Ate(dir_->path(), none), 2 * sim3Ate(dir_->path(), board));
  // Its world is the first camera's, and its map has no board corners.
  EXPECT_LT(none.estimate.front().T_world_camera.t().norm(), 1e-12);
}

TEST_F(MonoslamOnTv1, MapPointsCarryTheirUncertainty) {
  Sequence seq = openSequence(dir_->path());
  TrackerContext context;
  context.camera = seq.camera;
  context.target = seq.target;
  MonoslamTracker tracker(context, MonoslamOptions{});
  Frame frame;
  for (int i = 0; i < 30 && seq.frames->next(&frame); ++i) tracker.track(frame);
  const std::vector<MapPoint> points = tracker.mapPoints();
  ASSERT_GT(points.size(), 4u);
  int known = 0;
  for (const MapPoint& p : points) {
    EXPECT_GE(p.sigma, 0.0);
    EXPECT_LT(p.sigma, 0.5);
    if (p.sigma == 0.0) ++known;  // the board corners: exact
  }
  EXPECT_EQ(known, 4);
  EXPECT_TRUE(tracker.options().contains("search"));
}

// The overlay: each Matched feature inside its 3-sigma search ellipse, as many Matched as
// FrameResult::measured, rays drawn with their particles; nothing when not asked for.
TEST_F(MonoslamOnTv1, OverlayShowsWhatWasSearchedAndMatched) {
  Sequence seq = openSequence(dir_->path());
  TrackerContext context;
  context.camera = seq.camera;
  context.target = seq.target;
  context.want_overlay = true;
  MonoslamTracker tracker(context, MonoslamOptions{});
  MonoslamTracker plain([&] {
    TrackerContext c = context;
    c.want_overlay = false;
    return c;
  }(), MonoslamOptions{});
  Frame frame;
  int matched_total = 0, rays = 0;
  for (int i = 0; i < 15 && seq.frames->next(&frame); ++i) {
    const FrameResult r = tracker.track(frame);
    EXPECT_FALSE(plain.track(frame).overlay.has_value());
    ASSERT_TRUE(r.overlay.has_value());
    const FrameOverlay& o = *r.overlay;
    EXPECT_EQ(o.patch_size, 11);
    if (i == 0) {
      EXPECT_EQ(o.board_corners.size(), 54u);
    }
    EXPECT_EQ(o.board_axes.size(), 4u);
    int matched = 0, initialising = 0;
    for (const OverlayFeature& f : o.features) {
      if (f.state == OverlayFeatureState::Initialising) ++initialising;
      if (f.state != OverlayFeatureState::Matched) continue;
      ++matched;
      const auto e = std::find_if(o.search_ellipses.begin(), o.search_ellipses.end(),
                                  [&](const OverlayEllipse& x) { return x.feature_id == f.id; });
      ASSERT_NE(e, o.search_ellipses.end()) << "frame " << i << " feature " << f.id;
      EXPECT_TRUE(e->matched);
      const Vec2 d = f.uv - e->centre;
      EXPECT_LE(d.dot(e->S.inverse() * d), 9.0 + 1e-9) << "frame " << i << " feature " << f.id;
    }
    EXPECT_EQ(matched, r.measured) << "frame " << i;
    EXPECT_EQ(static_cast<int>(o.particle_lines.size()), initialising);
    for (const auto& line : o.particle_lines) EXPECT_GE(line.size(), 2u);
    matched_total += matched;
    rays += initialising;
  }
  EXPECT_GT(matched_total, 50);
  EXPECT_GT(rays, 0);
}

// tv4's first 130 frames orbit the board sideways (to frame 43), then move away from it along the
// optical axis (0.65 to 1.05 m), where a new feature's depth is weakly observed: promoted too early
// (depth std/mean 0.3) its depth error pulls the camera 5 cm (14 cm at worst) off; the defaults keep
// it to millimetres.
TEST(MonoslamTracker, Tv4MotionAlongTheOpticalAxisUnderOneCentimetre) {
  test::TempDir dir;
  renderFast("tv4", 130, dir.path());
  const RunResult run = runTracker(dir.path(), InitSource::Board, std::nullopt);
  EXPECT_EQ(run.tracked, run.frames);
  EXPECT_LT(run.ateRmse(), 0.01);
  EXPECT_LT(worstError(run), 0.02);
}

// A board-free map's scale is the gauge its first features fix (inverse_depth.scale_gauge_sigma):
// on tv4 (an orbit sideways about the board, then backing away) each feature's prior alone let it
// wander (full render: 0.43 m a unit over the first 20 frames, 0.195 from frame 40 on, full-length
// Sim(3) ATE 13.8 mm), with the gauge it held (0.33-0.34; 8.2 mm; 2.4 mm since session 25). Metres of ground-truth path per
// unit of estimated path, over frames 1-20 and 40-119. At one sample per pixel (here): 0.36 then
// 0.31 without, 0.342 then 0.346 with, Sim(3) ATE 10.8 against 1.9 mm (before new features
// avoided look-alikes, feature_init.distinct: 0.37 then 0.21 without, 0.32 then 0.30 with, 15 mm
// either way). The scale's drift is held to under a fifth of the drift without the gauge.
TEST(MonoslamTracker, BoardFreeScaleHeldByTheFirstFeatures) {
  test::TempDir dir;
  renderFast("tv4", 120, dir.path());
  const Trajectory groundtruth = *openSequence(dir.path()).groundtruth;
  const auto metresPerUnit = [&](const RunResult& run, size_t from, size_t to) {
    double truth = 0, estimate = 0;
    for (size_t k = from + 1; k <= to; ++k) {
      truth += (groundtruth[k].T_world_camera.t() - groundtruth[k - 1].T_world_camera.t()).norm();
      estimate += (run.estimate[k].T_world_camera.t() - run.estimate[k - 1].T_world_camera.t()).norm();
    }
    return truth / estimate;
  };
  MonoslamOptions without;
  without.filter.inverse_depth.scale_gauge_sigma = 0;
  std::map<bool, double> drift;  // |early / late - 1|
  for (const bool gauge : {true, false}) {
    const RunResult run = runTracker(dir.path(), InitSource::None, std::nullopt, -1, gauge ? MonoslamOptions{} : without);
    ASSERT_EQ(run.tracked, run.frames);
    const double early = metresPerUnit(run, 1, 20), late = metresPerUnit(run, 40, 119);
    const double ate = sim3Ate(dir.path(), run);
    std::cout << (gauge ? "with" : "without") << " the gauge: " << early << " then " << late
              << " m a unit, Sim(3) ATE " << ate * 1e3 << " mm\n";
    drift[gauge] = std::abs(early / late - 1);
    if (gauge) {
      EXPECT_LT(ate, 0.025);
    }
  }
  EXPECT_LT(drift[true], 0.05);
  EXPECT_LT(drift[true], 0.2 * drift[false]);  // the wander the gauge removes
}

// The same moving along the optical axis (tv3), on a roll of 110 degrees with strong distortion,
// orbiting the board (tv4) and with the board filling most of the first view (board_partial). The
// last two need new features placed where their patch has no look-alike
// (feature_init.distinct): a chessboard's corners repeat a square away, and in the first, wide
// searches they were matched there. Without it tv4 at 120 frames was 15.6 mm against 2.2 (its
// first frames orbit the board and the filter took the orbit for one the other way) and
// board_partial was lost in its first frames (5 of 120 posed), which the test checks too.
TEST(MonoslamTracker, BoardFreeStartOnFourPresetsWithinTwiceTheBoardStartedSim3Error) {
  for (const auto& [preset, frames] : {std::pair<std::string, int>{"tv3", 100}, {"roll_distortion", 100},
                                       {"tv4", 120}, {"board_partial", 120}}) {
    test::TempDir dir;
    renderFast(preset, frames, dir.path());
    const RunResult board = runTracker(dir.path(), InitSource::Board, std::nullopt);
    const RunResult none = runTracker(dir.path(), InitSource::None, std::nullopt);
    EXPECT_EQ(none.tracked, none.frames) << preset;
    EXPECT_LT(sim3Ate(dir.path(), none), 2 * sim3Ate(dir.path(), board)) << preset;
    if (preset == "board_partial") {
      MonoslamOptions anywhere;
      anywhere.filter.feature_init.distinct = "off";
      EXPECT_LT(runTracker(dir.path(), InitSource::None, std::nullopt, -1, anywhere).tracked, none.frames / 2);
    }
  }
}

// The board-started run on `preset` (one sample per pixel) poses at least `min_posed` frames and
// none 5 cm off or more; with a check turned off (`without`) a frame is posed over 5 cm off.
RunResult expectNoFrameOverFiveCentimetres(const std::string& preset, int frames, int seed, int min_posed,
                                           const MonoslamOptions& without) {
  test::TempDir dir;
  renderFast(preset, frames, dir.path(), seed);
  const RunResult run = runTracker(dir.path(), InitSource::Board, std::nullopt);
  EXPECT_GE(run.tracked, min_posed);
  EXPECT_LT(worstError(run), 0.05);
  EXPECT_GT(worstError(runTracker(dir.path(), InitSource::Board, std::nullopt, -1, without)), 0.05)
      << "what the check keeps out of the trajectory";
  return run;
}

// board_leaves seed 7: as the board leaves, a feature started on an occluding edge (a box against
// the plain wall) is matched 9 px from its place, and with the board's corners gone it carries
// the pose (full render: 3 -> 20 -> 59 mm in frames 94-98, then up to 11 cm). That frame's
// matches innovate about 240 times the run's own level (NIS per dof; reporting.max_innovation_jump
// 50): its frames are lost from there, not posed wrong. Measured here (one sample per pixel): 98
// of 110 posed, at most 19 mm; without the check all 110, 12 of them over 5 cm (up to 96 mm).
TEST(MonoslamTracker, MismatchCarryingThePoseIsReportedLost) {
  MonoslamOptions unchecked;
  unchecked.filter.reporting.max_innovation_jump = 0;
  const RunResult run = expectNoFrameOverFiveCentimetres("board_leaves", 110, 7, 90, unchecked);
  const auto jump = std::find_if(run.results.begin(), run.results.end(), [](const FrameResult& r) {
    return r.reason.find("times the run's innovation level") != std::string::npos;
  });
  EXPECT_NE(jump, run.results.end()) << "the lost frames name the innovation jump";
}

// wall_turn seed 15: turning to the other wall, monoslam measures the four or five features left
// a frame while its pose drifts 4-5 mm a frame, every match consistent with it. Its position std
// passes 3 cm (reporting.max_position_sigma) before the error passes 5 cm; 5 cm came after it
// (full render: 84 frames over 5 cm, up to 15 cm, before session 27). Measured here (one sample
// per pixel, 115 frames): worst 30 mm, 95 frames posed; at 5 cm 59 mm, 108 posed.
TEST(MonoslamTracker, TurningAwayIsLostBeforeFiveCentimetres) {
  MonoslamOptions loose;
  loose.filter.reporting.max_position_sigma = 0.05;
  expectNoFrameOverFiveCentimetres("wall_turn", 115, 15, 85, loose);
}

// Each posed frame's orientation error (degrees) in the first posed camera's frame, as
// `slamcmp eval --align origin` measures a board-free run.
std::vector<double> turnErrorsDeg(const std::string& path, const RunResult& run) {
  const Sequence seq = openSequence(path);
  std::optional<Mat3> R_gt0, R_est0;
  std::vector<double> errors;
  for (int i = 0; i < run.frames; ++i) {
    if (!run.results[i].T_world_camera) continue;
    const Mat3 R_gt = (*seq.groundtruth)[i].T_world_camera.R(), R_est = run.results[i].T_world_camera->R();
    if (!R_gt0) R_gt0 = R_gt, R_est0 = R_est;
    errors.push_back(rotationAngle((R_gt0->transpose() * R_gt).transpose() * (R_est0->transpose() * R_est)) * 180 /
                     M_PI);
  }
  return errors;
}

// The worst of them.
double worstTurnErrorDeg(const std::string& path, const RunResult& run) {
  const std::vector<double> errors = turnErrorsDeg(path, run);
  return errors.empty() ? 0.0 : *std::max_element(errors.begin(), errors.end());
}

// Board-free, wall_turn seed 32 (rendered as the full render, which this reproduces): as the
// camera reaches the other wall and starts along it, the filter keeps turning with 11-12 matches a
// frame that agree with it, 24 degrees too far by frame 125 (NEES 600). The matches' NIS per dof
// against the prior climbs from the run's 0.01 to 0.66 by frame 88, and the innovation jump
// (reporting.max_innovation_jump) marks the frames lost from there at 1 degree off, until the
// relocalisation finds the map again on the way back. It relocalises against, and resumes from, the
// map as it was in the last posed frame: the lost frames' own updates had moved it, and the
// relocalised frames were up to 4.9 degrees off (2.2 then). Here (230 frames) its first
// relocalisation, at frame 187, rested on 6 PnP inliers, two of them inverse-depth features
// uncertain by 6-7 px where they project, and was 0.15 units (7 % of the depth) off: the run's
// Sim(3) ATE 5.4 mm. Counting only the inliers known to within the inlier test, it relocalises at
// frame 200 (9 inliers, 6 of them counted: just min_inliers) and the ATE is 3.9 mm, within twice
// the board-started run's 2.06 (issue 18's target; the full render: 4.4 -> 3.1 mm against 1.85).
TEST(MonoslamTracker, BoardFreeTurningTooFarIsReportedLostAndRelocalised) {
  test::TempDir dir;
  // As the full render is anti-aliased: at one sample per pixel the filter turns right.
  renderFast("wall_turn", 230, dir.path(), 32, SynthOptions{}.supersample);
  const RunResult run = runTracker(dir.path(), InitSource::None, std::nullopt);
  EXPECT_GE(run.tracked, 110);
  EXPECT_LT(worstTurnErrorDeg(dir.path(), run), 3.0);
  const RunResult board = runTracker(dir.path(), InitSource::Board, std::nullopt);
  EXPECT_LT(sim3Ate(dir.path(), run), 2 * sim3Ate(dir.path(), board));
  const auto jump = std::find_if(run.results.begin(), run.results.end(), [](const FrameResult& r) {
    return r.reason.find("times the run's innovation level") != std::string::npos;
  });
  EXPECT_NE(jump, run.results.end()) << "the lost frames name the innovation jump";
  const auto relocalised = std::find_if(run.results.begin(), run.results.end(), [](const FrameResult& r) {
    return r.reason.find("relocalised against the map") != std::string::npos;
  });
  ASSERT_NE(relocalised, run.results.end());
  EXPECT_GT(relocalised - run.results.begin(), 150) << "found again on the way back";
  MonoslamOptions unchecked;
  unchecked.filter.reporting.max_innovation_jump = 0;
  const RunResult posed = runTracker(dir.path(), InitSource::None, std::nullopt, 130, unchecked);
  EXPECT_EQ(posed.tracked, 130);
  EXPECT_GT(worstTurnErrorDeg(dir.path(), posed), 10.0) << "what the check keeps out of the trajectory";
}

// handheld_rpy (30 fps, up to 80 degrees/s, as tum_fr1_rpy) through a 30 ms rolling shutter,
// board-free with the README's hand-held options. Read as a global shutter the filter turns 4-18 %
// too far (full renders, seeds 1-4: 3.8-5.6 degrees RMSE); searched where each row is read
// (search.rolling_shutter_readout), 1.4-2.4 degrees. Measured here (250 frames, one sample per
// pixel): 4.10 against 1.67 degrees.
TEST(MonoslamTracker, RollingShutterReadoutKeepsAHandHeldTurn) {
  test::TempDir dir;
  renderFast("handheld_rpy", 0, dir.path(), 1, 1, 0.03);
  MonoslamOptions hand_held = loadMonoslamOptions(kHandheldConfig);
  hand_held.two_view_orientation.enabled = false;
  const RunResult global = runTracker(dir.path(), InitSource::None, std::nullopt, -1, hand_held);
  hand_held.filter.search.rolling_shutter_readout = 0.03;
  const RunResult rolling = runTracker(dir.path(), InitSource::None, std::nullopt, -1, hand_held);
  const std::vector<double> global_errors = turnErrorsDeg(dir.path(), global);
  const std::vector<double> rolling_errors = turnErrorsDeg(dir.path(), rolling);
  EXPECT_EQ(rolling.tracked, 250);
  std::printf("orientation RMSE: read as a global shutter %.2f deg (%d posed), row by row %.2f deg (%d posed)\n",
              computeStatistics(global_errors).rmse, global.tracked, computeStatistics(rolling_errors).rmse, rolling.tracked);
  EXPECT_LT(computeStatistics(rolling_errors).rmse, 3.0);
  EXPECT_LT(computeStatistics(rolling_errors).rmse, 0.6 * computeStatistics(global_errors).rmse);
}

// handheld_rpy (global shutter) board-free with configs/monoslam_handheld.yaml: the tracks, the
// two-view rotations and their update run every frame. The render's filter does not over-turn
// (0.04 degrees RMSE over the full render), and the two-view rotations, over a scene that is mostly
// the board's wall, cost it accuracy (0.15 degrees; 0.43 with the LK pyramid's third level):
// README. Measured here (120 frames, one sample per pixel): 116 posed, 4 frames lost to innovation
// jumps (NIS per dof 1.7-2.2 against the run's own level of 0.01-0.02), 0.16 degrees RMSE, at most
// 1.4 (with the third level: 120 posed, 0.58 degrees, at most 3.7).
TEST(MonoslamTracker, TwoViewOrientationFollowsAHandHeldTurn) {
  test::TempDir dir;
  renderFast("handheld_rpy", 120, dir.path());
  const MonoslamOptions options = loadMonoslamOptions(kHandheldConfig);
  ASSERT_TRUE(options.two_view_orientation.enabled);
  const RunResult run = runTracker(dir.path(), InitSource::None, std::nullopt, -1, options);
  EXPECT_GE(run.tracked, 114);
  // Its cost is timed as a stage of its own in every frame after the first.
  const int timed = static_cast<int>(std::count_if(run.results.begin(), run.results.end(), [](const FrameResult& r) {
    return std::any_of(r.stages.begin(), r.stages.end(), [](const auto& s) { return s.first == "two_view"; });
  }));
  EXPECT_EQ(timed, run.frames - 1);
  const Statistics errors = computeStatistics(turnErrorsDeg(dir.path(), run));
  std::printf("%d posed, orientation RMSE %.3f deg, at most %.3f\n", run.tracked, errors.rmse, errors.max);
  EXPECT_LT(errors.rmse, 0.5);
}

// The two-view orientation is a board-free run's: with a board it is refused, not ignored.
TEST(MonoslamTracker, TwoViewOrientationWithABoardIsRefused) {
  TrackerContext context;
  context.camera = CameraModel::fromOpenCV(
      (cv::Mat_<double>(3, 3) << 500, 0, 319.5, 0, 500, 239.5, 0, 0, 1), cv::Mat::zeros(1, 5, CV_64F), {640, 480});
  context.target = ChessboardTarget{9, 6, 0.04};
  MonoslamOptions options;
  options.two_view_orientation.enabled = true;
  EXPECT_THROW(MonoslamTracker(context, options), InputError);
  context.init = InitSource::None;
  EXPECT_NO_THROW(MonoslamTracker(context, options));
  options.two_view_orientation.lk_window_px = 4;
  EXPECT_THROW(options.two_view_orientation.check(), OptionError);
  options.two_view_orientation.lk_window_px = 21;
  options.two_view_orientation.sigma_deg = 0;
  EXPECT_THROW(options.two_view_orientation.check(), OptionError);
  options.two_view_orientation.sigma_deg = 0.2;
  EXPECT_THROW(options.two_view_orientation.checkImage(cv::Size(20, 20)), OptionError);
}

// wall_turn seed 1: lost facing the other wall (too few measurements), the filter restarts from
// the board when the board is wholly back. The first frame of the return gives the restart its
// motion (the camera is still turning, 0.4 rad/s, which a restart taken for still would not
// follow); from the next every frame is posed. Measured: 1.0-3.1 mm over frames 195-229 (before
// session 27 a board-started filter, once lost, stayed lost to the end).
TEST(MonoslamTracker, RestartsFromTheBoardWhenItReturns) {
  test::TempDir dir;
  renderFast("wall_turn", 230, dir.path(), 1);
  const Sequence seq = openSequence(dir.path());
  const std::vector<Vec3> corners = seq.target->cornersWorld();
  const RunResult run = runTracker(dir.path(), InitSource::Board, std::nullopt);
  ASSERT_EQ(run.frames, 230);
  int returned = -1;  // the first frame with the whole board in view after frames with none
  bool gone = false;
  for (int i = 0; i < run.frames && returned < 0; ++i) {
    const int in_view = boardCornersInView(*seq.camera, corners, (*seq.groundtruth)[i].T_world_camera);
    gone = gone || in_view == 0;
    if (gone && in_view == static_cast<int>(corners.size())) returned = i;
  }
  ASSERT_GT(returned, 0);
  EXPECT_FALSE(run.results[returned - 1].T_world_camera) << "lost facing the other wall";
  EXPECT_FALSE(run.results[returned].T_world_camera);
  EXPECT_NE(run.results[returned].reason.find("the restart waits for the next frame's view"), std::string::npos)
      << run.results[returned].reason;
  EXPECT_EQ(run.results[returned + 1].source, "board");  // the restart's pose
  EXPECT_EQ(run.results[returned + 2].source, "ekf");
  for (int i = returned + 1; i < run.frames; ++i) {
    ASSERT_TRUE(run.results[i].T_world_camera) << "frame " << i << ": " << run.results[i].reason;
    EXPECT_LT((run.results[i].T_world_camera->t() - (*seq.groundtruth)[i].T_world_camera.t()).norm(), 0.01)
        << "frame " << i;
  }
}

TEST(MonoslamTracker, RealVamrCheckerboardFirst150Frames) {
  SLAMCMP_REQUIRE_SHARED(shared);
  const RunResult run = runTracker(shared + "/vamr_checkerboard", InitSource::Board, std::nullopt, 150);
  EXPECT_GE(run.tracked, 0.95 * run.frames);
  EXPECT_LT(run.ateRmse(), 0.03);
}

// tum_fr1_rpy board-free: a run's summary, and its orientation error without any fit. A board-free
// run's world frame is its first camera's, so the ground truth there is R_gt(first)^T R_gt (a
// position-only Sim(3) leaves the rotation of a turn on the spot ill-determined). A relocalised
// frame is held to it like any other.
struct TumRun {
  nlohmann::json summary;
  double rms_deg = 0, worst_deg = 0;
};

TumRun runOnTumFr1Rpy(const std::string& sequence, const std::string& options) {
  const Trajectory groundtruth = readTrajectory(sequence + "/groundtruth.txt", TrajectoryFormat::Tum);
  test::TempDir out;
  const test::CommandResult r = test::runSlamcmp("run --backend monoslam --init none --sequence '" + sequence +
                                                 "' --out '" + out.path() + "' --config '" + kHandheldConfig +
                                                 "' " + options);
  TumRun run;
  if (r.exit_code != 0) {
    ADD_FAILURE() << r.err;
    return run;
  }
  std::ifstream in(out.file("summary.json"));
  run.summary = nlohmann::json::parse(in);
  EXPECT_EQ(run.summary["frames"], 250);
  EXPECT_EQ(run.summary["tracked"].get<int>() + run.summary["lost"].get<int>() +
                run.summary["initialising"].get<int>(),
            250);
  EXPECT_EQ(run.summary["alignment"], "sim3");
  EXPECT_GT(run.summary["scale"].get<double>(), 0.0);
  // Never a made-up pose: trajectory.txt holds exactly the posed frames.
  const Trajectory estimate = readTrajectory(out.file("trajectory.txt"), TrajectoryFormat::Tum);
  if (estimate.size() != run.summary["tracked"].get<size_t>()) {
    ADD_FAILURE() << "trajectory.txt holds " << estimate.size() << " poses";
    return run;
  }
  const PosePairs pairs = associateByTime(groundtruth, estimate, 0.01);
  if (pairs.size() == 0 || pairs.estimate.front() != 0u) {
    ADD_FAILURE() << "the first frame is not posed";
    return run;
  }
  const Mat3 R_first = groundtruth[pairs.groundtruth.front()].T_world_camera.R();
  double sum2 = 0;
  for (size_t k = 0; k < pairs.size(); ++k) {
    const Mat3 R_gt = R_first.transpose() * groundtruth[pairs.groundtruth[k]].T_world_camera.R();
    const double e = rotvecFromRotation(R_gt.transpose() * estimate[pairs.estimate[k]].T_world_camera.R()).norm();
    sum2 += e * e;
    run.worst_deg = std::max(run.worst_deg, e * 180 / M_PI);
  }
  run.rms_deg = std::sqrt(sum2 / pairs.size()) * 180 / M_PI;
  return run;
}

std::string seedOption(int seed) { return " --set monoslam.feature_init.seed=" + std::to_string(seed); }

// Issue 18's real sequence: TUM RGB-D fr1_rpy (250 frames, handheld Kinect, 40-170 degrees/s of
// rotation, motion capture), run as a user runs it: `slamcmp run --init none`, with the motion
// noise of a hand-held camera at 30 Hz (sigma_alpha 12 rad/s^2; the default 3 suits the 10 fps
// presets) and Civera's feature management (25 features kept visible, 30 measured a frame, judged
// after 5 attempts). Which frames a run keeps through the 170 degrees/s burst near frame 113 turns
// on the features it holds there, so single seeds come and go with any change to where features
// start: seeds 0-3 are held together. Measured: 250 / 248 / 245 / 250 frames posed (seeds 1 and 2
// lost in frames 116-117 and 110-114 and relocalised), orientation error against the ground truth
// RMSE 5.7 / 6.2 / 3.4 / 5.9 degrees, at most 10.0 / 13.7 / 6.2 / 8.5, Sim(3) ATE 4.9 / 4.6 / 4.1 /
// 4.2 cm: 993 of 1000 frames. Seed 2 is found again only by the points of features deleted before
// its loss (relocalisation.retired_points; with none: lost from frame 114 on, 114 frames posed, 862
// of 1000). (Before new features avoided look-alikes, feature_init.distinct: 250 / 250 / 250 / 121,
// 3.7 / 6.2 / 5.4 / 6.2, at most 6.0 / 11.1 / 8.9 / 13.5, 3.9 / 4.5 / 3.8 / 3.5 cm.)
// Not met: the 2 degrees and 3 cm (the filter turns about 6 % more than the ground truth
// on this sequence; synthetic runs turn as their ground truth to 1 %). Lost frames are reported,
// never invented. Seed 2 with motion.sigma_a 8 was once relocalised 180 degrees off (a pose that
// fitted 6 of 10 matches with every one behind the camera); it now loses its orientation in the
// burst instead (15 degrees RMSE, at most 27, not reported lost: README), which the bound lets
// through while a pose turned round would not be.
TEST(MonoslamTracker, RealTumFr1RpyBoardFree) {
  SLAMCMP_REQUIRE_SHARED(shared);
  const std::string sequence = shared + "/tum_fr1_rpy";
  if (!std::filesystem::exists(sequence)) GTEST_SKIP() << sequence << " is absent: skipped";
  const std::string filter_alone = "--set monoslam.two_view_orientation.enabled=0";
  struct Run {
    int seed;
    std::string more_options;
  };
  std::vector<double> rms_deg;
  int posed = 0;
  for (const Run& run : {Run{0, ""}, Run{1, ""}, Run{2, ""}, Run{3, ""}, Run{2, " --set monoslam.motion.sigma_a=8"}}) {
    SCOPED_TRACE("feature_init.seed " + std::to_string(run.seed) + run.more_options);
    const TumRun tum = runOnTumFr1Rpy(sequence, filter_alone + seedOption(run.seed) + run.more_options);
    EXPECT_LE(tum.summary["ate"]["trans"]["rmse"].get<double>(), 0.06);
    EXPECT_LE(tum.worst_deg, run.more_options.empty() ? 15 : 45);
    if (run.more_options.empty()) {
      rms_deg.push_back(tum.rms_deg);
      posed += tum.summary["tracked"].get<int>();
    }
  }
  EXPECT_GE(posed, 950);  // 95 % of the four runs' frames
  EXPECT_LE(median(rms_deg), 7.0);
}

// The same with the orientation also measured by two-view geometry (configs/monoslam_handheld.yaml),
// held to issue 18's targets over seeds 0-7 (which frames a run keeps turns on where its features
// start: one seed is one draw). The filter alone turns 5 % too far (seeds 0-3 5.7, 6.2, 3.4 and 5.9
// degrees RMSE). Measured with the file: 250, 250, 250, 250, 250, 249, 250 and 250 frames posed
// (1999 of 2000), orientation RMSE 1.95, 1.92, 1.65, 2.06, 2.27, 1.68, 1.72 and 1.70 degrees (the
// median 1.82), at most 2.8-4.3, Sim(3) ATE 1.9, 2.2, 2.2, 3.0, 2.6, 3.8, 4.1 and 2.3 cm (the median
// 2.4). The runs are chaotic and these bounds are close to their edges: with
// two_view_orientation.sigma_deg 0.199 instead of 0.2 the median seed is at 3.3 cm and this test
// would fail (docs/findings.md, session 35).
TEST(MonoslamTracker, RealTumFr1RpyTwoViewOrientation) {
  SLAMCMP_REQUIRE_SHARED(shared);
  const std::string sequence = shared + "/tum_fr1_rpy";
  if (!std::filesystem::exists(sequence)) GTEST_SKIP() << sequence << " is absent: skipped";
  std::vector<double> rms_deg, ate;
  int posed = 0;
  for (int seed = 0; seed < 8; ++seed) {
    SCOPED_TRACE("feature_init.seed " + std::to_string(seed));
    const TumRun tum = runOnTumFr1Rpy(sequence, seedOption(seed));
    EXPECT_LE(tum.worst_deg, 6.0);
    rms_deg.push_back(tum.rms_deg);
    ate.push_back(tum.summary["ate"]["trans"]["rmse"].get<double>());
    posed += tum.summary["tracked"].get<int>();
  }
  EXPECT_GE(posed, 1900);  // 95 %
  EXPECT_LE(median(rms_deg), 2.0);
  EXPECT_LE(*std::max_element(rms_deg.begin(), rms_deg.end()), 3.5);
  EXPECT_LE(median(ate), 0.03);
}

// Without a board in view the tracker waits, says why, and never reports a pose.
TEST(MonoslamTracker, NoBoardMeansInitialisingWithAReason) {
  TrackerContext context;
  context.camera = CameraModel::fromOpenCV(
      (cv::Mat_<double>(3, 3) << 500, 0, 319.5, 0, 500, 239.5, 0, 0, 1), cv::Mat::zeros(1, 5, CV_64F), {640, 480});
  context.target = ChessboardTarget{9, 6, 0.04};
  MonoslamTracker tracker(context, MonoslamOptions{});
  cv::Mat noise(480, 640, CV_8U);
  cv::randu(noise, 0, 255);
  for (int i = 0; i < 3; ++i) {
    Frame frame;
    frame.index = i;
    frame.timestamp = 0.1 * i;
    frame.grey = noise;
    const FrameResult r = tracker.track(frame);
    EXPECT_EQ(r.status, TrackStatus::Initialising);
    EXPECT_FALSE(r.T_world_camera.has_value());
    EXPECT_EQ(r.reason, "no board seen");
  }
}

TEST(MonoslamTracker, RefusesContextsItCannotWorkWith) {
  TrackerContext context;
  EXPECT_THROW(MonoslamTracker(context, MonoslamOptions{}), InputError);  // no camera
  context.camera = CameraModel::fromOpenCV(cv::Mat::eye(3, 3, CV_64F), cv::Mat::zeros(1, 5, CV_64F), {640, 480});
  EXPECT_THROW(MonoslamTracker(context, MonoslamOptions{}), InputError);  // no target
  context.target = ChessboardTarget{9, 6, 0.04};
  context.init = InitSource::Manual;
  EXPECT_THROW(MonoslamTracker(context, MonoslamOptions{}), InputError);  // manual without a pose
  context.target.reset();
  context.init = InitSource::None;
  EXPECT_NO_THROW(MonoslamTracker(context, MonoslamOptions{}));  // board-free: no target needed
}

}  // namespace
}  // namespace slamcmp
