#pragma once
// A run scored by what the true camera sees of the board (SPEC section 8; issues 14 and 15's
// targets): while no corner is in view (a gap), the worst error against its allowance; the 30
// frames from the whole board's return against the error with the board long in view; frames
// with part of the board (half of it or more) against frames with all of it. Errors are
// |t - t_true| without alignment: the world frame is the board's for a board-started run.
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/camera.h"
#include "core/target.h"
#include "core/trajectory.h"

namespace slamcmp {

// A board corner is in view when the true pose projects it this far inside the image.
constexpr double kCornerInViewMarginPx = 3.0;
// The frames scored from the whole board's return on.
constexpr int kReturnFrames = 30;

// The board's corners (world) that a camera at T_world_camera sees at least margin_px inside the
// image.
int boardCornersInView(const CameraModel& camera, const std::vector<Vec3>& corners_world, const SE3& T_world_camera,
                       double margin_px = kCornerInViewMarginPx);

// The most a frame with no corner in view may be off (issues 14 and 15): 5 mm, or 1 % of the true
// path since the board was last in view if that is more.
double gapAllowanceM(double path_since_board_m);

struct BoardViewFrame {
  int frame = 0;                  // its index in the run (frames.csv's `frame`)
  int corners_in_view = 0;        // by the true pose, through the camera (lens included)
  double step_m = 0;              // the true path since the previous frame
  std::optional<double> error_m;  // |t - t_true|; none when the run did not pose the frame
};

// One frame per entry of frame_timestamps (the run's frames, frame k at frame_timestamps[k]) that
// has a ground-truth pose within max_diff seconds (those without are left out); its error from the
// estimate's pose of that frame (the estimate's timestamp within a quarter of the shortest frame
// interval and max_diff: a lost frame never borrows a neighbour's pose). Throws InputError when
// either trajectory's timestamps go back in time.
std::vector<BoardViewFrame> boardViewFrames(const std::vector<double>& frame_timestamps, const Trajectory& groundtruth,
                                            const Trajectory& estimate, const CameraModel& camera,
                                            const ChessboardTarget& target, double max_diff);

struct BoardGap {
  int first = 0, last = 0;  // its first and last frame (BoardViewFrame::frame)
  int lost = 0;             // frames of the gap the run did not pose
  // At the posed frame worst against its allowance: error / gapAllowanceM(path since the board);
  // NaN when every frame of the gap was lost.
  double worst_error_m = 0, worst_over_allowance = 0;
};

struct BoardVisibilityScores {
  int corners = 0;                 // the board's
  std::vector<BoardGap> gaps;      // runs of frames with no corner in view after one with some
  // The first frame with the whole board in view after the first gap (later returns are not
  // scored), and how many of the kReturnFrames from there the run did not pose.
  std::optional<int> return_frame;
  int after_return_lost = 0;
  // RMS errors (metres, NaN without frames): the posed ones of the kReturnFrames from
  // return_frame; frames with the whole board in view and within 30 frames of none without it,
  // after the first 10 (settled); frames with half the corners or more in view but not all
  // (partial; returning_partial: those after a gap), and with all (whole).
  double after_return_rms = 0, settled_rms = 0, partial_rms = 0, returning_partial_rms = 0, whole_rms = 0;
  int partial_frames = 0, returning_partial_frames = 0, whole_frames = 0;
};

BoardVisibilityScores scoreBoardVisibility(const std::vector<BoardViewFrame>& frames, int corners);

// {corners, gaps: [{first, last, lost, worst_error, worst_over_allowance}], return_frame,
// after_return_lost, after_return_rms, settled_rms, after_return_over_settled, partial_rms,
// returning_partial_rms, whole_rms, partial_over_whole, partial_frames, returning_partial_frames,
// whole_frames}; a figure that cannot be had is null.
nlohmann::json boardVisibilityToJson(const BoardVisibilityScores& scores);

}  // namespace slamcmp
