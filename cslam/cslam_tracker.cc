#include "cslam/cslam_tracker.h"

#include <opencv2/video/tracking.hpp>

#include "core/error.h"
#include "core/options.h"
#include "core/stage_timer.h"
#include "core/statistics.h"
#include "geometry/bundle_adjustment.h"
#include "geometry/essential_eight_point.h"
#include "geometry/pose_refinement.h"
#include "geometry/triangulation.h"
#include "geometry/two_view_motion.h"

namespace slamcmp {

void CslamOptions::check() const {
  if (lk_window_px < 5 || lk_window_px % 2 == 0) throw OptionError("lk_window_px", "must be odd and >= 5");
  if (lk_levels < 0 || lk_levels > 6) throw OptionError("lk_levels", "must be in [0, 6]");
  if (!(max_epipolar_error_px > 0)) throw OptionError("max_epipolar_error_px", "must be positive");
  if (reference_frames < 1) throw OptionError("reference_frames", "must be >= 1");
  if (min_scale_points < 1) throw OptionError("min_scale_points", "must be >= 1");
  if (!(max_map_error_px > 0)) throw OptionError("max_map_error_px", "must be positive");
  if (two_view_init_map_points < 1) throw OptionError("two_view_init_map_points", "must be >= 1");
}

void CslamOptions::checkImage(cv::Size image) const {
  requireWithinImage("lk_window_px", lk_window_px, std::min(image.width, image.height), image);
}

namespace {

// The motion model predicts at most this many frames past the last pose.
constexpr int kMaxFramesPredicted = 5;
// The fusion's motion is measured on the thesis's map when it holds this many of the tracked
// features, else on the refined map.
constexpr int kMinThesisMotionPoints = 30;
// A map point's depth below this (metres) is taken as this when the drift is turned into pixels.
constexpr double kMinDriftDepthM = 0.1;
// A point of the features' motion is dropped beyond this many times the median residual (and
// fusion.max_motion_residual_px), as a board corner is (tracking/board_corner_tracker.cc).
constexpr double kMaxMotionResidualOverMedian = 3.0;
// A point the refined map placed with too little parallax counts with this many times a feature's
// standard deviation in a frame's pose.
constexpr double kBarelyTriangulatedSigmaFactor = 3.0;

}  // namespace

CslamTracker::CslamTracker(std::optional<CameraModel> camera, const ChessboardTarget& target, cv::Size image_size,
                           const std::string& mode, const CslamOptions& options, bool want_overlay)
    : camera_(std::move(camera)),
      target_(target),
      corners_world_(target.cornersWorld()),
      image_size_(image_size),
      mode_name_(mode.empty() ? "combined" : mode),
      options_(options),
      want_overlay_(want_overlay),
      board_(target, options.board),
      features_(options.features),
      fusion_(options.fusion) {
  if (mode_name_ == "combined") {
    mode_ = Mode::Combined;
  } else if (mode_name_ == "calibration") {
    mode_ = Mode::Calibration;
  } else if (mode_name_ == "two_view") {
    mode_ = Mode::TwoView;
  } else {
    throw InputError("--mode", "cslam knows combined, calibration and two_view, not '" + mode + "'");
  }
  if (camera_) {
    focal_px_ = 0.5 * (camera_->fx + camera_->fy);
    makeMap();
  } else {
    calibration_views_.emplace(target_, image_size_, options_.calibration, options_.board_pose);
  }
}

nlohmann::json CslamTracker::options() const {
  nlohmann::json j = optionsToJson(options_);
  j["mode"] = mode_name_;
  if (calibration_rms_px_) j["self_calibration"] = selfCalibrationJson(*camera_, *calibration_rms_px_);
  return j;
}

void CslamTracker::finish() {
  if (!camera_)
    throw InputError("", calibration_views_->whyNotCalibrated());
  if (posed_frames_ == 0)  // every mode needs the board once: it sets the world frame and the scale
    throw InputError("", "the board never appeared: it sets the world frame and the scale in every mode");
}

std::vector<KeyframePose> CslamTracker::keyframePoses() const {
  return window_ ? window_->keyframePoses() : std::vector<KeyframePose>{};
}

std::vector<MapPoint> CslamTracker::mapPoints() const {
  if (window_) return window_->points();
  return map_ ? map_->points() : std::vector<MapPoint>{};
}

void CslamTracker::makeMap() {
  map_ = std::make_unique<FeatureMap>(options_.map, focal_px_);
  if (mode_ == Mode::Combined && options_.refinement.enabled)
    window_ = std::make_unique<KeyframeWindow>(options_.refinement, focal_px_, corners_world_);
  // Combined mode always has a pose to predict the board from (the refined map's).
  if (mode_ != Mode::Combined && options_.board_motion.enabled) board_motion_.emplace(options_.board_motion, focal_px_);
}

std::optional<Vec3> CslamTracker::mapPosition(int feature_id) const {
  return window_ ? window_->position(feature_id) : map_->position(feature_id);
}

std::vector<Vec2> CslamTracker::featuresNormalised() const {
  std::vector<Vec2> xy;
  xy.reserve(features_.features().size());
  for (const auto& f : features_.features()) xy.push_back(camera_->undistortPixel(Vec2(f.uv.x, f.uv.y)));
  return xy;
}

bool CslamTracker::gatherCalibrationViews(const Frame& frame, FrameResult* result) {
  // Every frame is searched: a view for the calibration is worth a search's cost, and after a miss
  // the tracker's interval skipped frames showing the whole board (video_chessboard 102, 103, 174, 175).
  board_.searchNextFrame();
  const auto corners = board_.searchWholeBoard(frame.grey);
  std::string refused;  // why a calibration tried on this frame was not used
  if (const auto calibrated = calibration_views_->add(frame.index, corners ? &*corners : nullptr, &refused)) {
    camera_ = calibrated->camera;
    calibration_rms_px_ = calibrated->rms_px;
    focal_px_ = 0.5 * (camera_->fx + camera_->fy);
    makeMap();
    result->late_poses = calibration_views_->latePoses(*camera_, frame.index);  // this frame is posed below
    calibration_views_.reset();
    return true;
  }
  result->status = TrackStatus::Initialising;
  result->reason = calibration_views_->gatheringReason(refused);
  return false;
}

std::optional<CslamTracker::BoardView> CslamTracker::boardPoseInFrame(const cv::Mat& grey,
                                                                      const std::optional<SE3>& T_world_predicted,
                                                                      FrameResult* result) {
  const cv::Size window(options_.lk_window_px, options_.lk_window_px);
  // A full search costs up to seconds on a cluttered frame with part of the board or none: skip it
  // while the last pose (else the predicted one) says the board is not well inside the image.
  bool board_expected = true;
  if (const std::optional<SE3>& T_world_last = last_pose_ ? last_pose_ : T_world_predicted) {
    const SE3 T_camera_world = T_world_last->inverse();
    for (const Vec3& p : target_.outerCornersWorld()) {
      const Vec3 p_camera = T_camera_world * p;
      board_expected = board_expected && p_camera.z() > 0 &&
                       camera_->inImage(camera_->project(p_camera), options_.board.search_margin_px);
    }
  }
  // The corners are tracked from where the predicted pose puts them, and a lost board is looked
  // for there (a symmetric board's origin is kept by continuity with it). Without a pose, where
  // the image's motion carried the board's last view; else the last posed frame's pose.
  const SE3* T_world_reference = T_world_predicted ? &*T_world_predicted : nullptr;
  std::vector<cv::Point2f> uv_predicted;
  if (!T_world_reference && !last_pose_ && board_motion_ && board_motion_->predicting()) {
    // The tracker searches the region where they put the board, the whole image only now and then.
    uv_predicted = board_motion_->corners(*camera_, corners_world_);
    board_expected = true;
  } else if (!T_world_reference && !history_.empty()) {
    T_world_reference = &history_.back().T_world_camera;
  }
  auto corners = board_.findCorners(grey, pyramid_prev_, pyramid_, window, options_.lk_levels, *camera_,
                                    T_world_reference, board_expected, uv_predicted.empty() ? nullptr : &uv_predicted);
  if (!corners) return std::nullopt;
  result->measured = static_cast<int>(corners->ids.size());
  if (!corners->complete)
    result->reason = "part of the board (" + std::to_string(corners->ids.size()) + " of " +
                     std::to_string(target_.numCorners()) + " corners)";
  BoardView view = boardView(std::move(*corners));
  if (board_motion_) board_motion_->seen(view.p_world, view.xy);
  return view;
}

CslamTracker::BoardView CslamTracker::boardView(BoardCorners corners) const {
  BoardView view;
  view.ids = std::move(corners.ids);
  view.uv = std::move(corners.uv);
  view.xy.reserve(view.uv.size());
  for (const auto& c : view.uv) view.xy.push_back(camera_->undistortPixel(Vec2(c.x, c.y)));
  for (int id : view.ids) view.p_world.push_back(corners_world_[id]);
  const BoardPose pose = boardPose(view.p_world, view.xy, focal_px_, options_.board_pose);
  view.T_world_camera = pose.T_camera_board.inverse();
  view.rms_px = pose.rms_px;
  return view;
}

SE3 CslamTracker::fuseBoardAndMap(const BoardView& board, const std::vector<Vec2>& xy, int frame_index,
                                  FrameResult* result) {
  const PoseWithCovariance board_pose = poseWithCovariance(board.T_world_camera.inverse(), board.p_world, board.xy,
                                                           focal_px_, board.rms_px, options_.fusion.min_pixel_sigma);
  // The features' motion from the previous frame: their poses in both frames against the same
  // points of the map (the map's error cancels): the thesis's map (triangulated from every posed
  // frame's rays, its points are the more accurate in forward motion), or the refined map while
  // the thesis's holds few of them (the board back after a gap: the refined map's points are
  // placed at less parallax, and found again).
  std::optional<MapMotion> motion;
  if (!history_.empty() && history_.back().index == frame_index - 1) {
    const PosedFrame& prev = history_.back();
    const auto& features = features_.features();
    struct Common {
      std::vector<Vec3> p_world;
      std::vector<Vec2> xy_now, xy_prev;
    } thesis, refined;
    for (size_t i = 0; i < features.size(); ++i) {
      const auto before = prev.xy_normalised.find(features[i].id);
      if (before == prev.xy_normalised.end()) continue;
      for (auto [map_point, common] : {std::make_pair(map_->position(features[i].id), &thesis),
                                       std::make_pair(window_ ? window_->position(features[i].id) : std::nullopt,
                                                      &refined)}) {
        if (!map_point) continue;
        common->p_world.push_back(*map_point);
        common->xy_now.push_back(xy[i]);
        common->xy_prev.push_back(before->second);
      }
    }
    const Common& used = static_cast<int>(thesis.p_world.size()) >= kMinThesisMotionPoints || !window_ ? thesis : refined;
    if (static_cast<int>(used.p_world.size()) >= options_.min_scale_points) {
      motion = mapMotion(prev.T_world_camera, board.T_world_camera, used.p_world, used.xy_prev, used.xy_now);
      result->measured += static_cast<int>(used.p_world.size());
    }
  }
  // The filter (re)starts, e.g. when the board returns after a gap, or has no motion to go by:
  // from the board and the refined map together, whose points (found again, many of them placed
  // while the board was seen) hold the board's tilt that a single view of it (a strip of it at
  // the image's edge above all) leaves loose; after a gap they are trusted only as far as the
  // path since the board may have moved them (fusion.map_drift_fraction).
  std::optional<PoseWithCovariance> start;
  if ((fusion_.restarting() || !motion) && window_)
    start = boardAndMapPose(board, xy, options_.fusion.map_drift_fraction * path_since_anchor_m_);
  const SE3 T_camera_world = fusion_.update(board_pose, motion, start ? &*start : nullptr);
  if (fusion_.heldLastBoard())
    result->reason += std::string(result->reason.empty() ? "" : "; ") +
                      "board pose off the features' motion: the motion's pose kept";
  return T_camera_world.inverse();
}

std::optional<PoseWithCovariance> CslamTracker::boardAndMapPose(const BoardView& board, const std::vector<Vec2>& xy,
                                                                double map_drift_m) const {
  const MapCorrespondences seen = mapPointsSeen(xy);
  if (static_cast<int>(seen.p_world.size()) < options_.min_scale_points) return std::nullopt;
  const double sigma_board = options_.refinement.board_sigma_px;
  const SE3 T_camera_world_by_board = board.T_world_camera.inverse();  // from the board alone
  double sigma_map = options_.refinement.feature_sigma_px;
  if (map_drift_m > 0) {
    // The drift moved the map's points together: an error they share, whose weight does not grow
    // with their number, so each point's variance grows by n times the square of the drift's
    // image shift at the points' median depth.
    std::vector<double> depth;
    for (const Vec3& p : seen.p_world) depth.push_back((T_camera_world_by_board * p).z());
    const double n = static_cast<double>(depth.size());
    const double shift_px = focal_px_ * map_drift_m / std::max(median(std::move(depth)), kMinDriftDepthM);
    sigma_map = std::sqrt(sigma_map * sigma_map + n * shift_px * shift_px);
  }
  BundleAdjustment ba;
  const int camera = ba.addCamera(T_camera_world_by_board, false);
  for (size_t k = 0; k < board.p_world.size(); ++k)
    ba.addObservation(camera, ba.addPoint(board.p_world[k], true), board.xy[k], sigma_board);
  for (size_t k = 0; k < seen.p_world.size(); ++k)
    ba.addObservation(camera, ba.addPoint(seen.p_world[k], true), seen.xy_normalised[k], sigma_map);
  ba.solve(options_.refinement.bundle_adjustment, focal_px_);
  const SE3 T_camera_world = ba.camera(camera);
  const Mat6 information =
      reprojectionHessian(T_camera_world, board.p_world, board.xy, focal_px_) / (sigma_board * sigma_board) +
      reprojectionHessian(T_camera_world, seen.p_world, seen.xy_normalised, focal_px_) / (sigma_map * sigma_map);
  return PoseWithCovariance{T_camera_world, information.completeOrthogonalDecomposition().pseudoInverse()};
}

PoseWithCovariance CslamTracker::mapPose(const SE3& T_world_start, const std::vector<Vec3>& p_world,
                                        const std::vector<Vec2>& xy_normalised) const {
  const auto refined = refinePose(T_world_start.inverse(), p_world, xy_normalised, focal_px_, options_.map_refinement);
  return poseWithCovariance(refined.T_camera_world, p_world, xy_normalised, focal_px_, refined.rms_px,
                            options_.fusion.min_pixel_sigma);
}

MapMotion CslamTracker::mapMotion(const SE3& T_world_previous, const SE3& T_world_current,
                                  const std::vector<Vec3>& p_world, const std::vector<Vec2>& xy_previous,
                                  const std::vector<Vec2>& xy_current) const {
  MapMotion motion{mapPose(T_world_previous, p_world, xy_previous), mapPose(T_world_current, p_world, xy_current)};
  // Huber's weights bound a stray point's pull, but not enough: one 5 px point among a hundred, or
  // a few features sliding along the image in a fast pan, moved the motion by 1-3 mm along what a
  // narrow view leaves loose (a sideways step against a turn) in board_leaves' pan.
  const std::vector<double> previous =
      reprojectionErrorsPx(motion.previous.T_camera_world, p_world, xy_previous, focal_px_);
  const std::vector<double> current = reprojectionErrorsPx(motion.current.T_camera_world, p_world, xy_current, focal_px_);
  const auto limit = [&](const std::vector<double>& errors) {
    return std::max(options_.fusion.max_motion_residual_px, kMaxMotionResidualOverMedian * median(errors));
  };
  const double limit_previous = limit(previous), limit_current = limit(current);
  std::vector<Vec3> kept_world;
  std::vector<Vec2> kept_previous, kept_current;
  for (size_t k = 0; k < p_world.size(); ++k) {
    if (!(previous[k] <= limit_previous && current[k] <= limit_current)) continue;
    kept_world.push_back(p_world[k]);
    kept_previous.push_back(xy_previous[k]);
    kept_current.push_back(xy_current[k]);
  }
  if (kept_world.size() == p_world.size() || static_cast<int>(kept_world.size()) < options_.min_scale_points)
    return motion;
  // The poses refitted; their covariances stay those of the fit to every point, against which
  // fusion.motion_noise_scale was measured (the refit's own, from its smaller residuals, made the
  // fused pose follow the features more and held it off the board after wall_turn's return: its
  // 30 frames 0.98 -> 1.48 times the settled error).
  for (auto [pose, xy] : {std::make_pair(&motion.previous, &kept_previous), std::make_pair(&motion.current, &kept_current)})
    pose->T_camera_world =
        refinePose(pose->T_camera_world, kept_world, *xy, focal_px_, options_.map_refinement).T_camera_world;
  return motion;
}

void CslamTracker::dropEpipolarOutliers(const SE3& T_world_camera, std::vector<Vec2>* xy) {
  if (history_.empty()) return;
  const PosedFrame& prev = history_.back();
  const SE3 T_cur_prev = T_world_camera.inverse() * prev.T_world_camera;
  if (T_cur_prev.t().norm() < 1e-9) return;  // no baseline: no epipolar line
  const Mat3 E = essentialFromMotion(SE3(T_cur_prev.R(), T_cur_prev.t().normalized()));
  const double max2 = std::pow(options_.max_epipolar_error_px / focal_px_, 2);
  const auto& features = features_.features();
  std::vector<char> keep(features.size(), 1);
  for (size_t i = 0; i < features.size(); ++i) {
    const auto it = prev.xy_normalised.find(features[i].id);
    if (it != prev.xy_normalised.end()) keep[i] = sampsonErrorSquared(E, it->second, (*xy)[i]) <= max2;
  }
  features_.keepOnly(keep);
  size_t kept = 0;
  for (size_t i = 0; i < keep.size(); ++i)
    if (keep[i]) (*xy)[kept++] = (*xy)[i];
  xy->resize(kept);
}

std::optional<SE3> CslamTracker::twoViewPose(const std::vector<Vec2>& xy, FrameResult* result) {
  // Map points seen now: their positions fix the scale and refine the pose. In a fast turn the
  // features that enter the image have too little parallax to be map points for a while; the
  // refined map has placed them all the same (their directions hold the rotation), and they
  // take part with less weight.
  const MapCorrespondences seen = mapPointsSeen(xy);
  const MapCorrespondences barely = window_ ? mapPointsSeen(xy, true) : MapCorrespondences{};
  const int n_map = static_cast<int>(seen.p_world.size());
  const bool map_usable = n_map + static_cast<int>(barely.p_world.size()) >= options_.min_scale_points;
  std::string essential_failure;
  std::optional<SE3> T_world_essential = essentialPose(xy, &essential_failure, result);
  if (!map_usable) {
    if (!T_world_essential) result->reason = essential_failure;
    return T_world_essential;
  }
  // The essential matrix alone is fragile: with most features near one plane (the board and its
  // surround) a lateral translation trades for a rotation (the bas-relief ambiguity), and tiny
  // baselines or pure rotations leave the translation undetermined. The map's points decide:
  // the two-view motion and the last posed frame's pose (constant velocity when the previous
  // frame was posed) both start a refinement on the map, and the one the map fits best stands.
  struct Candidate {
    SE3 T_camera_world;
    double median_px;
  };
  // The fit is judged on the map points proper when there are enough of them.
  const bool judge_on_map = n_map >= options_.min_scale_points;
  auto refineOnMap = [&](const SE3& T_world_camera) {
    SE3 T_camera_world;
    if (window_) {
      BundleAdjustment ba;
      const int camera = ba.addCamera(T_world_camera.inverse(), false);
      for (size_t k = 0; k < seen.p_world.size(); ++k)
        ba.addObservation(camera, ba.addPoint(seen.p_world[k], true), seen.xy_normalised[k],
                          options_.refinement.feature_sigma_px);
      for (size_t k = 0; k < barely.p_world.size(); ++k)
        ba.addObservation(camera, ba.addPoint(barely.p_world[k], true), barely.xy_normalised[k],
                          kBarelyTriangulatedSigmaFactor * options_.refinement.feature_sigma_px);
      ba.solve(options_.refinement.bundle_adjustment, focal_px_);
      T_camera_world = ba.camera(camera);
    } else {
      T_camera_world =
          refinePose(T_world_camera.inverse(), seen.p_world, seen.xy_normalised, focal_px_, options_.map_refinement)
              .T_camera_world;
    }
    std::vector<double> errors = reprojectionErrorsPx(T_camera_world, seen.p_world, seen.xy_normalised, focal_px_);
    if (!judge_on_map) {
      const auto more = reprojectionErrorsPx(T_camera_world, barely.p_world, barely.xy_normalised, focal_px_);
      errors.insert(errors.end(), more.begin(), more.end());
    }
    return Candidate{T_camera_world, median(errors)};
  };
  std::optional<Candidate> from_essential;
  if (T_world_essential) from_essential = refineOnMap(*T_world_essential);
  const Candidate from_motion = refineOnMap(predictedPose());
  const bool essential_wins = from_essential && from_essential->median_px <= from_motion.median_px;
  const Candidate& best = essential_wins ? *from_essential : from_motion;
  if (best.median_px > options_.max_map_error_px) {
    result->reason = "two-view pose disagrees with the map (median " + std::to_string(best.median_px) + " px)";
    return std::nullopt;
  }
  if (!essential_wins) {
    result->measured = n_map + static_cast<int>(barely.p_world.size());
    result->reason = (T_world_essential ? std::string("the map rejects the two-view motion")
                                        : essential_failure) +
                     (judge_on_map ? "; pose from the map's points"
                                   : "; pose from the map's points, most with little parallax");
  }
  return best.T_camera_world.inverse();
}

SE3 CslamTracker::predictedPose() const {
  return T_world_predicted_ ? *T_world_predicted_ : history_.back().T_world_camera;
}

std::optional<SE3> CslamTracker::motionPrediction(int frame_index) const {
  if (history_.empty()) return std::nullopt;
  const PosedFrame& last = history_.back();
  const int ahead = frame_index - last.index;
  if (ahead > kMaxFramesPredicted) return std::nullopt;
  if (history_.size() < 2) return last.T_world_camera;
  // Constant velocity over the last two consecutive posed frames, carried over frames lost since.
  const PosedFrame& before = history_[history_.size() - 2];
  if (last.index - before.index != 1) return last.T_world_camera;
  const SE3 step = before.T_world_camera.inverse() * last.T_world_camera;
  SE3 T = last.T_world_camera;
  for (int k = 0; k < ahead; ++k) T = T * step;
  return T;
}

std::vector<cv::Point2f> CslamTracker::predictedFeatures(const SE3& T_world_predicted) const {
  const PosedFrame& prev = history_.back();
  const SE3 T_predicted_world = T_world_predicted.inverse();
  const Mat3 R_predicted_prev = T_predicted_world.R() * prev.T_world_camera.R();
  std::vector<cv::Point2f> uv;
  uv.reserve(features_.features().size());
  for (const Feature& f : features_.features()) {
    // A map point where the predicted pose projects it; a feature without one turned by the
    // predicted rotation (its depth unknown: right for distant points and for turns).
    Vec3 p_camera(0, 0, -1);
    if (const auto p = mapPosition(f.id)) {
      p_camera = T_predicted_world * *p;
    } else if (const auto it = prev.xy_normalised.find(f.id); it != prev.xy_normalised.end()) {
      p_camera = R_predicted_prev * it->second.homogeneous();
    }
    Vec2 q(f.uv.x, f.uv.y);
    if (p_camera.z() > 1e-3) {
      const Vec2 projected = camera_->project(p_camera);
      if (camera_->inImage(projected, -50)) q = projected;
    }
    uv.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()));
  }
  return uv;
}

