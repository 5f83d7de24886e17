#pragma once
// The CSLAM back-end (thesis Algorithm 3.2): per frame, the board pose when the board is seen,
// else two-view motion from a recent posed frame scaled by the triangulated map; features tracked
// across the whole image and triangulated into the map from every posed frame.
//
// Modes: "calibration" (board only; frames without it are lost), "two_view" (the board only until
// the map is built, then two-view motion chained from frame to frame, as the thesis),
// "combined" (default: board when seen, fused with the features' frame-to-frame motion; two-view
// otherwise, on a map refined over a sliding window of keyframes by bundle adjustment, with the
// board's corners as known points while it is seen and the gap re-anchored when it returns:
// cslam/keyframe_window.h). A two-view motion is never chained blindly: it and the
// motion-predicted pose are both refined on the map's points and the better fit stands (a planar
// scene, a tiny baseline or a pure rotation leave the essential matrix degenerate; the map then
// poses the frame). A board partly out of the image poses the frame from the corners that remain;
// the board is re-acquired where the predicted pose projects it. Without a camera the first
// frames gather board views for self-calibration (status initialising).
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/backend_registry.h"
#include "core/tracker.h"
#include "tracking/board_corner_tracker.h"
#include "cslam/board_image_motion.h"
#include "cslam/board_odometry_fusion.h"
#include "cslam/feature_map.h"
#include "cslam/keyframe_window.h"
#include "tracking/feature_tracker.h"
#include "geometry/homography_pose.h"
#include "tracking/calibration_views.h"
#include "geometry/two_view_motion.h"

namespace slamcmp {

struct CslamOptions {
  // Lucas-Kanade window side (board corners and features): 9 tracks as well as 13 on tv1..tv4
  // and vamr (same ATE within 2 %) at half the cost per feature.
  int lk_window_px = 9;
  int lk_levels = 3;      // pyramid levels above the image
  BoardCornerTrackerOptions board;
  BoardImageMotionOptions board_motion;
  BoardPoseOptions board_pose;
  FeatureTrackerOptions features;
  double max_epipolar_error_px = 1.0;  // board frames: features farther from their epipolar line are dropped
  TwoViewOptions two_view;
  int reference_frames = 8;      // two-view reference: the oldest of the last this many posed frames
  int min_scale_points = 8;      // map points needed for the two-view metric scale
  PoseRefinementOptions map_refinement{10, 2.0};  // poses refined on the map's points (two-view, fusion)
  double max_map_error_px = 2.0;  // a two-view pose whose median map reprojection error exceeds this is lost
  FeatureMapOptions map;
  KeyframeWindowOptions refinement;
  MapPointSearchOptions map_search;
  BoardOdometryFusionOptions fusion;
  int two_view_init_map_points = 40;  // two_view mode: the board is used until the map holds this many points
  SelfCalibrationOptions calibration;
  template <class V>
  void visit(V& v) {
    v("lk_window_px", lk_window_px, "Lucas-Kanade window side, pixels (board corners and features)");
    v("lk_levels", lk_levels, "Lucas-Kanade pyramid levels above the image");
    v("board", board, "finding the board: tracking, confirmation, full search");
    v("board_motion", board_motion,
      "calibration and two_view modes: the board predicted by the image's motion while no pose predicts it");
    v("board_pose", board_pose, "pose from the board homography (thesis eqs. 3.1 to 3.17)");
    v("features", features, "Shi-Tomasi features and their Lucas-Kanade tracking");
    v("max_epipolar_error_px", max_epipolar_error_px,
      "in board frames, features farther than this (Sampson, pixels) from their epipolar line are dropped");
    v("two_view", two_view, "two-view motion (thesis eqs. 3.27 to 3.37)");
    v("reference_frames", reference_frames, "two-view reference: the oldest of the last this many posed frames");
    v("min_scale_points", min_scale_points, "map points needed for the metric scale of a two-view motion");
    v("map_refinement", map_refinement, "refinement of a pose on the map's points (two-view motion, fusion)");
    v("max_map_error_px", max_map_error_px,
      "a two-view pose whose median reprojection error of map points exceeds this is lost, pixels");
    v("map", map,
      "triangulation of the features from every posed frame (thesis Algorithm 3.1): the map of calibration and "
      "two_view modes, the fusion's frame-to-frame motion in combined mode");
    v("refinement", refinement,
      "combined mode: the map from keyframes refined over a sliding window by bundle adjustment, re-anchored "
      "when the board returns");
    v("map_search", map_search,
      "combined mode: map points no longer tracked looked for where the pose projects them (at keyframes)");
    v("fusion", fusion, "combined mode: each board pose fused with the features' frame-to-frame motion");
    v("two_view_init_map_points", two_view_init_map_points,
      "two_view mode: the board sets the world frame and scale until the map holds this many points");
    v("calibration", calibration, "self-calibration when no camera file is given");
  }
  void check() const;
  void checkImage(cv::Size image) const;  // the Lucas-Kanade window fits in the image
};

class CslamTracker : public Tracker {
 public:
  // mode: "combined" (also ""), "calibration" or "two_view".
  // want_overlay: fill FrameResult::overlay (board corners and axes, features) in every frame.
  CslamTracker(std::optional<CameraModel> camera, const ChessboardTarget& target, cv::Size image_size,
               const std::string& mode, const CslamOptions& options, bool want_overlay = false);

