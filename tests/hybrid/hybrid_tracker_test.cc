// The hybrid back-end on shortened renders of the presets made for it (the board leaving for a
// long stretch, half the board out of the image, large roll through a strong lens), with the
// targets of its issue as thresholds, and on the real vamr_checkerboard.
#include "hybrid/hybrid_tracker.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <optional>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/camera.h"
#include "core/options.h"
#include "core/sequence.h"
#include "datasets/synth_sequence.h"
#include "eval/metrics/board_visibility.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

using test::TempDir;

// One frame of a run against the ground truth.
struct FrameScore {
  int corners_in_view = 0;  // board corners the true pose puts 3 px inside the image (boardCornersInView)
  std::optional<double> error;  // position error of the reported pose, metres
  // The truth's position less the reported one along the reported camera's optical axis, metres:
  // negative when the camera is put too near what it looks at.
  std::optional<double> depth_error;
  double path_since_board = 0;  // metres the camera travelled since it last saw a corner
  std::string reason;
  double gapAllowance() const { return gapAllowanceM(path_since_board); }
};

struct TrackedRun {
  std::vector<FrameScore> frames;
  int corners = 0;
  bool finish_refused = false;
  double rmsWhere(const std::function<bool(const FrameScore&)>& keep) const {
    double sum = 0;
    int n = 0;
    for (const FrameScore& f : frames)
      if (f.error && keep(f)) {
        sum += *f.error * *f.error;
        ++n;
      }
    return n ? std::sqrt(sum / n) : NAN;
  }
  int posed() const {
    int n = 0;
    for (const FrameScore& f : frames) n += f.error.has_value();
    return n;
  }
  // The first frame from `first` on with the whole board in view; 0 if none.
  size_t wholeBoardFrom(size_t first) const {
    for (size_t i = first; i < frames.size(); ++i)
      if (frames[i].corners_in_view == corners) return i;
    return 0;
  }
};

// One of the project's option files (configs/...), as `slamcmp run --config` reads it.
HybridOptions loadConfig(const std::string& relative) {
  const std::string path = std::string(SLAMCMP_SOURCE_DIR) + "/" + relative;
  const cv::FileStorage fs(path, cv::FileStorage::READ);
  EXPECT_TRUE(fs.isOpened()) << path;
  HybridOptions options;
  if (fs.isOpened()) loadOptions(fs["hybrid"], path, options);
  return options;
}

std::string render(const TempDir& dir, const std::string& preset, int frames) {
  SynthOptions options;
  options.preset = preset;
  options.frames = frames;
  options.supersample = 2;  // under half the rendering time (the presets' 3 is for the figures)
  const std::string out = dir.file(preset);
  writeSyntheticSequence(options, out);
  return out;
}

TrackedRun runOn(const std::string& path, int max_frames = -1, bool with_camera = true,
                 const HybridOptions& options = {}) {
  Sequence seq = openSequence(path);
  TrackerContext context;
  if (with_camera) context.camera = seq.camera;
  context.target = seq.target;
  context.image_size = seq.image_size;
  context.mode = "ekf";
  HybridTracker tracker(context, options);
  const std::vector<Vec3> corners = seq.target->cornersWorld();
  TrackedRun run;
  run.corners = static_cast<int>(corners.size());
  Frame frame;
  double travelled = 0, last_seen = 0;
  std::optional<Vec3> previous;
  for (int i = 0; (max_frames < 0 || i < max_frames) && seq.frames->next(&frame); ++i) {
    const FrameResult r = tracker.track(frame);
    const SE3& truth = seq.groundtruth->at(i).T_world_camera;
    if (previous) travelled += (truth.t() - *previous).norm();
    previous = truth.t();
    FrameScore s;
    s.corners_in_view = boardCornersInView(*seq.camera, corners, truth);
    if (s.corners_in_view > 0) last_seen = travelled;
    s.path_since_board = travelled - last_seen;
    if (r.T_world_camera) {
      EXPECT_TRUE(r.pose_covariance) << "frame " << i;
      s.error = (r.T_world_camera->t() - truth.t()).norm();
      s.depth_error = (r.T_world_camera->R().transpose() * (truth.t() - r.T_world_camera->t())).z();
    } else {
      EXPECT_FALSE(r.reason.empty()) << "frame " << i << ": a frame without a pose says why";
    }
    s.reason = r.reason;
    run.frames.push_back(s);
    for (const LatePose& late : r.late_poses) {  // earlier frames posed once self-calibrated
      EXPECT_LT(late.frame_index, i);
      FrameScore& earlier = run.frames.at(late.frame_index);
      EXPECT_FALSE(earlier.error.has_value()) << "frame " << late.frame_index << " posed twice";
      earlier.error = (late.T_world_camera.t() - seq.groundtruth->at(late.frame_index).T_world_camera.t()).norm();
    }
  }
  try {
    tracker.finish();
  } catch (const InputError&) {
    run.finish_refused = true;
  }
  return run;
}