std::optional<SE3> CslamTracker::essentialPose(const std::vector<Vec2>& xy, std::string* failure,
                                               FrameResult* result) {
  const auto& features = features_.features();
  // Reference: the oldest recent posed frame (widest baseline) sharing enough features.
  const PosedFrame* ref = nullptr;
  std::vector<int> common;  // indices into features
  const size_t first = history_.size() > static_cast<size_t>(options_.reference_frames)
                           ? history_.size() - options_.reference_frames
                           : 0;
  for (size_t h = first; h < history_.size() && !ref; ++h) {
    common.clear();
    for (size_t i = 0; i < features.size(); ++i)
      if (history_[h].xy_normalised.count(features[i].id)) common.push_back(static_cast<int>(i));
    if (static_cast<int>(common.size()) >= options_.two_view.min_inliers) ref = &history_[h];
  }
  if (!ref) {
    *failure = "no recent posed frame shares enough features for two-view motion";
    return std::nullopt;
  }
  std::vector<Vec2> xy_ref, xy_cur;
  for (int i : common) xy_ref.push_back(ref->xy_normalised.at(features[i].id)), xy_cur.push_back(xy[i]);
  const TwoViewResult motion = estimateTwoViewMotion(xy_ref, xy_cur, focal_px_, options_.two_view);
  if (!motion.ok) {
    *failure = motion.reason;
    return std::nullopt;
  }
  // Metric scale (the map): depth of each map point in the reference camera over its depth
  // triangulated with the unit baseline.
  const SE3 T_ref_cur_unit = motion.T_b_a.inverse();
  const SE3 T_ref_world = ref->T_world_camera.inverse();
  std::vector<double> ratios;
  for (size_t k = 0; k < common.size(); ++k) {
    if (!motion.inliers[k]) continue;
    const auto p = mapPosition(features[common[k]].id);
    if (!p) continue;
    const Ray ray_ref{Vec3::Zero(), xy_ref[k].homogeneous().normalized()};
    const Ray ray_cur = rayFromObservation(T_ref_cur_unit, xy_cur[k]);
    Vec3 a, b;
    if (!closestPointsOfRays(ray_ref, ray_cur, &a, &b)) continue;
    const double depth_unit = 0.5 * (a + b).z();
    const double depth_map = (T_ref_world * *p).z();
    if (depth_unit > 0 && depth_map > 0) ratios.push_back(depth_map / depth_unit);
  }
  if (static_cast<int>(ratios.size()) < options_.min_scale_points) {
    *failure = "too few map points for the two-view scale (" + std::to_string(ratios.size()) + ")";
    return std::nullopt;
  }
  result->measured = motion.num_inliers;
  const SE3 T_cur_ref(motion.T_b_a.R(), median(ratios) * motion.T_b_a.t());
  return ref->T_world_camera * T_cur_ref.inverse();
}

