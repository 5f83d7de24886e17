// cslam beyond the board (issue 15) on shortened renders of the presets that take the board away:
// wall_turn (12 s facing another wall), board_leaves (a 55-degree pan away) and board_partial (up
// to half the board out of the image). The renders use one sample per pixel (the presets' three
// cost nine times the rendering; the tracking is alike) so that each test stays under ~15 s.
//
// Errors are |t_estimate - t_truth| in the board's frame (no alignment). The targets: while the
// board is away, the worst error at most 1 % of the path since the board was last seen, or 5 mm;
// the board re-acquired in the frame it is wholly back, and over the 30 frames from there an RMS
// error at most 1.2 times that of frames where it has been in view for a while; while half the
// board or more is in the image, an RMS error at most 1.3 times that of the whole board.
#include <cmath>
#include <map>

#include <opencv2/video/tracking.hpp>

#include <gtest/gtest.h>

#include "core/options.h"
#include "core/sequence.h"
#include "cslam/cslam_tracker.h"
#include "datasets/synth_sequence.h"
#include "eval/metrics/board_visibility.h"
#include "tests/test_util.h"
#include "tracking/board_corner_tracker.h"

namespace slamcmp {
namespace {

using test::TempDir;

std::string render(const TempDir& dir, const std::string& preset, int frames) {
  SynthOptions options;
  options.preset = preset;
  options.frames = frames;
  options.supersample = 1;
  const std::string out = dir.file(preset);
  writeSyntheticSequence(options, out);
  return out;
}

struct FrameRecord {
  std::string status;
  std::string reason;
  std::optional<double> error;  // metres
  int corners_in_view = 0;      // by the true pose, 3 px inside the image
  double step = 0;              // true path length since the previous frame, metres
};

// keyframes: when given, combined mode's keyframes as refined by the end of the run.
std::vector<FrameRecord> run(const std::string& path, const std::string& mode = "combined",
                             const CslamOptions& options = {}, std::vector<KeyframePose>* keyframes = nullptr) {
  Sequence seq = openSequence(path);
  CslamTracker tracker(seq.camera, *seq.target, seq.image_size, mode, options);
  const std::vector<Vec3> corners = seq.target->cornersWorld();
  std::vector<FrameRecord> records;
  std::optional<Vec3> last_centre;
  Frame frame;
  while (seq.frames->next(&frame)) {
    const FrameResult r = tracker.track(frame);
    const SE3& truth = (*seq.groundtruth)[records.size()].T_world_camera;
    FrameRecord rec;
    rec.status = statusLabel(r.status, r.source);
    rec.reason = r.reason;
    if (r.T_world_camera) rec.error = (r.T_world_camera->t() - truth.t()).norm();
    rec.corners_in_view = boardCornersInView(*seq.camera, corners, truth);
    if (last_centre) rec.step = (truth.t() - *last_centre).norm();
    last_centre = truth.t();
    EXPECT_EQ(r.T_world_camera.has_value(), r.status != TrackStatus::Lost) << records.size();
    if (r.status == TrackStatus::Lost) {
      EXPECT_FALSE(r.reason.empty()) << records.size();
    }
    records.push_back(rec);
  }
  if (keyframes) *keyframes = tracker.keyframePoses();
  return records;
}

// The run scored as `slamcmp run` scores it (summary.json's board_view).
BoardVisibilityScores scores(const std::vector<FrameRecord>& records) {
  std::vector<BoardViewFrame> frames;
  for (const FrameRecord& r : records)
    frames.push_back({static_cast<int>(frames.size()), r.corners_in_view, r.step, r.error});
  return scoreBoardVisibility(frames, 54);
}

// The gaps: frames not posed from the board after one that was. For each, the worst error over
// the allowance max(1 % of the path since the board, 5 mm), and the frames lost.
struct Gap {
  int first = 0, last = 0;
  double worst_over_allowed = 0;
  double worst_error = 0;
  int lost = 0;
};
std::vector<Gap> gaps(const std::vector<FrameRecord>& records) {
  std::vector<Gap> out;
  bool seen_board = false, in_gap = false;
  double path = 0;
  for (int i = 0; i < static_cast<int>(records.size()); ++i) {
    const FrameRecord& r = records[i];
    if (r.status == "board") {
      seen_board = true;
      in_gap = false;
      path = 0;
      continue;
    }
    if (!seen_board) continue;
    if (!in_gap) out.push_back({i, i}), in_gap = true;
    Gap& g = out.back();
    g.last = i;
    path += r.step;
    if (!r.error) {
      ++g.lost;
      continue;
    }
    const double ratio = *r.error / gapAllowanceM(path);
    if (ratio > g.worst_over_allowed) g.worst_over_allowed = ratio, g.worst_error = *r.error;
  }
  return out;
}

const Gap& longestGap(const std::vector<Gap>& g) {
  return *std::max_element(g.begin(), g.end(),
                           [](const Gap& a, const Gap& b) { return a.last - a.first < b.last - b.first; });
}

// The board re-acquired in the frame it is wholly back, and the RMS error over the 30 frames from
// there at most `factor` times that of frames with the board long in view.
void expectReacquiredWithoutLag(const std::vector<FrameRecord>& records, double factor) {
  const BoardVisibilityScores s = scores(records);
  ASSERT_TRUE(s.return_frame);
  const int back = *s.return_frame;
  ASSERT_LE(back + kReturnFrames, static_cast<int>(records.size()));
  EXPECT_EQ(records[back].status, "board");
  EXPECT_EQ(s.after_return_lost, 0);
  std::printf("30 frames from the return %.3f mm, settled %.3f mm: %.2f\n", 1e3 * s.after_return_rms,
              1e3 * s.settled_rms, s.after_return_rms / s.settled_rms);
  EXPECT_LT(s.after_return_rms, factor * s.settled_rms) << s.after_return_rms << " m against " << s.settled_rms;
}

// board_partial's first 60 frames: up to half the board leaves the image, and boxes in front of
// the wall hide its edge. Every frame is posed, those with half the board or more from the
// board, as accurately as those with all of it (measured: RMS 0.45 mm against 0.44 mm).
TEST(CslamBeyondBoard, PartialBoardAsAccurateAsTheWholeBoard) {
  TempDir dir;
  const std::vector<FrameRecord> records = run(render(dir, "board_partial", 60));
  for (const FrameRecord& r : records) {
    ASSERT_TRUE(r.error.has_value());
    if (2 * r.corners_in_view >= 54 && r.corners_in_view < 54) {
      EXPECT_EQ(r.status, "board");
    }
  }
  const BoardVisibilityScores s = scores(records);
  ASSERT_GT(s.partial_frames, 20);
  ASSERT_GT(s.whole_frames, 10);
  EXPECT_LT(s.partial_rms, 1.3 * s.whole_rms) << s.partial_rms << " m against " << s.whole_rms;
}

// board_leaves' first 210 frames: the pan away (from frame ~88), 8 s without the board, the pan
// back. The gap is posed throughout within 1 % of the path or 5 mm (measured: a fifth of that),
// the board is re-acquired in the frame it is wholly back, and the 30 frames from there are as
// accurate as the board frames well inside its view (target 1.2; measured 0.43, 0.54 when
// written). The pan's frames with half the board or more are as accurate as those with all of it
// (target 1.3, held to 1.0 here; measured 0.82; 1.26 before features tracked astray were dropped
// from the motion).
TEST(CslamBeyondBoard, BoardLeavesGapReturnAndReanchoring) {
  TempDir dir;
  const std::vector<FrameRecord> records = run(render(dir, "board_leaves", 210));
  const std::vector<Gap> g = gaps(records);
  ASSERT_FALSE(g.empty());
  int gap_frames = 0;
  for (const Gap& gap : g) {
    EXPECT_EQ(gap.lost, 0) << gap.first;
    EXPECT_LE(gap.worst_over_allowed, 1.0) << "frames " << gap.first << "-" << gap.last << ": " << gap.worst_error;
    gap_frames += gap.last - gap.first + 1;
  }
  EXPECT_GT(gap_frames, 60);
  expectReacquiredWithoutLag(records, 1.2);
  const BoardVisibilityScores s = scores(records);
  ASSERT_GE(s.partial_frames, 8);
  EXPECT_LT(s.partial_rms, 1.0 * s.whole_rms) << s.partial_rms << " m against " << s.whole_rms;
}

// The re-anchoring itself (issue 15's "correct the gap's keyframes and the map points seen from
// them"), on board_leaves' first 210 frames: once the board is back, the gap's keyframes are
// corrected by a pose graph and, with refinement.refine_gap, then refined with the whole gap, both
// ends held by the board. They end closer to the truth than without the re-anchoring, where they
// keep what the board-less window made of them (measured: RMS 0.54 against 1.03 mm; the pose graph
// alone, the default, 1.03: docs/findings.md, session 45).
TEST(CslamBeyondBoard, ReturningBoardCorrectsTheGapsKeyframes) {
  TempDir dir;
  const std::string path = render(dir, "board_leaves", 210);
  const Sequence seq = openSequence(path);
  const auto& truth = *seq.groundtruth;
  const auto gap_keyframes_rms = [&](bool reanchor) {
    CslamOptions options;
    options.refinement.reanchor = reanchor;
    options.refinement.refine_gap = reanchor;
    std::vector<KeyframePose> keyframes;
    const std::vector<Gap> g = gaps(run(path, "combined", options, &keyframes));
    if (g.empty()) return std::make_pair(0, double(NAN));
    const Gap& longest = longestGap(g);
    double sum = 0;
    int n = 0;
    for (const auto& [frame, T_world_camera] : keyframes) {
      if (frame < longest.first || frame > longest.last) continue;
      sum += (T_world_camera.t() - truth[frame].T_world_camera.t()).squaredNorm();
      ++n;
    }
    return std::make_pair(n, n > 0 ? std::sqrt(sum / n) : double(NAN));
  };
  const auto [n_on, rms_on] = gap_keyframes_rms(true);
  const auto [n_off, rms_off] = gap_keyframes_rms(false);
  std::printf("gap keyframes: %d re-anchored %.3f mm, %d without %.3f mm\n", n_on, 1e3 * rms_on, n_off,
              1e3 * rms_off);
  ASSERT_GE(n_on, 10);
  ASSERT_GE(n_off, 10);
  EXPECT_LT(rms_on, 0.8 * rms_off) << rms_on << " m against " << rms_off;
}

// configs/cslam_gradient.yaml on board_leaves' first 210 frames, against the defaults. The
// gradient corners cut the whole board's error (measured 0.78 -> 0.33 mm RMS) and the returning
// half boards' (0.60 -> 0.49 mm). Since the features keep off the board's corners (session 44)
// the gradient corners alone do better on this render's returning half boards (0.43 mm) than the
// file, which trusts the gap's map only to its drift; over the 55 renders the file's trust still
// wins (returns within 1.2 of the settled error 29 of 49, half boards within 1.3 33 of 55, against
// 18 and 16 without it). The file's 30 frames from the return are within 1.2 times its settled
// error (measured 0.41; 0.37 while the re-anchoring trusted the map as if no drift were left).
TEST(CslamBeyondBoard, GradientCornersAndTheGapsMapTrustedToItsDrift) {
  TempDir dir;
  const std::string path = render(dir, "board_leaves", 210);
  CslamOptions file;
  const std::string config = std::string(SLAMCMP_SOURCE_DIR) + "/configs/cslam_gradient.yaml";
  loadOptions(cv::FileStorage(config, cv::FileStorage::READ)["cslam"], config, file);
  ASSERT_EQ(file.board.detector.subpixel.method, "gradient");
  ASSERT_GT(file.fusion.map_drift_fraction, 0);
  CslamOptions gradient_alone = file;
  gradient_alone.fusion.map_drift_fraction = 0;
  struct Rms {
    double returning_half, whole;
  };
  const auto score = [&](const char* name, const CslamOptions& options, bool hold_return = false) {
    SCOPED_TRACE(name);
    const std::vector<FrameRecord> records = run(path, "combined", options);
    if (hold_return) expectReacquiredWithoutLag(records, 1.2);
    const BoardVisibilityScores s = scores(records);
    EXPECT_GE(s.returning_partial_frames, 4);
    std::printf("%s: returning half boards %.3f mm, whole board %.3f mm\n", name, 1e3 * s.returning_partial_rms,
                1e3 * s.whole_rms);
    return Rms{s.returning_partial_rms, s.whole_rms};
  };
  const Rms defaults = score("defaults", CslamOptions{}), alone = score("gradient alone", gradient_alone),
            with_file = score("the file", file, true);
  EXPECT_LT(with_file.whole, 0.7 * defaults.whole) << with_file.whole << " m against " << defaults.whole;
  EXPECT_LT(with_file.returning_half, 0.9 * defaults.returning_half)
      << with_file.returning_half << " m against " << defaults.returning_half;
  EXPECT_LT(alone.whole, 0.7 * defaults.whole) << alone.whole << " m against " << defaults.whole;
}

// wall_turn's first 232 frames: a 90-degree turn to the right-hand wall (frames 60-90), 9 s along
// it, the turn back (180-210). Every frame of the gap is posed within 1 % of the path or 5 mm
// (measured: 0.39 of that), the board is re-acquired in the frame it is wholly back (194), and
// the 30 frames from there are within 1.2 times the settled error (measured 1.16 in session 45,
// 0.77 when written: thin, see docs/findings.md, session 45; 1.16 also while half a board
// anchored the map at the return).
TEST(CslamBeyondBoard, WallTurnPosedThroughTheGapAndReacquired) {
  TempDir dir;
  const std::vector<FrameRecord> records = run(render(dir, "wall_turn", 232));
  const std::vector<Gap> g = gaps(records);
  ASSERT_FALSE(g.empty());
  const Gap& longest = longestGap(g);
  EXPECT_GT(longest.last - longest.first, 100);
  EXPECT_EQ(longest.lost, 0);
  EXPECT_LE(longest.worst_over_allowed, 1.0) << longest.worst_error;
  expectReacquiredWithoutLag(records, 1.2);
}

// wall_turn's first 232 frames in the modes without a pose while the board is away (calibration:
// the board only): the features' motion carries the board's last view, so the whole image is not
// searched while it puts the board out of view (a search there costs 200 to 400 ms on the
// textured wall), and yet the board is re-acquired in the frame it is wholly back.
TEST(CslamBeyondBoard, CalibrationModeSearchesOnlyWhereTheBoardCanBe) {
  TempDir dir;
  const std::vector<FrameRecord> records = run(render(dir, "wall_turn", 232), "calibration");
  int away = 0, not_searched = 0;
  for (const FrameRecord& r : records) {
    if (r.corners_in_view > 0) continue;
    ++away;
    EXPECT_EQ(r.status, "lost");
    not_searched += r.reason == "no board (searched only where predicted)";
  }
  EXPECT_GT(away, 90);
  // The rest: the frames as the board leaves (the motion model's pose still says it may be in
  // view) and one in search_interval_when_away (30), in case the prediction is wrong.
  EXPECT_GT(not_searched, 0.85 * away) << not_searched << " of " << away;
  const std::optional<int> back = scores(records).return_frame;
  ASSERT_TRUE(back);
  EXPECT_EQ(records[*back].status, "board");
}

// The board tracker keeps the identities of a partial board: on board_partial's first 40
// frames, tracked without any pose, every corner it reports lies within 0.3 px of where the
// truth projects that corner, and at least 8 are reported whenever half the board is in view.
TEST(CslamBeyondBoard, PartialBoardCornersKeepTheirIdentities) {
  TempDir dir;
  Sequence seq = openSequence(render(dir, "board_partial", 40));
  BoardCornerTracker tracker(*seq.target, BoardCornerTrackerOptions{});
  const std::vector<Vec3> corners = seq.target->cornersWorld();
  const cv::Size window(9, 9);
  std::vector<cv::Mat> previous, current;
  Frame frame;
  int k = 0, partial_frames = 0;
  while (seq.frames->next(&frame)) {
    cv::buildOpticalFlowPyramid(frame.grey, current, window, 3);
    const SE3& truth = (*seq.groundtruth)[k++].T_world_camera;
    const auto found = tracker.findCorners(frame.grey, previous, current, window, 3, *seq.camera, nullptr, true);
    std::swap(previous, current);
    const int in_view = boardCornersInView(*seq.camera, corners, truth);
    if (2 * in_view >= static_cast<int>(corners.size())) {
      ASSERT_TRUE(found) << "frame " << k - 1;
      EXPECT_GE(found->ids.size(), 8u);
      partial_frames += in_view < static_cast<int>(corners.size());
    }
    if (!found) continue;
    for (size_t i = 0; i < found->ids.size(); ++i) {
      const Vec2 expected = seq.camera->project(truth.inverse() * corners[found->ids[i]]);
      EXPECT_LT((expected - Vec2(found->uv[i].x, found->uv[i].y)).norm(), 0.3)
          << "frame " << k - 1 << " corner " << found->ids[i];
    }
  }
  EXPECT_GT(partial_frames, 10);
}

// A board predicted two squares off keeps its squares' colours: the predicted search must not
// confirm it under the wrong numbering. On board_partial's frame 0 the board's low-x edge is in
// view (its squares would go on beyond the slipped edge corners); on frames 20-35 the board leaves
// the image at that edge and its corners stop two columns short of the other, whose real edge, in
// view beside them, is the slipped board's margin (confirmed there with 24-42 corners, each 8 cm (two squares) off
// before the squares beyond corners short of an edge were checked). A prediction a few millimetres
// off, the same frames, confirms the right numbering.
TEST(CslamBeyondBoard, PredictedSearchRefusesASlippedBoard) {
  TempDir dir;
  Sequence seq = openSequence(render(dir, "board_partial", 36));
  const std::vector<Vec3> corners = seq.target->cornersWorld();
  Frame frame;
  for (int k = 0; seq.frames->next(&frame); ++k) {
    if (k != 0 && (k < 20 || k % 5 != 0)) continue;
    SCOPED_TRACE("frame " + std::to_string(k));
    const SE3& truth = (*seq.groundtruth)[k].T_world_camera;
    const SE3 slipped = SE3(Mat3::Identity(), Vec3(-2 * seq.target->square_size, 0, 0)) * truth;
    BoardCornerTracker tracker(*seq.target, BoardCornerTrackerOptions{});
    const auto wrong = tracker.findCorners(frame.grey, {}, {}, cv::Size(9, 9), 3, *seq.camera, &slipped, false);
    EXPECT_FALSE(wrong);
    if (wrong) {
      for (size_t i = 0; i < wrong->ids.size(); ++i)
        EXPECT_LT((seq.camera->project(truth.inverse() * corners[wrong->ids[i]]) - Vec2(wrong->uv[i].x, wrong->uv[i].y))
                      .norm(),
                  0.5)
            << "corner " << wrong->ids[i] << " reported under another's identity";
    }
    const SE3 drifted = truth * SE3::fromRotvec(Vec3(0.002, -0.0025, 0.001), Vec3(0.002, -0.0015, 0.0015));
    BoardCornerTracker again(*seq.target, BoardCornerTrackerOptions{});
    const auto right = again.findCorners(frame.grey, {}, {}, cv::Size(9, 9), 3, *seq.camera, &drifted, false);
    ASSERT_TRUE(right);
    EXPECT_EQ(again.lastFound(), BoardFound::Predicted);
    EXPECT_GE(right->ids.size(), 24u);
    for (size_t i = 0; i < right->ids.size(); ++i)
      EXPECT_LT(
          (seq.camera->project(truth.inverse() * corners[right->ids[i]]) - Vec2(right->uv[i].x, right->uv[i].y)).norm(),
          0.3);
  }
}

}  // namespace
}  // namespace slamcmp