  std::string name() const override { return "cslam"; }
  FrameResult track(const Frame& frame) override;
  std::vector<MapPoint> mapPoints() const override;
  nlohmann::json options() const override;
  // Throws InputError when the run was impossible: calibration mode and the board never posed a
  // frame, or no camera and too few board views to self-calibrate.
  void finish() override;

  // The camera in use (given, or self-calibrated); empty while calibrating.
  const std::optional<CameraModel>& camera() const { return camera_; }
  // Combined mode's keyframes: a gap's re-anchored once the board returned, where the frames' own
  // poses were given as they came.
  std::vector<KeyframePose> keyframePoses() const override;

 private:
  enum class Mode { Combined, Calibration, TwoView };
  struct PosedFrame {
    int index = 0;
    SE3 T_world_camera;
    std::unordered_map<int, Vec2> xy_normalised;  // feature id -> undistorted normalised coordinates
  };

  void makeMap();  // once the camera is known: the thesis's map, and in combined mode the refined one
  bool gatherCalibrationViews(const Frame& frame, FrameResult* result);
  struct BoardView {
    SE3 T_world_camera;            // from the board alone
    std::vector<int> ids;          // the corners seen (all of them, or the part in the image)
    std::vector<cv::Point2f> uv;   // corners, distorted pixels
    std::vector<Vec2> xy;          // corners, undistorted normalised
    std::vector<Vec3> p_world;     // corners, world frame
    double rms_px = 0;             // reprojection error of the board pose
  };
  // T_world_predicted: this frame's pose as the motion predicts it (tracking starts there; a lost
  // board is searched for where it puts it).
  std::optional<BoardView> boardPoseInFrame(const cv::Mat& grey, const std::optional<SE3>& T_world_predicted,
                                            FrameResult* result);
  BoardView boardView(BoardCorners corners) const;  // the pose from the corners
  // Combined mode: the board pose fused with the features' motion from the previous frame (xy:
  // the features' coordinates).
  SE3 fuseBoardAndMap(const BoardView& board, const std::vector<Vec2>& xy, int frame_index, FrameResult* result);
  // The pose from the board's corners and the refined map's points together (weighted by their
  // standard deviations, the map's also by map_drift_m, how far it may have drifted as a whole),
  // with its covariance; empty with too few map points.
  std::optional<PoseWithCovariance> boardAndMapPose(const BoardView& board, const std::vector<Vec2>& xy,
                                                    double map_drift_m) const;
  // The pose fitted to map points seen at xy_normalised, refined from T_world_start, with its
  // covariance.
  PoseWithCovariance mapPose(const SE3& T_world_start, const std::vector<Vec3>& p_world,
                             const std::vector<Vec2>& xy_normalised) const;
  // The features' motion: their poses in the previous frame and this one (refined from the given
  // poses) against the same map points, refitted without the points either pose leaves beyond
  // fusion.max_motion_residual_px (and 3 times the median): features tracked astray.
  MapMotion mapMotion(const SE3& T_world_previous, const SE3& T_world_current, const std::vector<Vec3>& p_world,
                      const std::vector<Vec2>& xy_previous, const std::vector<Vec2>& xy_current) const;
  std::optional<SE3> twoViewPose(const std::vector<Vec2>& xy, FrameResult* result);
  // The features tracked from the last frame into this one (started where T_world_predicted puts
  // them), their undistorted normalised coordinates (xy[i] for features()[i]); the board's motion
  // (board_motion_) advanced with them.
  std::vector<Vec2> trackFeatures(const std::optional<SE3>& T_world_predicted);
  // A posed frame's features to the map, the history and (when it is one) the keyframe window,
  // whose refinement may move *T_world_camera; features replenished either way.
  void addToMap(const Frame& frame, const BoardView* board, std::optional<SE3>* T_world_camera, FrameResult* result);
  // path_since_anchor_m_: the path the map may have drifted over since the board last anchored it.
  void updatePathSinceAnchor(const std::optional<SE3>& T_world_camera, const BoardView* board);
  // Combined mode's refined map: whether this posed frame becomes a keyframe (if so, map points no
  // longer tracked are looked for first, while few are tracked).
  bool prepareKeyframe(const Frame& frame, const SE3& T_world_camera, const BoardView* board);
  // Adds the keyframe (the features after replenishing: posed, xy) and refines the window; returns
  // the frame's pose: the refined one without the board, the board's and the re-anchored map's
  // when the board ends a gap, else posed's.
  SE3 addKeyframe(const Frame& frame, const PosedFrame& posed, const BoardView* board, const std::vector<Vec2>& xy,
                  FrameResult* result);
  // The thesis's two-view pose (essential matrix from the reference frame, scale from the map),
  // or empty with *failure saying why.
  std::optional<SE3> essentialPose(const std::vector<Vec2>& xy, std::string* failure, FrameResult* result);
  SE3 predictedPose() const;  // this frame's motion prediction, else the last posed frame's pose
  // Constant velocity from the last two posed frames, over frames lost since (a few at most).
  std::optional<SE3> motionPrediction(int frame_index) const;
  // Where the features of the previous (posed) frame should be now if the camera is at
  // T_world_predicted: map points projected, the others turned by the predicted rotation.
  std::vector<cv::Point2f> predictedFeatures(const SE3& T_world_predicted) const;
  std::optional<Vec3> mapPosition(int feature_id) const;  // the refined map's in combined mode
  // Drops the features (and their entries of *xy) off their epipolar line from the last posed frame.
  void dropEpipolarOutliers(const SE3& T_world_camera, std::vector<Vec2>* xy);
  std::vector<Vec2> featuresNormalised() const;
  // The tracked features with a usable map position: their points and (xy[i] for features()[i])
  // observations.
  struct MapCorrespondences {
    std::vector<Vec3> p_world;
    std::vector<Vec2> xy_normalised;
  };
  // barely_triangulated: instead, the refined map's features placed with too little parallax to
  // be map points.
  MapCorrespondences mapPointsSeen(const std::vector<Vec2>& xy, bool barely_triangulated = false) const;
  FrameOverlay overlay(const BoardView* board, const std::optional<SE3>& T_world_camera) const;

