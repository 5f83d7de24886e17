#pragma once
// The chessboard's inner corners in every frame: the previous frame's corners tracked by pyramidal
// Lucas-Kanade and confirmed (sub-pixel re-refinement, a homography consistent with the grid on
// the undistorted corners, the square colours), with core's full search as the fallback. A full
// search costs 100 to 600 ms on a frame without the board, tracking well under a millisecond.
//
// findCorners() also follows a board that is partly out of the image (the corners that remain,
// their identities known from tracking; the missing ones return as they re-enter the image) and
// re-acquires a board where a predicted camera pose projects it (the predicted corners aligned and
// refined), so the expensive full search is needed only when there is no pose to predict from.
#include <optional>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/chessboard.h"
#include "core/target.h"
#include "tracking/board_presence.h"

namespace slamcmp {

struct BoardCornerTrackerOptions {
  // The sub-pixel window as wide as the thesis allows (under half a square): on tv1..tv4 it cuts
  // the board pose error by 5 to 8 % against core's default of 0.4.
  ChessboardDetectorOptions detector = [] {
    ChessboardDetectorOptions d;
    d.refine_window_fraction = 0.49;
    return d;
  }();
  bool track = true;                   // track last frame's corners before any full search
  double max_grid_error_px = 1.0;      // confirm: RMS homography error of the undistorted corners
  double max_corner_error_px = 0.3;    // findCorners: a corner the homography misses by more is dropped
  double max_refine_shift_px = 2.0;    // confirm: sub-pixel refinement moves no corner further
  int search_interval_when_lost = 3;   // after a miss, full search only every this many frames
  // With a prediction of the corners, the region around them is searched in every frame and the
  // whole image only every this many frames (in case the prediction is wrong).
  int search_interval_when_predicted = 30;
  double region_margin_px = 40;        // the region: the predicted corners' box grown by this and a square
  double search_margin_px = 20;        // full search only if the last pose puts the board this far inside
  // findCorners only: a board partly out of the image is kept while this many corners remain
  // (their identities from tracking); 0 = the whole board only.
  int min_partial_corners = 8;
  bool predicted_search = true;        // findCorners: re-acquire where a predicted pose projects the board
  double max_prediction_error_px = 10; // the predicted corners are aligned within this radius first
  double min_square_contrast = 10;     // grey levels between the white and the black squares
  BoardPresenceOptions presence;       // the quick test before a search, once the board has been seen
  template <class V>
  void visit(V& v) {
    v("detector", detector, "the full search (core chessboard detector)");
    v("track", track, "track last frame's corners by Lucas-Kanade before any full search");
    v("max_grid_error_px", max_grid_error_px,
      "tracked corners are accepted when a homography fits the undistorted grid to this RMS, pixels");
    v("max_corner_error_px", max_corner_error_px,
      "findCorners: a corner the grid's homography (a robust fit) misses by more than this (and by 3 times the "
      "median corner) is dropped, pixels (the edge of something hiding part of the board pulls the refinement off)");
    v("max_refine_shift_px", max_refine_shift_px,
      "a tracked or predicted corner that sub-pixel refinement moves further than this is dropped, pixels");
    v("search_interval_when_lost", search_interval_when_lost,
      "while the board is not seen and nothing predicts it, the full search runs every this many frames (1 = "
      "every frame)");
    v("search_interval_when_predicted", search_interval_when_predicted,
      "findCorners: while the corners are predicted, the region around them is searched in every frame and the "
      "whole image only every this many frames (in case the prediction is wrong)");
    v("region_margin_px", region_margin_px,
      "findCorners: the region searched is the box of the predicted corners grown by a square and this, pixels "
      "(the prediction's error); it is searched while the predicted board is within this of the image");
    v("search_margin_px", search_margin_px,
      "the full search is skipped while the last pose puts an outer corner of the board closer than this "
      "to the image border, pixels (a search on a frame with part of the board costs up to seconds)");
    v("min_partial_corners", min_partial_corners,
      "a board partly out of the image is used while at least this many of its corners are tracked (0: only "
      "the whole board)");
    v("predicted_search", predicted_search,
      "re-acquire the board at the corners a predicted camera pose projects (aligned, refined, confirmed) before "
      "any full search");
    v("max_prediction_error_px", max_prediction_error_px,
      "predicted corners are first aligned to the strongest corner response within this radius, pixels");
    v("min_square_contrast", min_square_contrast,
      "confirm: the white squares must be this much brighter than the black ones, grey levels");
    v("presence", presence, "the quick test (X-junctions) before any search for the whole board");
  }
  void check() const;
};

// The corners of a board found in one frame: some or all of them.
struct BoardCorners {
  std::vector<int> ids;          // corner indices j * cols + i (SPEC section 2), ascending
  std::vector<cv::Point2f> uv;   // distorted pixels; uv[k] is corner ids[k]
  bool complete = false;         // every corner of the board
};

// How findCorners found the board.
enum class BoardFound { None, Tracked, Predicted, Searched };

class BoardCornerTracker {
 public:
  BoardCornerTracker(const ChessboardTarget& target, const BoardCornerTrackerOptions& options);