FrameOverlay CslamTracker::overlay(const BoardView* board, const std::optional<SE3>& T_world_camera) const {
  FrameOverlay o;
  if (board)
    for (size_t k = 0; k < board->ids.size(); ++k)
      o.board_corners.push_back({board->ids[k], Vec2(board->uv[k].x, board->uv[k].y)});
  if (T_world_camera) o.board_axes = boardAxes(*camera_, target_.square_size, *T_world_camera);
  for (const auto& f : features_.features())
    o.features.push_back({f.id, Vec2(f.uv.x, f.uv.y), OverlayFeatureState::Inlier});
  for (const auto& f : features_.dropped())
    o.features.push_back({f.id, Vec2(f.uv.x, f.uv.y), OverlayFeatureState::Rejected});
  return o;
}

FrameResult CslamTracker::track(const Frame& frame) {
  FrameResult result;
  if (!camera_ && !gatherCalibrationViews(frame, &result)) return result;

  const cv::Size window(options_.lk_window_px, options_.lk_window_px);
  {
    const StageTimer timer(&result.stages, "pyramid");
    cv::buildOpticalFlowPyramid(frame.grey, pyramid_, window, options_.lk_levels);
  }
  // The motion model's pose for this frame (from the last posed frames).
  T_world_predicted_ = motionPrediction(frame.index);
  const std::optional<SE3>& T_world_predicted = T_world_predicted_;

  // The features first: their motion carries a prediction of the board when no pose does.
  std::vector<Vec2> xy;
  {
    const StageTimer timer(&result.stages, "features");
    xy = trackFeatures(T_world_predicted);
  }

  std::optional<SE3> T_world_camera;
  const bool use_board = mode_ != Mode::TwoView || two_view_board_phase_;
  std::optional<BoardView> board;
  if (use_board) {
    const StageTimer timer(&result.stages, "board");
    // Until the board has set the world frame every frame is searched: the interval after a miss
    // skipped a frame showing the whole board right after a self-calibration that ended on a frame
    // without it.
    if (history_.empty()) board_.searchNextFrame();
    if ((board = boardPoseInFrame(frame.grey, T_world_predicted, &result))) {
      T_world_camera = board->T_world_camera;
      result.status = TrackStatus::Tracked;
      result.source = "board";
    }
  }

  {
    const StageTimer timer(&result.stages, "motion");
    if (!T_world_camera) {
      if (mode_ == Mode::Calibration) {
        // Without the whole image searched, say so: the board may be there, unseen.
        result.reason = board_.lastSearchedWholeImage() ? "no board" : "no board (searched only where predicted)";
      } else if (history_.empty()) {
        result.reason = "no board yet: the world frame is not set";
      } else if ((T_world_camera = twoViewPose(xy, &result))) {
        result.status = TrackStatus::Tracked;
        result.source = "two_view";
      }
    }
    if (T_world_camera) dropEpipolarOutliers(*T_world_camera, &xy);
    if (board && mode_ == Mode::Combined && options_.fusion.enabled) {
      T_world_camera = fuseBoardAndMap(*board, xy, frame.index, &result);
    } else {
      fusion_.reset();
    }
  }

  if (want_overlay_) result.overlay = overlay(board ? &*board : nullptr, T_world_camera);
  {
    const StageTimer timer(&result.stages, "map");
    addToMap(frame, board ? &*board : nullptr, &T_world_camera, &result);
  }
  updatePathSinceAnchor(T_world_camera, board ? &*board : nullptr);
  last_pose_ = T_world_camera;
  if (!T_world_camera) {
    // Before the board first set the world frame the run is waiting to start, not lost.
    result.status = posed_frames_ == 0 ? TrackStatus::Initialising : TrackStatus::Lost;
    // Two-view chaining broke: the board, when it comes back, starts the chain again.
    if (mode_ == Mode::TwoView) two_view_board_phase_ = true;
  }
  for (const int id : features_.ended()) map_->forgetIfUnusable(id);
  result.features = static_cast<int>(features_.features().size());
  std::swap(pyramid_prev_, pyramid_);
  return result;
}

