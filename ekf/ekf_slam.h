#pragma once
// The MonoSLAM filter shared by the EKF back-ends (SPEC section 5): the state and its map of
// features, predicted with the constant-velocity model, measured by active patch search, grown by
// depth-particle rays in free image boxes and pruned of features that fail. A back-end decides when
// it starts and what else it measures (monoslam: four board corners in the state; hybrid: every
// board corner as a known landmark).
#include <deque>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/frame_overlay.h"
#include "core/target.h"
#include "core/tracker.h"
#include "ekf/adaptive_motion_noise.h"
#include "ekf/ekf_options.h"
#include "ekf/ekf_state.h"
#include "ekf/frame_measurement.h"
#include "ekf/map_feature.h"
#include "ekf/relocaliser.h"

namespace slamcmp {

// The filter's options, listed flat in the back-ends' own option structs (their YAML sections
// keep `motion:`, `search:`, ... at the top): visitFilterOptions is that list.
struct EkfSlamOptions {
  MotionModelOptions motion;
  ActiveSearchOptions search;
  FeatureInitOptions feature_init;
  MapManagementOptions map;
  HealthOptions health;
  ReportingOptions reporting;
  InverseDepthOptions inverse_depth;  // board-free start (issue 18)
  OnePointRansacOptions ransac;
};

template <class V>
void visitFilterOptions(V& v, EkfSlamOptions& o) {
  v("motion", o.motion, "constant-velocity motion model");
  v("search", o.search, "active search");
  v("feature_init", o.feature_init, "new features: rays with depth particles");
  v("map", o.map, "map size and deletion");
  v("health", o.health, "divergence detection");
  v("reporting", o.reporting, "when frames are reported lost instead of extrapolated");
  v("inverse_depth", o.inverse_depth, "features in inverse depth (Civera 2008; board-free start)");
  v("ransac", o.ransac, "1-point RANSAC update (Civera 2010; board-free start)");
}

class EkfSlam {
 public:
  // board_free: the map starts from nothing (`--init none`), which turns the "auto" of
  // inverse_depth.use, ransac.use and feature_init.distinct on. relocalisation (enabled): features
  // keep descriptors and relocalise() can find a lost camera again.
  EkfSlam(const CameraModel& camera, const EkfSlamOptions& options, bool board_free = false,
          const RelocalisationOptions* relocalisation = nullptr);

  // The camera alone at T_world_camera with covariance P_camera (13x13); the map is cleared.
  void reset(const SE3& T_world_camera, const Eigen::Matrix<double, 13, 13>& P_camera);
  // A feature at an exactly known world point (zero covariance), its template cut from `grey`
  // around uv. False if the template cannot be cut there.
  bool addKnownPoint(const cv::Mat& grey, const Vec2& uv, const Vec3& p_world, const Vec3& normal_world);

  // The motion model over dt seconds (default_dt when dt is not positive), its noise adapted to
  // the filter's velocity corrections when motion.adaptive is on.
  void predict(double dt);
  // The motion noise back to its set values (motion.adaptive): the filter was found too sure of
  // its motion (the board where it did not expect it).
  void distrustMotion() { motion_noise_.restart(); }
  // The motion noise of the last prediction (adapted, or as set).
  const MotionModelOptions& motionNoise() const { return motion_noise_.current(); }
  // Active search of the map's points and their update (frame_measurement.h).
  FrameMeasurement measure(const cv::Mat& grey);
  // Depth particles of the initialising rays weighted in this frame; converged rays become points,
  // failed ones are dropped; inverse-depth features linear enough become points. Then features
  // failing too often are deleted and, when too few are visible, a new ray (or up to
  // inverse_depth.new_per_frame inverse-depth features) is started in image boxes free of features
  // and of `keep_clear` (pixels, e.g. a board's corners: its repeated squares are a patch search's
  // worst case).
  void updateMap(const cv::Mat& grey, int visible, const std::vector<Vec2>& keep_clear = {});