  // The whole board's corners (distorted pixels, SPEC section 2 order) by a search of the whole
  // image, when the search schedule allows one (search_interval_when_lost frames after a miss;
  // searchNextFrame() makes the next call search): self-calibration's views, whose camera is not
  // known yet.
  std::optional<std::vector<cv::Point2f>> searchWholeBoard(const cv::Mat& grey);

  // The per-frame board step, with partial boards (min_partial_corners) and the predicted search: the corners
  // tracked from the last frame (starting where they are predicted, when they are), then the
  // predicted corners found in the image, then (allow_search, at most every
  // search_interval_when_lost frames) the full search; with a prediction, the region around the
  // predicted board in every frame instead, and the whole image every search_interval_when_predicted
  // frames. The prediction is where
  // T_world_camera_predicted projects the corners, or without a pose `uv_predicted` (every corner,
  // distorted pixels, SPEC section 2 order, NaN where not predicted; e.g. the corners last seen
  // carried by the image's motion).
  std::optional<BoardCorners> findCorners(const cv::Mat& grey, const std::vector<cv::Mat>& pyramid_prev,
                                          const std::vector<cv::Mat>& pyramid, cv::Size lk_window, int lk_levels,
                                          const CameraModel& camera, const SE3* T_world_camera_predicted,
                                          bool allow_search, const std::vector<cv::Point2f>* uv_predicted = nullptr);

  // Whether the last call searched the whole image (else at most the predicted board's region).
  bool lastSearchedWholeImage() const { return last_searched_whole_; }
  BoardFound lastFound() const { return last_found_; }
  // The next call searches the whole image whatever search_interval_when_lost says (a view worth
  // its cost, e.g. one for self-calibration).
  void searchNextFrame() { frames_since_search_ = kNeverSearched; }

 private:
  // Refines `corners` (from where they were given), drops those the refinement moves too far, and checks
  // the rest: enough of them, a plane seen through the lens, the squares' colours.
  bool confirmCorners(const cv::Mat& grey, BoardCorners* corners, const CameraModel& camera) const;
  // The corners of `corners` plus those their homography puts inside the image.
  BoardCorners withReenteringCorners(const BoardCorners& corners, const CameraModel& camera) const;
  // The corners predicted inside the image (`expected`: every corner, NaN where not predicted),
  // aligned on the strongest corner responses nearby; empty if too few.
  std::optional<BoardCorners> predictedCorners(const cv::Mat& grey, const CameraModel& camera,
                                               const std::vector<cv::Point2f>& expected) const;
  // The detector in `region` of the image, unless the presence test rules the board out there. `expected` (every corner, or empty): where a symmetric
  // board's origin is looked for.
  std::optional<BoardCorners> fullSearch(const cv::Mat& grey, const std::vector<cv::Point2f>& expected,
                                         const cv::Rect& region);
  // The region around the predicted board (`expected`: every corner) worth searching: empty when
  // a corner is not predicted or the board cannot be wholly in the image.
  cv::Rect predictedRegion(const cv::Mat& grey, const std::vector<cv::Point2f>& expected) const;
  // Whether the four squares around the corner at grid coordinates `grid` show their colours near
  // it (H: grid to undistorted pixels).
  bool squaresClear(const cv::Mat& grey, const CameraModel& camera, const Mat3& H, const Vec2& grid) const;
  // Mean grey levels (black, white) of the squares between `corners`, as SPEC section 2 (and
  // parity_) number them; empty without a square of each colour.
  std::optional<std::pair<double, double>> squareMeans(const cv::Mat& grey, const BoardCorners& corners) const;
  double squareContrast(const cv::Mat& grey, const BoardCorners& corners) const;  // white - black
  // Whether the squares stop beyond those of `corners` on the board's edges (H: grid to
  // undistorted pixels): false for a board slipped by two squares.
  bool endsAtItsEdges(const cv::Mat& grey, const CameraModel& camera, const Mat3& H,
                      const BoardCorners& corners) const;
  // Whether the whole image is searched in this frame: allow_search, at once when the board is
  // lost, then every search_interval_when_lost (predicted: search_interval_when_predicted) frames.
  bool fullSearchDue(bool allow_search, bool predicted);
  int minCorners() const;
  double refineMarginPx(const BoardCorners& corners) const;
  // Keeps a view of the whole board: the origin for a symmetric board's numbering, and what the
  // full search's presence test learns from.
  void rememberWholeBoard(const cv::Mat& grey, const std::vector<cv::Point2f>& uv);

  ChessboardTarget target_;
  BoardCornerTrackerOptions options_;
  BoardCorners corners_;                // last frame's, empty if not seen
  std::vector<cv::Point2f> last_seen_;  // the last whole board found in any frame, empty if none yet
  PresenceGatedDetector detector_;  // the full search
  // +1, or for a symmetric board whose origin continuity chose the other way round, -1: the sign
  // of the white-minus-black contrast the corner numbering gives.
  double parity_ = 1.0;
  static constexpr int kNeverSearched = 1 << 20;
  int frames_since_search_ = kNeverSearched;  // since the last whole-image search, or the board seen
  bool last_searched_whole_ = false;
  BoardFound last_found_ = BoardFound::None;
};

}  // namespace slamcmp