// Every frame posed while no corner is in view within its gap allowance; returns how many there are.
int expectGapWithinAllowance(const TrackedRun& run) {
  int away = 0;
  for (const FrameScore& f : run.frames) {
    if (f.corners_in_view > 0 || !f.error) continue;
    ++away;
    EXPECT_LE(*f.error, f.gapAllowance());
  }
  return away;
}

// board_leaves, 200 frames: the board in view, 55 degrees away for about 6 s, back. Targets: no
// frame left unposed while the room's features are measured; away, worst error at most 1 % of
// the path since the board was last seen or 5 mm; back, within 5 frames under 1.5 times the
// board-visible error. Measured at this length and supersample 2 with the defaults to session 20
// (cv::cornerSubPix's corners at 0.2 px): about 1 mm in view, 2 mm worst away, 2.6 mm just after
// the return (1.5 mm at supersample 3): the last is held at 3 mm.
void expectBoardLeavesTargets(const TrackedRun& run) {
  const double in_view = run.rmsWhere([&](const FrameScore& f) { return f.corners_in_view == run.corners; });
  EXPECT_LT(in_view, 0.0015);
  const int away = expectGapWithinAllowance(run);
  EXPECT_EQ(run.posed(), 200);
  EXPECT_GT(away, 40);
  // The frames after the return: the first with the whole board back, then five more.
  size_t back = 0;
  for (size_t i = 1; i < run.frames.size(); ++i)
    if (run.frames[i].corners_in_view == run.corners && run.frames[i - 1].corners_in_view == 0) back = i;
  for (size_t i = 1; back == 0 && i < run.frames.size(); ++i)
    if (run.frames[i].corners_in_view > 0 && run.frames[i - 1].corners_in_view == 0) back = i;
  ASSERT_GT(back, 0u);
  for (size_t i = back + 5; i < std::min(run.frames.size(), back + 30); ++i)
    if (run.frames[i].error) {
      EXPECT_LT(*run.frames[i].error, std::max(1.5 * in_view, 0.003)) << "frame " << i;
    }
}

// With the defaults (the tracked features on) over five seeds of the boxes new patch features are
// drawn in: every frame posed, the gap within its allowance (worst 0.42 / 0.46 / 0.47 / 0.50 /
// 0.36 of it; 0.48 / 0.63 / 0.67 / 0.53 / 0.67 with the patch features at SceneLib's 1 px).
TEST(HybridTracker, BoardLeavesAndComesBack) {
  TempDir dir;
  const std::string path = render(dir, "board_leaves", 200);
  for (const int seed : {0, 1, 2, 3, 4}) {
    SCOPED_TRACE("feature_init.seed " + std::to_string(seed));
    HybridOptions options;
    options.filter.feature_init.seed = seed;
    expectBoardLeavesTargets(runOn(path, -1, true, options));
  }
}

// Without the tracked features (configs/hybrid_patches.yaml, the defaults to session 22), whether
// the filter carries on after the last corner hangs on its few young patch features. Seeds 0, 1
// and 3 pose every frame, the gap within its allowance (0.42 / 0.85 / 0.62 of it; 0.56 / 0.94 /
// 0.65 with a new feature started only below 12 visible, SceneLib's and monoslam's). Seeds 2 and
// 4 report all but 2 and 0 of the gap's 65 frames lost (the camera's position std passes 1 cm;
// posed at 5 cm they are 5-6 mm off): what they do pose must be within it too (seed 2's two
// frames 0.88 of it; 1.28 with 12), never a made-up pose.
TEST(HybridTracker, BoardLeavesWithPatchFeaturesOnly) {
  TempDir dir;
  const std::string path = render(dir, "board_leaves", 200);
  const HybridOptions patches = loadConfig("configs/hybrid_patches.yaml");
  ASSERT_FALSE(patches.tracked_motion.enabled);
  for (const int seed : {0, 1, 2, 3, 4}) {
    SCOPED_TRACE("feature_init.seed " + std::to_string(seed));
    HybridOptions options = patches;
    options.filter.feature_init.seed = seed;
    const TrackedRun run = runOn(path, -1, true, options);
    if (seed == 2 || seed == 4) {
      expectGapWithinAllowance(run);
    } else {
      expectBoardLeavesTargets(run);
    }
  }
}