std::vector<Vec2> CslamTracker::trackFeatures(const std::optional<SE3>& T_world_predicted) {
  if (!pyramid_prev_.empty()) {
    std::vector<cv::Point2f> predicted;
    if (T_world_predicted) predicted = predictedFeatures(*T_world_predicted);
    const cv::Size window(options_.lk_window_px, options_.lk_window_px);
    features_.track(pyramid_prev_, pyramid_, window, options_.lk_levels, T_world_predicted ? &predicted : nullptr);
  }
  std::vector<Vec2> xy = featuresNormalised();
  if (board_motion_) {
    std::unordered_map<int, Vec2> xy_current;
    for (size_t i = 0; i < xy.size(); ++i) xy_current.emplace(features_.features()[i].id, xy[i]);
    board_motion_->advance(xy_previous_, xy_current);
    xy_previous_ = std::move(xy_current);
  }
  return xy;
}

void CslamTracker::addToMap(const Frame& frame, const BoardView* board, std::optional<SE3>* T_world_camera,
                            FrameResult* result) {
  const bool keyframe = *T_world_camera && window_ && prepareKeyframe(frame, **T_world_camera, board);
  // Combined: not on the board's corners, which the board measures; a feature there would measure
  // them again in the motion, the joint pose and the window, each time as if independent. The other
  // modes fuse nothing with the board, and their features on it carry its view while it leaves.
  static const std::vector<cv::Point2f> kNothing;
  features_.replenish(frame.grey, board && mode_ == Mode::Combined ? board->uv : kNothing);
  if (!*T_world_camera) return;
  const std::vector<Vec2> xy = featuresNormalised();
  PosedFrame posed{frame.index, **T_world_camera, {}};
  for (size_t i = 0; i < xy.size(); ++i) {
    const int id = features_.features()[i].id;
    map_->addObservation(id, **T_world_camera, xy[i]);
    posed.xy_normalised.emplace(id, xy[i]);
  }
  if (keyframe) *T_world_camera = posed.T_world_camera = addKeyframe(frame, posed, board, xy, result);
  history_.push_back(std::move(posed));
  while (static_cast<int>(history_.size()) > options_.reference_frames) history_.pop_front();
  if (mode_ == Mode::TwoView && two_view_board_phase_ &&
      static_cast<int>(mapPointsSeen(xy).p_world.size()) >= options_.two_view_init_map_points)
    two_view_board_phase_ = false;
  result->T_world_camera = *T_world_camera;
  ++posed_frames_;
}