  // Whether features keep descriptors and lost frames can be relocalised.
  bool relocalises() const { return relocaliser_ != nullptr; }
  // T_world_camera found again from the map's features with ids under `below_id` (those mapped
  // while the frames were posed), and the points of the features deleted while posed (the last
  // relocalisation.retired_points), matched in `grey` (then near where the filter's own pose
  // projects them); nullopt if too few agree, or the map is not finite. *inliers: how many agreed.
  std::optional<SE3> relocalise(const cv::Mat& grey, int below_id, int* inliers) const;
  // The camera moved to T_world_camera with covariance P_camera, at rest, uncorrelated with the
  // map, which keeps its features under `below_id` (the others were mapped from a lost pose) with
  // their failed searches forgotten.
  void relocate(const SE3& T_world_camera, const Eigen::Matrix<double, 13, 13>& P_camera, int below_id);
  // Keeps the filter as it is now, a posed frame's (with relocalisation; else nothing): relocalise() matches
  // against that map and relocate() resumes from it, so the lost frames' own updates (look-alikes
  // matched from a wrong pose, moving the map through its correlations) never reach it. The
  // features the last posed map had and this one has not are kept as retired points.
  void rememberPosedMap();
  // Features with ids under `id` are not deleted for failing (while the frames are lost their
  // searches fail for the pose's fault, not theirs); 0 lifts it.
  void protectFeaturesBelow(int id) { protected_below_ = id; }

  // Why the filter cannot be trusted ("" if it can): not finite, not positive semi-definite, a
  // position std, speed or angular speed beyond the health options.
  std::string divergence() const;

  const EkfState& state() const { return state_; }
  EkfState& state() { return state_; }
  const std::vector<MapFeature>& features() const { return features_; }
  int nextFeatureId() const { return next_id_; }  // ids grow: a feature mapped later has a larger one
  SE3 T_world_camera() const { return state_.T_world_camera(); }
  PoseCovariance poseCovariance() const;
  std::vector<MapPoint> mapPoints() const;  // points (not rays), known ones included
  // What the filter saw this frame; call before updateMap (which may remove measured features).
  FrameOverlay overlay(const FrameMeasurement& measurement, const ChessboardTarget& target) const;

 private:
  void removeFeature(size_t index);
  // Board-free: the first frame's features fix the map's scale (inverse_depth.scale_gauge_sigma).
  void fixScaleGauge();
  void updateRays(const cv::Mat& grey);
  void convertLinearFeatures();
  // A new feature at the strongest corner of a free box, or without a board the strongest with no
  // look-alike (a ray, or in inverse depth); false if none.
  bool addFeature(const cv::Mat& grey, std::vector<Vec2>& occupied);
  void pruneAndGrow(const cv::Mat& grey, int visible, const std::vector<Vec2>& keep_clear);

  CameraModel camera_;
  EkfSlamOptions options_;
  bool inverse_depth_ = false;  // new features in inverse depth, not depth particles
  bool board_free_ = false;
  bool scale_gauge_pending_ = false;  // board-free: the first features' mean inverse depth not yet fixed
  bool ransac_ = false;         // 1-point RANSAC instead of joint compatibility
  bool distinct_ = false;       // new corners preferably without look-alikes (feature_init.distinct)
  EkfState state_;
  AdaptiveMotionNoise motion_noise_{options_.motion};
  std::vector<MapFeature> features_;
  int next_id_ = 0;
  int protected_below_ = 0;
  std::unique_ptr<Relocaliser> relocaliser_;  // when relocalisation is used
  struct PosedMap {
    EkfState state;
    std::vector<MapFeature> features;
  };
  std::optional<PosedMap> posed_map_;  // rememberPosedMap()'s
  // A deleted feature's point as its last posed map knew it: a camera turning about a room sees
  // the features it deleted again (tum_fr1_rpy: the filter holds about 40, a relocalisation
  // matched 3-10 of them).
  struct RetiredPoint {
    Vec3 p_world;
    Mat3 P_world;
    cv::Mat descriptor;
  };
  std::deque<RetiredPoint> retired_;  // newest first
  // How far the last frame's searches reached (3-sigma half axis, pixels; with distinct_),
  // unbounded before any.
  double search_reach_px_ = std::numeric_limits<double>::infinity();
  std::mt19937 rng_{static_cast<std::mt19937::result_type>(options_.feature_init.seed)};
};

}  // namespace slamcmp