// board_partial, 150 frames: while half the corners or more are in view, as accurate as with the
// whole board (at most 1.3 times; measured 1.13: 0.111 against 0.098 mm; 1.16 without the tracks).
// The corners by gradient orthogonality with their noise estimated and the motion noise adapted
// (since session 21), against cv::cornerSubPix's at a fixed 0.2 px and the motion noise as set
// (the defaults to session 20), both without the tracked features: 0.39 -> 0.11 mm over the run.
// The tracked features add little here with the board in view: they are for the frames without it.
TEST(HybridTracker, PartialBoardIsAsGoodAsTheWholeBoard) {
  TempDir dir;
  const std::string path = render(dir, "board_partial", 150);
  const HybridOptions patches = loadConfig("configs/hybrid_patches.yaml");
  HybridOptions opencv_corners = patches;
  opencv_corners.corners.detector.subpixel.method = "opencv";
  opencv_corners.corners.pixel_sigma = 0.2;
  opencv_corners.corners.noise.enabled = false;
  opencv_corners.filter.motion.adaptive.enabled = false;
  const double before = runOn(path, -1, true, opencv_corners).rmsWhere([](const FrameScore&) { return true; });
  HybridOptions window_alone;
  window_alone.tracked_motion.points.max = 0;
  double without_tracks = 0;
  for (const auto& [name, options] : {std::make_pair("configs/hybrid_patches.yaml", patches),
                                      std::make_pair("the window alone", window_alone),
                                      std::make_pair("the defaults", HybridOptions())}) {
    SCOPED_TRACE(name);
    const TrackedRun run = runOn(path, -1, true, options);
    const double full = run.rmsWhere([&](const FrameScore& f) { return f.corners_in_view == run.corners; });
    const double partial = run.rmsWhere([&](const FrameScore& f) {
      return f.corners_in_view >= run.corners / 2 && f.corners_in_view < run.corners;
    });
    ASSERT_TRUE(std::isfinite(partial));
    EXPECT_LT(full, 0.0005);
    EXPECT_LE(partial, 1.3 * std::max(full, 0.0001));
    const double all = run.rmsWhere([](const FrameScore&) { return true; });
    if (options.tracked_motion.enabled) {
      EXPECT_LT(all, 1.15 * without_tracks);
    } else {
      without_tracks = all;
      EXPECT_LT(all, 0.5 * before);
    }
  }
}

// wall_turn, 240 frames: 12 s facing another wall. The target there is max(5 mm, 1 % of the
// path since the board was last seen). With the defaults (tracks and corners at 0.05 px, the
// corners' noise estimated, four poses in the window, the tracks also without the board, the motion
// noise adapted, the patch features at 0.5 px) every frame is posed, the worst away 0.57 of the
// target (0.80 with the patches at 1 px: held at 0.8 of that), held at 1. Their angular floor at
// 1 rad/s^2 against 0.5: 0.57 against 0.67 (0.80 against 1.01 at 1 px; at 0.5 the prediction lags
// the turn's start as the board leaves), held at 0.95 of it. From the fifth frame after the return
// within 1 mm.
double worstAwayOverTarget(const TrackedRun& run) {
  double worst = 0;
  int away = 0;
  for (size_t i = 0; i < run.frames.size(); ++i) {
    const FrameScore& f = run.frames[i];
    EXPECT_TRUE(f.error) << "frame " << i << ": " << f.reason;
    if (f.corners_in_view > 0 || !f.error) continue;
    ++away;
    worst = std::max(worst, *f.error / f.gapAllowance());
  }
  EXPECT_GT(away, 90);
  return worst;
}