void CslamTracker::updatePathSinceAnchor(const std::optional<SE3>& T_world_camera, const BoardView* board) {
  // Frames posed without the board add to it, a view of the board that anchors the map ends it, a
  // strip of the board does neither.
  if (T_world_camera && !board && last_posed_centre_)
    path_since_anchor_m_ += (T_world_camera->t() - *last_posed_centre_).norm();
  if (board && window_ && window_->anchors(static_cast<int>(board->ids.size()))) path_since_anchor_m_ = 0;
  if (T_world_camera) last_posed_centre_ = T_world_camera->t();
}

bool CslamTracker::prepareKeyframe(const Frame& frame, const SE3& T_world_camera, const BoardView* board) {
  std::vector<int> ids;
  int tracked_map_points = 0;
  for (const Feature& f : features_.features()) {
    ids.push_back(f.id);
    tracked_map_points += window_->position(f.id).has_value();
  }
  std::sort(ids.begin(), ids.end());
  if (!window_->wantsKeyframe(frame.index, T_world_camera, ids, board ? static_cast<int>(board->ids.size()) : 0))
    return false;
  // Few map points tracked (the board back after a gap, the camera turned back): those no longer
  // tracked are looked for where the pose projects them.
  if (options_.map_search.enabled && tracked_map_points < options_.map_search.below_map_points)
    features_.add(searchMapPoints(frame.grey, *camera_, T_world_camera, window_->untrackedPoints(ids),
                                  features_.features(), options_.features.min_distance_px, options_.map_search));
  return true;
}

