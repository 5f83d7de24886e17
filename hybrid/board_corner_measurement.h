#pragma once
// Every board corner measured on its own, as a known landmark of the EKF (SPEC section 8): each
// corner the filter predicts in the image is tracked by Lucas-Kanade from the previous frame,
// or refined at the pixel the filter predicts when its search region is smaller than a square, or
// found by a board search in the region where the filter predicts the board (the frame the board
// comes back). Each measurement is gated by its own innovation covariance, and the set by a
// homography of the board plane, so a corner one square off never reaches the update.
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/chessboard.h"
#include "core/target.h"
#include "ekf/ekf_options.h"
#include "ekf/ekf_state.h"
#include "ekf/ekf_update.h"
#include "ekf/measurement_model.h"
#include "hybrid/corner_noise.h"
#include "hybrid/exposure_shift.h"
#include "tracking/board_presence.h"

namespace slamcmp {

struct BoardCornerMeasurementOptions {
  // Pixels, a corner's measurement noise: the start of the estimate (noise) from the first frames.
  // The gradient corners lie 0.006-0.013 px from the truth on the renders, about 0.1 px on vamr.
  double pixel_sigma = 0.05;
  double gate = 0.9999;              // chi-square (2 dof) probability of a corner's innovation gate
  int lk_window_px = 11;             // Lucas-Kanade window side, pixels
  int lk_levels = 3;                 // pyramid levels above the image
  double max_track_disagreement_px = 0.5;  // the two tracks of a corner (from its prediction, from its last place) must agree, pixels
  // Refine a corner at its prediction when the prediction's 3-sigma half axis is under this many
  // squares: a start a square off is then 6 sigma away, outside the gate (4.3 sigma at 0.9999).
  // The board coming back into view after a gap is then measured corner by corner as it enters
  // (wall_turn: 3 sigma 0.46 squares there, the error 0.04), where 0.3 waited for the whole board
  // and its search: wall_turn seeds 1-10, frames with half the board or more in view, 0.42-1.28
  // -> 0.14-0.28 mm; board_leaves 1-7 0.20-0.66 -> 0.17-0.27; vamr the same (1.1658 mm). 0.5 is
  // the most check() takes.
  double max_predicted_search = 0.5;
  double max_plane_error_px = 1.5;   // corners off the board plane's homography by more are dropped, pixels
  int min_corners = 6;               // fewer corners kept: none is used this frame
  // Grey levels a tracked corner's neighbourhood must span in this frame: a blank or washed-out
  // frame's corners stayed at their predictions and were measured there (tv1 with five black
  // frames: all posed as `board`, 54 corners each).
  double min_corner_contrast = 16;
  int search_interval = 5;           // while the board is not seen where predicted, a full search every this many frames
  // m, its square added to the camera's position variance when a found board disagrees with the filter
  double reanchor_position_sigma = 0.02;
  double reanchor_orientation_sigma = 0.02;  // per quaternion component, likewise
  int border_px = 6;                 // corners predicted closer to the image border (or to its refinement window) are not measured
  CornerNoiseOptions noise;          // pixel_sigma estimated from the corners' scatter about the board plane
  ExposureShiftOptions exposure;     // the shift all corners share in a motion-blurred frame
  // The corners by gradient orthogonality (core/subpixel_corner.h): cv::cornerSubPix leans up to
  // 0.05 px towards the nearest half pixel, the same in every frame, which a filter that weighs
  // the corners as they scatter cannot average out.
  ChessboardDetectorOptions detector = [] {
    ChessboardDetectorOptions d;
    d.subpixel.method = "gradient";
    return d;
  }();
  BoardPresenceOptions presence;     // the quick test before each board search, once the board has been seen
  template <class V>
  void visit(V& v) {
    v("pixel_sigma", pixel_sigma, "pixels, measurement noise of a board corner (where the estimate starts when noise.enabled)");
    v("gate", gate, "chi-square (2 dof) probability of each corner's innovation gate");
    v("lk_window_px", lk_window_px, "Lucas-Kanade window side for tracking corners, pixels");
    v("lk_levels", lk_levels, "Lucas-Kanade pyramid levels above the image");
    v("max_track_disagreement_px", max_track_disagreement_px,
      "a corner is tracked from its predicted and from its last pixel; the two must agree this closely, pixels");
    v("max_predicted_search", max_predicted_search,
      "a corner is refined at its predicted pixel when its 3-sigma half axis is under this many squares");
    v("max_plane_error_px", max_plane_error_px,
      "corners farther than this from the board plane's homography through the others are dropped, pixels");
    v("min_corners", min_corners, "fewer corners kept: the board is not used in this frame");
    v("min_corner_contrast", min_corner_contrast,
      "grey levels a tracked corner's neighbourhood must span in this frame to be measured (a blank frame's span none)");
    v("search_interval", search_interval,
      "while the board is not where the filter predicts it, the whole image is searched every this many frames");
    v("reanchor_position_sigma", reanchor_position_sigma,
      "m, its square added to the camera's position variance when a board found by a search disagrees with the "
      "filter (then it restarts)");
    v("reanchor_orientation_sigma", reanchor_orientation_sigma,
      "per quaternion component, its square added likewise");
    v("border_px", border_px, "corners predicted closer than this to the image border are not measured, pixels");
    v("noise", noise, "the corners' noise estimated from their scatter about the board plane");
    v("exposure", exposure, "the shift every corner of a motion-blurred frame shares while the camera accelerates");
    v("detector", detector, "the board search where the filter predicts the board");
    v("presence", presence, "the quick test (X-junctions) before each search for the whole board");
  }
  void check() const;
  void checkImage(cv::Size image) const;  // the window and the border fit in the image
};

// The corners of `ids` (SPEC order: id = j * cols + i) checked first for a tracking start a square
// off: the extremes of i, j, i + j and i - j among them, on the hull of the tracked part of the
// board, where the start error of a pose error (nearly affine over the board) is largest; at most
// 8, each once.
std::vector<int> spotCheckCorners(const std::vector<int>& ids, int cols);

// A board found by a search is measured only when this fraction of its corners fits the filter's
// gates: a few that happen to lie near a drifted prediction (wall_turn seed 2's return with the
// gradient corners: 9 of 54, one column and a row's end) pulled the camera 17 cm off where the
// board's own pose is right.
constexpr double kMinFoundCornersFitting = 0.5;

struct BoardCornerMeasurement {
  std::vector<PointObservation> observations;  // offset kKnownPoint; z and h per kept corner
  std::vector<int> corner_ids;                 // the corner index (SPEC order) of each observation
};

class BoardCornerMeasurer {
 public:
  // rolling_shutter_readout (s, ActiveSearchOptions'): each corner is predicted where its row is
  // read (ekf/rolling_shutter.h's predictAtRowTime); 0, a global shutter.
  BoardCornerMeasurer(const CameraModel& camera, const ChessboardTarget& target,
                      const BoardCornerMeasurementOptions& options, double rolling_shutter_readout = 0);