double worstAfterReturn(const TrackedRun& run) {
  const size_t back = run.wholeBoardFrom(100);
  EXPECT_GT(back, 0u);
  double worst = 0;
  for (size_t i = back + 5; back > 0 && i < run.frames.size(); ++i)
    worst = std::max(worst, run.frames[i].error.value_or(INFINITY));
  return worst;
}

TEST(HybridTracker, AnotherWallIsPosedThroughout) {
  TempDir dir;
  const std::string path = render(dir, "wall_turn", 240);
  const HybridOptions defaults;
  ASSERT_EQ(defaults.filter.motion.adaptive.min_sigma_alpha, 1.0);
  HybridOptions half_floor;
  half_floor.filter.motion.adaptive.min_sigma_alpha = 0.5;
  const TrackedRun run = runOn(path, -1, true, defaults);
  const double away = worstAwayOverTarget(run);
  EXPECT_LE(away, 1.0);
  EXPECT_LT(away, 0.95 * worstAwayOverTarget(runOn(path, -1, true, half_floor)));
  ASSERT_EQ(defaults.filter.search.pixel_sigma, 0.5);
  HybridOptions patches_at_1px;
  patches_at_1px.filter.search.pixel_sigma = 1.0;
  EXPECT_LT(away, 0.8 * worstAwayOverTarget(runOn(path, -1, true, patches_at_1px)));
  EXPECT_LT(worstAfterReturn(run), 0.001);
  // The board coming back into view, corner by corner: from half its corners on, as accurate as
  // the whole board (issue 14's "wholly or in part"; 1.3 times, issue 15's measure). Measured
  // 0.09-0.15 mm against 0.20 over the whole-board frames; 1.9-3.1 mm when the corners were
  // refined at their predictions only under 0.3 squares (3 sigma): the board waited to be whole.
  const double in_view = run.rmsWhere([&](const FrameScore& f) { return f.corners_in_view == run.corners; });
  const size_t back = run.wholeBoardFrom(100);
  int partly_back = 0;
  for (size_t i = 100; i < back; ++i)
    if (run.frames[i].corners_in_view >= run.corners / 2 && run.frames[i].error) {
      ++partly_back;
      EXPECT_LT(*run.frames[i].error, 1.3 * in_view) << "frame " << i;
    }
  EXPECT_GE(partly_back, 3);
}

// Without the tracked features (configs/hybrid_patches.yaml) the frames the filter cannot pose well
// are lost, never invented (no reported pose 5 cm off); the board re-anchors it within 5 frames of
// its return. Also with the corners' noise held at 0.06 px (not estimated, 0.01 px on the
// renders): the first corners found again are then far from the drifted prior for their noise,
// where one linearisation missed by 13 cm (the update is iterated, ekf_update.h).
TEST(HybridTracker, AnotherWallWithPatchFeaturesOnlyThenTheBoardAgain) {
  TempDir dir;
  const std::string path = render(dir, "wall_turn", 240);
  const HybridOptions patches = loadConfig("configs/hybrid_patches.yaml");
  HybridOptions held = patches;
  held.corners.noise.enabled = false;
  held.corners.pixel_sigma = 0.06;
  for (const auto& [name, options] : {std::make_pair("configs/hybrid_patches.yaml", patches),
                                      std::make_pair("the corners held at 0.06 px", held)}) {
    SCOPED_TRACE(name);
    const TrackedRun run = runOn(path, -1, true, options);
    for (size_t i = 0; i < run.frames.size(); ++i)
      if (run.frames[i].error) {
        EXPECT_LT(*run.frames[i].error, 0.05) << "frame " << i;
      }
    // Measured 142 and 128 of 240 posed.
    EXPECT_LT(run.posed(), 220) << "frames facing the other wall posed by the patch features alone";
    const size_t back = run.wholeBoardFrom(100);
    ASSERT_GT(back, 0u);
    for (size_t i = back + 5; i < run.frames.size(); ++i) {
      ASSERT_TRUE(run.frames[i].error) << "frame " << i << ": " << run.frames[i].reason;
      EXPECT_LT(*run.frames[i].error, 0.003) << "frame " << i;
    }
  }
}