SE3 CslamTracker::addKeyframe(const Frame& frame, const PosedFrame& posed, const BoardView* board,
                              const std::vector<Vec2>& xy, FrameResult* result) {
  Keyframe keyframe;
  keyframe.frame_index = frame.index;
  keyframe.T_world_camera = posed.T_world_camera;
  keyframe.features = posed.xy_normalised;
  if (board) {
    keyframe.board_ids = board->ids;
    keyframe.board_xy = board->xy;
    keyframe.T_world_camera_by_board = board->T_world_camera;
  }
  const KeyframeWindow::Added added = window_->add(std::move(keyframe));
  for (const Feature& f : features_.features())
    if (window_->position(f.id)) window_->setPatch(f.id, mapPointPatch(frame.grey, f.uv));
  if (added.reanchored) {
    // The board is back and the map re-anchored to it: this frame's pose from both, and the
    // fusion starts again from there. The pose graph moves the gap's keyframes, and their points
    // with them, but leaves part of the drift, so the map is trusted here as in the restart as
    // the board's first corners came back (fusion.map_drift_fraction). With the map trusted as
    // if no drift were left, configs/cslam_gradient.yaml's 30 frames from the return were 1.22 /
    // 1.51 times the settled error on board_leaves seeds 3 / 4, now 0.81 / 0.74 (README).
    result->reason = "board back: the gap's keyframes and map points re-anchored";
    if (const auto joint = boardAndMapPose(*board, xy, options_.fusion.map_drift_fraction * path_since_anchor_m_)) {
      if (mode_ == Mode::Combined && options_.fusion.enabled) fusion_.restartFrom(*joint);
      return joint->T_camera_world.inverse();
    }
  }
  // Without the board the window's refinement is the best pose; with it, the board fused with
  // the motion stands (the window refines the map around it).
  return board ? posed.T_world_camera : added.T_world_camera;
}