  // The corners measured in `grey` given the filter's prior `state` (not changed). Remembers what
  // it kept for the next frame's tracking.
  BoardCornerMeasurement measure(const EkfState& state, const cv::Mat& grey);
  // After the update with measure()'s corners: the corners that entered the image or were not
  // tracked, refined at the pixels the updated filter predicts (now well under a square away).
  BoardCornerMeasurement measureNew(const EkfState& state, const cv::Mat& grey);
  // The corners of a board detection (SPEC order, distorted pixels), gated against the prior.
  BoardCornerMeasurement measureDetected(const EkfState& state, const cv::Mat& grey,
                                         const std::vector<cv::Point2f>& uv_distorted);
  // The filter updated with `m`'s corners, iterated to convergence (ekf_update.h: a board found
  // again after a drift is far from the prior); m's predictions then are the updated state's.
  // The shift a blurred frame's corners share is one per frame: a second update in the frame (the
  // corners entering the view) takes their common part as spent, discarded.
  bool update(EkfState& state, BoardCornerMeasurement* m);
  // Forget the tracked corners (a restart).
  void reset();
  // The filter restarted from the board: the corners' last frames tell no acceleration (a
  // symmetric board's ids may have turned).
  void restart() {
    reset();
    exposure_.forgetFrames();
  }
  // The frame's board measurements are done: its corners kept go to the exposure shift's history.
  void endFrame(double timestamp, const cv::Mat& grey) {
    exposure_.addFrame(timestamp, grey, target_.cols, tracked_ids_, tracked_uv_);
    shift_spent_ = false;
  }
  // With a rolling shutter, the motion noise of this frame's prediction: the corners' noise is then
  // at least rollingShutterPixelSigma's (their rows' times predicted under constant velocities).
  void setMotionNoise(const MotionModelOptions& motion);
  // The whole board anywhere in `grey` (SPEC order, distorted pixels), empty if none; skipped
  // where the presence test rules it out (tracking/board_presence).
  std::vector<cv::Point2f> searchWholeImage(const cv::Mat& grey);
  // The whole board (SPEC order, distorted pixels) that the last measure() detected where the
  // filter predicts it with fewer than kMinFoundCornersFitting of its corners inside their gates
  // (then none is measured), else empty: the prediction, not the board, was wrong. reset()
  // leaves it.
  const std::vector<cv::Point2f>& boardOutsideGates() const { return outside_gates_; }
  // The Lucas-Kanade pyramid of the image last measured (measure, measureDetected), for other
  // trackers of the same frame.
  const std::vector<cv::Mat>& pyramid() const { return pyramid_prev_; }
  cv::Size lkWindow() const { return cv::Size(options_.lk_window_px, options_.lk_window_px); }
  int lkLevels() const { return options_.lk_levels; }