// Issue 14's in-view target (hybrid within 1.2 times cslam's ATE) with hybrid's defaults (the
// gradient corners with their noise estimated, the motion noise adapted, the tracked features),
// both back-ends run as a user runs them on tv1 and tv2 at 120 frames: measured 0.128 / 0.180 mm
// against cslam's 0.35 / 0.37 (0.135 / 0.192 without the tracks; the defaults to session 20:
// 0.6-0.7 mm on the full presets); held at 0.8 times cslam's. Its NEES too.
TEST(HybridTracker, DefaultsBeatCslamWithTheBoardInView) {
  for (const char* preset : {"tv1", "tv2"}) {
    SCOPED_TRACE(preset);
    TempDir dir;
    SynthOptions synth;
    synth.preset = preset;
    synth.frames = 120;
    synth.supersample = 2;
    const std::string sequence = dir.file("sequence");
    writeSyntheticSequence(synth, sequence);
    const auto summary = [&](const std::string& backend) -> nlohmann::json {
      const std::string out = dir.file(backend);
      const test::CommandResult r =
          test::runSlamcmp("run --backend " + backend + " --sequence '" + sequence + "' --out '" + out + "'");
      EXPECT_EQ(r.exit_code, 0) << r.err;
      if (r.exit_code != 0) return nlohmann::json::object();
      std::ifstream in(out + "/summary.json");
      const nlohmann::json s = nlohmann::json::parse(in);
      EXPECT_EQ(s["tracked"], 120) << backend;
      return s;
    };
    const nlohmann::json cslam = summary("cslam");
    const nlohmann::json hybrid = summary("hybrid");
    if (cslam.empty() || hybrid.empty()) continue;
    const double cslam_ate = cslam["ate"]["trans"]["rmse"], hybrid_ate = hybrid["ate"]["trans"]["rmse"];
    EXPECT_LT(hybrid_ate, 0.8 * cslam_ate) << "hybrid " << hybrid_ate << " m, cslam " << cslam_ate << " m";
    // With its corners' noise estimated (corner_noise.h) the filter is about as sure as it should
    // be: measured 4.33 / 4.89 against 6 (0.22 / 0.36 with the corners held to 0.05 px).
    const double nees = hybrid["nees"]["mean"];
    EXPECT_GT(nees, 3.0);
    EXPECT_LT(nees, 12.0);
  }
}

// tv1 through a long exposure (`synth --blur 3`: the shutter open the whole frame, 80 frames): the
// corners share the shift of an accelerating image's exposure (hybrid/exposure_shift.h), which
// the filter's own noise cannot hold. With the shift's covariance the NEES is 19 (bounds 5.3-6.8;
// the first four frames, before the edges show the blur, give 800 of its 1500), without it
// (max_exposure 0) 84; the error is the same.
TEST(HybridTracker, MotionBlurredCornersShareTheExposuresShift) {
  TempDir dir;
  SynthOptions synth;
  synth.preset = "tv1";
  synth.frames = 80;
  synth.supersample = 2;
  synth.blur = 3;
  const std::string sequence = dir.file("sequence");
  writeSyntheticSequence(synth, sequence);
  const auto summary = [&](const std::string& name, const std::string& extra) -> nlohmann::json {
    const std::string out = dir.file(name);
    const test::CommandResult r =
        test::runSlamcmp("run --backend hybrid --sequence '" + sequence + "' --out '" + out + "'" + extra);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    if (r.exit_code != 0) return nlohmann::json::object();
    std::ifstream in(out + "/summary.json");
    return nlohmann::json::parse(in);
  };
  const nlohmann::json shared = summary("shared", "");
  const nlohmann::json own = summary("own", " --set hybrid.corners.exposure.max_exposure=0");
  if (shared.empty() || own.empty()) return;
  const double nees_shared = shared["nees"]["mean"], nees_own = own["nees"]["mean"];
  const double ate_shared = shared["ate"]["trans"]["rmse"], ate_own = own["ate"]["trans"]["rmse"];
  std::printf("blurred tv1: NEES %.1f with the shared shift, %.1f without (bounds %.2f-%.2f); ATE %.4f / %.4f mm\n",
              nees_shared, nees_own, static_cast<double>(shared["nees"]["lower"]),
              static_cast<double>(shared["nees"]["upper"]), 1e3 * ate_shared, 1e3 * ate_own);
  EXPECT_LT(nees_shared, 25.0);
  EXPECT_GT(nees_own, 3 * nees_shared);
  EXPECT_NEAR(ate_shared, ate_own, 0.05 * ate_own);
}