CslamTracker::MapCorrespondences CslamTracker::mapPointsSeen(const std::vector<Vec2>& xy,
                                                            bool barely_triangulated) const {
  MapCorrespondences m;
  const auto& features = features_.features();
  for (size_t i = 0; i < features.size(); ++i) {
    const auto p = barely_triangulated ? (mapPosition(features[i].id) ? std::nullopt : window_->position(features[i].id, true))
                                       : mapPosition(features[i].id);
    if (p) {
      m.p_world.push_back(*p);
      m.xy_normalised.push_back(xy[i]);
    }
  }
  return m;
}

BackendRegistration cslamBackend() {
  BackendRegistration r = makeRegistration<CslamOptions>(
      "cslam", "calibration integrated SLAM (thesis ch. 3): board pose, LK features, two-view motion, map",
      {{"combined", "cslam (combined)", "#1f77b4", "CSLAM with two-view"},
       {"calibration", "cslam calibration", "#d62728", "CSLAM without two-view"},
       {"two_view", "cslam two_view", "#2ca02c"}},
      /*takes_init=*/false, [](const TrackerContext& context, const CslamOptions& options) {
        if (!context.target)
          throw InputError("--target",
                           "cslam needs the chessboard target (target.yaml beside the sequence or --target)");
        cv::Size size = context.image_size;
        if (context.camera) size = cv::Size(context.camera->width, context.camera->height);
        return std::make_unique<CslamTracker>(context.camera, *context.target, size, context.mode, options,
                                              context.want_overlay);
      });
  r.stages = {"pyramid", "board", "features", "motion", "map"};
  return r;
}

}  // namespace slamcmp