 private:
  struct CornerPrediction {
    bool in_image = false;
    PointMeasurement h;
    Mat2 S = Mat2::Identity();
    double half_axis_px = 0;  // 3-sigma half axis of S
    double square_px = 0;     // the square's side near this corner, pixels
  };
  std::vector<CornerPrediction> predict(const EkfState& state, const cv::Mat& grey) const;
  // The corners' noise now: the estimate (CornerNoise), at least rolling_shutter_sigma_.
  double pixelSigma() const;
  int refineHalfWindow(double square_px) const;
  // Corner `id` measured at z (prediction h) goes to the update and is tracked into the next frame.
  void use(int id, const Vec2& z, const PointMeasurement& h, BoardCornerMeasurement* out);
  // The measurement within the corner's innovation gate (chi-square, 2 dof, options_.gate).
  bool withinGate(const CornerPrediction& p, const Vec2& measured) const;
  // The board detected in the region where the filter predicts it, its corners gated as keep()
  // does; nothing when the detector found none.
  std::optional<BoardCornerMeasurement> searchPredicted(const std::vector<CornerPrediction>& pred,
                                                        const cv::Mat& grey, double square_px);
  // A board detection in the region where the filter predicts the board; empty if none.
  std::vector<cv::Point2f> searchPredictedRegion(const std::vector<CornerPrediction>& pred, const cv::Mat& grey,
                                                 double square_px);
  // The corners tracked by Lucas-Kanade from the last frame (its pyramid) into this one (`pyramid`),
  // appended to ids and uv (distorted pixels): those whose starts at the prediction and at the last
  // pixel agree.
  void trackCorners(const std::vector<CornerPrediction>& pred, const std::vector<cv::Mat>& pyramid,
                    std::vector<int>* ids, std::vector<cv::Point2f>* uv) const;
  // Appends the corners not tracked that the filter predicts well under a square off, refines
  // every candidate to sub-pixel (windows of `half`) and drops those on a flat window.
  void refineCandidates(const std::vector<CornerPrediction>& pred, const cv::Mat& grey, int half,
                        std::vector<int>* ids, std::vector<cv::Point2f>* uv) const;
  // Each corner's distance to the board plane's homography through all of them, pixels.
  std::vector<double> planeErrorsPx(const std::vector<int>& ids, const std::vector<Vec2>& z) const;
  // Gates each candidate (ids[k] measured at uv[k]) by its innovation, then the set by the board
  // plane; remembers the kept ones for tracking.
  BoardCornerMeasurement keep(const std::vector<CornerPrediction>& pred, const std::vector<int>& ids,
                              const std::vector<cv::Point2f>& uv);

  CameraModel camera_;
  ChessboardTarget target_;
  std::vector<Vec3> corners_world_;
  BoardCornerMeasurementOptions options_;
  double readout_ = 0;
  double rolling_shutter_sigma_ = 0;  // pixels, setMotionNoise's
  std::vector<cv::Mat> pyramid_prev_;
  std::vector<int> tracked_ids_;
  std::vector<cv::Point2f> tracked_uv_;
  std::vector<cv::Point2f> outside_gates_;  // boardOutsideGates()
  CornerNoise noise_;
  ExposureShift exposure_;  // the shared shift's covariance, from the last three frames' corners
  bool shift_spent_ = false;  // an update of this frame has held the shared shift
  PresenceGatedDetector detector_;  // the board searches; learns from every view of the whole board
};

}  // namespace slamcmp