  std::optional<CameraModel> camera_;
  ChessboardTarget target_;
  std::vector<Vec3> corners_world_;
  cv::Size image_size_;
  Mode mode_;
  std::string mode_name_;
  CslamOptions options_;
  double focal_px_ = 0;
  bool want_overlay_ = false;

  BoardCornerTracker board_;
  FeatureTracker features_;
  BoardOdometryFusion fusion_;
  std::unique_ptr<FeatureMap> map_;        // the thesis's map (in combined mode, for the fusion's motion)
  std::unique_ptr<KeyframeWindow> window_;  // combined mode's refined map
  std::optional<CalibrationViews> calibration_views_;  // while self-calibrating
  // Calibration and two_view modes: where the board is while no pose says so.
  std::optional<BoardImageMotion> board_motion_;
  std::unordered_map<int, Vec2> xy_previous_;  // the previous frame's features by id (for board_motion_)
  std::optional<double> calibration_rms_px_;

  std::vector<cv::Mat> pyramid_prev_, pyramid_;
  std::optional<SE3> last_pose_;    // the previous frame's, if it had one
  std::optional<Vec3> last_posed_centre_;  // the last posed frame's camera centre
  double path_since_anchor_m_ = 0;         // travelled without the board since it last anchored the map
  std::optional<SE3> T_world_predicted_;  // this frame's, by the motion model
  std::deque<PosedFrame> history_;  // the last posed frames, oldest first
  bool two_view_board_phase_ = true;
  int posed_frames_ = 0;
};

// The back-end's registration (core/backend_registry.h): modes combined, calibration, two_view.
BackendRegistration cslamBackend();

}  // namespace slamcmp