// roll_distortion, 100 frames: up to 110 degrees of roll through a strong lens, the board always in
// view (measured 0.084 mm, 0.075 without the tracks; cslam 0.24 mm). The lens bends the squares'
// edges; with the corners refined as if they were straight in the image the board looked 7e-5
// larger than it is, and the camera sat 32 um too near it in every frame, three times its std.
TEST(HybridTracker, LargeRollThroughAStrongLens) {
  TempDir dir;
  const std::string sequence = render(dir, "roll_distortion", 100);
  const TrackedRun run = runOn(sequence);
  EXPECT_EQ(run.posed(), 100);
  EXPECT_LT(run.rmsWhere([](const FrameScore&) { return true; }), 0.001);
  HybridOptions in_image;
  in_image.corners.detector.subpixel.undistorted = false;
  const TrackedRun bent = runOn(sequence, -1, true, in_image);
  const auto mean_depth_error = [](const TrackedRun& r) {
    double sum = 0;
    int n = 0;
    for (const FrameScore& f : r.frames)
      if (f.depth_error) sum += *f.depth_error, ++n;
    return n ? sum / n : NAN;
  };
  // Measured: 0.2 um with the edges taken straight through the lens, -32.2 um in the image.
  const double straight = mean_depth_error(run), leaning = mean_depth_error(bent);
  EXPECT_LT(leaning, -15e-6) << "the bias the lens model removes";
  EXPECT_LT(std::abs(straight), 0.2 * std::abs(leaning));
}

// Without a camera file: initialising while it gathers board views (the first 150 frames of the
// real vamr_checkerboard, whose handheld tilts give enough distinct views; the presets' steady
// distance gives too few), then calibrated and tracking; the frames that gathered views are posed
// late from their corners, as cslam's (every one of the 200 shows the board; measured 1.14 mm RMS
// over all 200; without the late poses 51 were posed, 1.13 mm).
TEST(HybridTracker, SelfCalibratesWithoutACameraFile) {
  SLAMCMP_REQUIRE_SHARED(shared);
  const TrackedRun run = runOn(shared + "/vamr_checkerboard", 200, false);
  EXPECT_FALSE(run.finish_refused);
  EXPECT_EQ(run.posed(), 200);
  EXPECT_LT(run.rmsWhere([](const FrameScore&) { return true; }), 0.005);
}

// A preset's first frames through a 30 ms rolling shutter.
std::string renderThroughRollingShutter(const TempDir& dir, const std::string& preset, int frames, int seed,
                                        int supersample) {
  SynthOptions options;
  options.preset = preset;
  options.frames = frames;
  options.seed = seed;
  options.rolling_shutter = 0.03;
  options.supersample = supersample;
  const std::string out = dir.file(preset);
  writeSyntheticSequence(options, out);
  return out;
}

// handheld_rpy's roll and tilt (its first 120 frames, supersample 1) through a 30 ms rolling
// shutter. Compared as read, the board's corners (0.01 px) move pixels with the rows and pose the
// camera 76 mm off (RMS; 200 mm at worst); each predicted where the camera is when its row is read,
// the velocities in its Jacobians (configs/hybrid_rolling_shutter.yaml), 2.5 mm (measured; the same
// render through a global shutter, the defaults: 0.5 mm).
TEST(HybridTracker, RollingShutterCornersArePredictedAtTheirRowsTimes) {
  TempDir dir;
  const std::string sequence = renderThroughRollingShutter(dir, "handheld_rpy", 120, 1, 1);
  const auto rms = [](const TrackedRun& run) { return run.rmsWhere([](const FrameScore&) { return true; }); };
  const TrackedRun as_read = runOn(sequence);
  const TrackedRun row_timed = runOn(sequence, -1, true, loadConfig("configs/hybrid_rolling_shutter.yaml"));
  std::printf("hybrid through a 30 ms rolling shutter: corners as read %.1f mm, at their rows' times %.2f mm\n",
              1e3 * rms(as_read), 1e3 * rms(row_timed));
  EXPECT_EQ(row_timed.posed(), 120);
  EXPECT_LT(rms(row_timed), 0.004);
  EXPECT_LT(rms(row_timed), 0.1 * rms(as_read));
}

// wall_turn's turn to the other wall (150 frames, supersample 2) through a 30 ms rolling shutter,
// the defaults with the readout: the tracked features (their points predicted at their rows'
// times, the window's pixels turned back to their frames' times by the angular velocity alone) pose
// every frame away from the board, at most 1.07 times the gap's allowance (measured: 5.3 mm
// against 5 mm; the full render 4.2 mm; its global-shutter render 5.0 mm). Without them
// (configs/hybrid_rolling_shutter.yaml) the patch features alone drift there (to 20 mm) and those
// frames are reported lost.
TEST(HybridTracker, RollingShutterTracksPoseAnotherWall) {
  TempDir dir;
  const std::string sequence = renderThroughRollingShutter(dir, "wall_turn", 150, 2, 2);
  HybridOptions tracks;
  tracks.filter.search.rolling_shutter_readout = 0.03;
  const TrackedRun run = runOn(sequence, -1, true, tracks);
  EXPECT_EQ(run.posed(), 150);
  int away = 0;
  double worst = 0;  // of the error over the allowance
  for (const FrameScore& f : run.frames)
    if (f.corners_in_view == 0 && f.error) ++away, worst = std::max(worst, *f.error / f.gapAllowance());
  std::printf("through a rolling shutter, %d frames away from the board: at most %.2f times the allowance\n", away, worst);
  EXPECT_GT(away, 30);
  EXPECT_LT(worst, 1.2);
  const TrackedRun patches = runOn(sequence, -1, true, loadConfig("configs/hybrid_rolling_shutter.yaml"));
  EXPECT_LT(patches.posed(), 130);
}

TEST(HybridTracker, TrackedMotionRefusesASnoopingProbabilityOutsideZeroToOne) {
  for (const double p : {-0.1, 1.0, double(NAN)}) {
    TrackedMotionOptions options;
    options.snooping_probability = p;
    EXPECT_THROW(options.check(), OptionError) << p;
  }
  TrackedMotionOptions off;
  off.snooping_probability = 0;
  EXPECT_NO_THROW(off.check());
}

TEST(HybridTracker, NeverStartedIsRefusedAtTheEnd) {
  TrackerContext context;
  context.camera = CameraModel::fromOpenCV(cv::Mat::eye(3, 3, CV_64F) * 500, cv::Mat::zeros(1, 5, CV_64F), {320, 240});
  context.target = ChessboardTarget{9, 6, 0.04};
  context.image_size = {320, 240};
  HybridTracker tracker(context, HybridOptions{});
  Frame frame;
  frame.grey = cv::Mat(240, 320, CV_8UC1, cv::Scalar(128));
  const FrameResult r = tracker.track(frame);
  EXPECT_EQ(r.status, TrackStatus::Initialising);
  EXPECT_FALSE(r.T_world_camera);
  EXPECT_FALSE(r.reason.empty());
  EXPECT_THROW(tracker.finish(), InputError);
}

// vamr_checkerboard (real, handheld; reference poses from the board): as accurate as the board
// allows, 1.5 mm or less.
TEST(HybridTracker, VamrMatchesBoardReference) {
  SLAMCMP_REQUIRE_SHARED(shared);
  const TrackedRun run = runOn(shared + "/vamr_checkerboard", 150);
  EXPECT_GE(run.posed(), 147);
  EXPECT_LT(run.rmsWhere([](const FrameScore&) { return true; }), 0.0015);
}

// The defaults with ten tracked points on vamr_checkerboard's first 300 frames: the
// board is lost at frames 214-219 (a fast tilt) and comes back where the filter, unsure after the
// gap, predicts it about a square off. Refined there, every corner settled on its neighbour and the
// filter held the board one square (40 mm) off for the 500 frames after; the board detector now
// orders the returning corners. Measured: every frame posed, at most 2.4 mm off from frame 225 on
// (42 mm before). With the defaults' 20 points the board comes back nearer its prediction.
TEST(HybridTracker, TakesTheReturningRealBoardCornerForCorner) {
  SLAMCMP_REQUIRE_SHARED(shared);
  HybridOptions options;
  options.tracked_motion.points.max = 10;
  const TrackedRun run = runOn(shared + "/vamr_checkerboard", 300, true, options);
  double worst_after = 0;
  for (size_t i = 225; i < run.frames.size(); ++i)
    if (run.frames[i].error) worst_after = std::max(worst_after, *run.frames[i].error);
  EXPECT_GE(run.posed(), 295);
  EXPECT_LT(worst_after, 0.005);
}

}  // namespace
}  // namespace slamcmp
