#include "ekf/ekf_slam.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include <Eigen/Eigenvalues>

#include "core/image.h"
#include "ekf/corner_selection.h"
#include "ekf/ekf_overlay.h"
#include "ekf/inverse_depth.h"
#include "ekf/measurement_model.h"
#include "ekf/motion_model.h"
#include "ekf/rolling_shutter.h"

namespace slamcmp {

namespace {

std::string fixed(double value, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

Mat3 rotationOf(const Vec4& q) { return Quat(q(0), q(1), q(2), q(3)).normalized().toRotationMatrix(); }

}  // namespace

EkfSlam::EkfSlam(const CameraModel& camera, const EkfSlamOptions& options, bool board_free,
                 const RelocalisationOptions* relocalisation)
    : camera_(camera),
      options_(options),
      inverse_depth_(usesOption(options.inverse_depth.use, board_free)),
      board_free_(board_free),
      ransac_(usesOption(options.ransac.use, board_free)),
      distinct_(usesOption(options.feature_init.distinct, board_free)) {
  if (relocalisation && relocalisation->enabled) relocaliser_ = std::make_unique<Relocaliser>(*relocalisation);
}

void EkfSlam::reset(const SE3& T_world_camera, const Eigen::Matrix<double, 13, 13>& P_camera) {
  state_.reset(T_world_camera, P_camera);
  search_reach_px_ = std::numeric_limits<double>::infinity();
  motion_noise_.restart();
  features_.clear();
  posed_map_.reset();  // a new map: nothing of the old one relocalises it
  retired_.clear();
  scale_gauge_pending_ = board_free_ && inverse_depth_ && options_.inverse_depth.scale_gauge_sigma > 0;
}

void EkfSlam::fixScaleGauge() {
  std::vector<int> offsets;
  for (const MapFeature& f : features_)
    if (f.inverse_depth) offsets.push_back(f.offset);
  scale_gauge_pending_ = offsets.empty();
  const InverseDepthOptions& io = options_.inverse_depth;
  constrainMeanInverseDepth(state_, offsets, io.rho0, io.scale_gauge_sigma);
}

bool EkfSlam::addKnownPoint(const cv::Mat& grey, const Vec2& uv, const Vec3& p_world, const Vec3& normal_world) {
  MapFeature f;
  if (!makePatchSource(grey, uv, options_.search.source_size, state_.T_world_camera(), &f.source)) return false;
  f.source.normal_world = normal_world;
  f.id = next_id_++;
  f.known = true;
  f.offset = state_.append(p_world, Mat3::Zero(), Eigen::MatrixXd::Zero(3, state_.size()));
  features_.push_back(std::move(f));
  return true;
}

void EkfSlam::predict(double dt) {
  const double step = dt > 0 ? dt : options_.motion.default_dt;
  slamcmp::predict(state_, step, motion_noise_.next(state_, step));
}

FrameMeasurement EkfSlam::measure(const cv::Mat& grey) {
  FrameMeasurement m =
      measureFeatures(state_, features_, camera_, grey, options_.search, ransac_ ? &options_.ransac : nullptr, &rng_);
  if (distinct_) {
    double reach = 0;  // the widest search's
    for (const FeatureSearch& f : m.features)
      if (f.outcome != SearchOutcome::Unmeasured) reach = std::max(reach, f.half_axis);
    if (reach > 0) search_reach_px_ = reach;
  }
  return m;
}

void EkfSlam::updateMap(const cv::Mat& grey, int visible, const std::vector<Vec2>& keep_clear) {
  updateRays(grey);
  convertLinearFeatures();
  pruneAndGrow(grey, visible, keep_clear);
}

void EkfSlam::removeFeature(size_t index) {
  const int offset = features_[index].offset;
  const int dim = features_[index].dim();
  state_.remove(offset, dim);
  for (MapFeature& f : features_)
    if (f.offset > offset) f.offset -= dim;
  features_.erase(features_.begin() + static_cast<long>(index));
}

void EkfSlam::updateRays(const cv::Mat& grey) {
  const FeatureInitOptions& fo = options_.feature_init;
  for (size_t i = 0; i < features_.size();) {
    MapFeature& f = features_[i];
    if (!f.is_ray) {
      ++i;
      continue;
    }
    ++f.ray_frames;
    updateDepthParticles(state_, f.offset, camera_, grey, f.ray_template, options_.search, fo.prune_threshold,
                         &f.particles);
    const double mean = f.particles.mean(), stddev = f.particles.stddev();
    if (f.particles.size() >= 1 && stddev < fo.promote_ratio * mean) {
      // Particles are spaced (max - min)/(n - 1) apart: add that quantisation to the variance.
      const double spacing = (fo.max_depth - fo.min_depth) / (fo.particles - 1);
      const int ray_offset = f.offset;
      const int point_offset = promoteRay(state_, ray_offset, mean, stddev * stddev + spacing * spacing / 12);
      for (MapFeature& g : features_)
        if (g.offset > ray_offset) g.offset -= 6;
      f.offset = point_offset;
      f.is_ray = false;
      f.particles = DepthParticles();
      ++i;
    } else if (f.particles.size() < fo.min_particles || f.ray_frames > fo.max_frames) {
      removeFeature(i);
    } else {
      ++i;
    }
  }
}

void EkfSlam::convertLinearFeatures() {
  for (MapFeature& f : features_) {
    if (!f.inverse_depth || linearityIndex(state_, f.offset) >= options_.inverse_depth.linearity_threshold) continue;
    const int id_offset = f.offset;
    f.offset = convertToPoint(state_, id_offset);
    f.inverse_depth = false;
    for (MapFeature& g : features_)
      if (&g != &f && g.offset > id_offset) g.offset -= 6;
  }
}

void EkfSlam::pruneAndGrow(const cv::Mat& grey, int visible, const std::vector<Vec2>& keep_clear) {
  const MapManagementOptions& mo = options_.map;
  for (size_t i = 0; i < features_.size();) {
    const MapFeature& f = features_[i];
    const bool poor_record = f.attempts >= mo.min_attempts && f.successes < mo.min_success_ratio * f.attempts;
    // A board's known corners fix the map's scale and are never added again: only their record judges them.
    const bool missed_in_a_row =
        !f.known && mo.max_misses_in_a_row > 0 && f.misses_in_a_row >= mo.max_misses_in_a_row;
    if (!f.is_ray && f.id >= protected_below_ && (poor_record || missed_in_a_row))
      removeFeature(i);
    else
      ++i;
  }

  const FeatureInitOptions& fo = options_.feature_init;
  const int rays = static_cast<int>(
      std::count_if(features_.begin(), features_.end(), [](const MapFeature& f) { return f.is_ray; }));
  // A ray a frame while fewer than max_initialising wait for their particles; inverse-depth
  // features are measured at once, several a frame.
  const int wanted = inverse_depth_ ? std::min(fo.min_visible - visible, options_.inverse_depth.new_per_frame)
                                    : std::min(1, fo.max_initialising - rays);
  if (visible >= fo.min_visible || wanted <= 0) return;
  std::vector<Vec2> occupied = keep_clear;
  for (const MapFeature& f : features_) {
    PointMeasurement m;
    if (predictMeasurement(camera_, state_.r(), state_.q(), featurePoint(state_.x(), f), &m))
      occupied.push_back(m.uv_distorted);
  }
  for (int k = 0; k < wanted && static_cast<int>(features_.size()) < mo.max_features; ++k)
    if (!addFeature(grey, occupied)) break;
  if (scale_gauge_pending_) fixScaleGauge();
}

bool EkfSlam::addFeature(const cv::Mat& grey, std::vector<Vec2>& occupied) {
  const FeatureInitOptions& fo = options_.feature_init;
  Vec2 uv;
  const int margin = options_.search.source_size / 2 + 1;
  // Without a board the first searches are wide: a corner with a look-alike where they reach (the
  // last frame's widest, at most distinct_radius) is taken only when no free box offers one
  // without. Too flat a patch is refused below; with a choice of corners it is passed over here.
  const int size = options_.search.patch_size;
  const int radius = static_cast<int>(std::min<double>(fo.distinct_radius, std::ceil(search_reach_px_)));
  const auto distinct = [&](const Vec2& corner) {
    return hasNoLookAlike(grey, corner, size, radius, options_.search.min_ncc);
  };
  const auto textured = [&](const Vec2& corner) {
    const std::optional<cv::Rect> patch = patchAround(grey, corner, size);
    return patch && patchStdDev(grey(*patch)) >= options_.search.min_patch_stddev;
  };
  if (!findCornerInFreeBox(grey, occupied, fo, margin, rng_, &uv,
                           distinct_ ? distinct : std::function<bool(const Vec2&)>(), textured))
    return false;
  MapFeature f;
  if (!makePatchSource(grey, uv, options_.search.source_size, state_.T_world_camera(), &f.source) ||
      !sourceTemplate(f.source, options_.search.patch_size, &f.ray_template) ||
      patchStdDev(f.ray_template) < options_.search.min_patch_stddev)
    return false;
  f.id = next_id_++;
  if (relocaliser_) f.descriptor = relocaliser_->describe(grey, uv);
  // Its ray from the camera at the frame's time (the state's), not at its row's.
  const Vec2 uv_frame_time = pixelAtFrameTime(camera_, options_.search.rolling_shutter_readout, state_.w(), uv);
  if (inverse_depth_) {
    const InverseDepthOptions& io = options_.inverse_depth;
    f.inverse_depth = true;
    f.ray_template.release();  // only rays search with the unwarped template
    f.offset = appendInverseDepthFeature(state_, camera_, uv_frame_time, options_.search.pixel_sigma, io.rho0,
                                         io.rho_sigma);
    if (f.offset < 0) return false;
  } else {
    f.is_ray = true;
    f.offset = appendRay(state_, camera_, uv_frame_time, options_.search.pixel_sigma);
    f.particles = uniformParticles(fo.particles, fo.min_depth, fo.max_depth);
  }
  features_.push_back(std::move(f));
  occupied.push_back(uv);
  return true;
}

std::string EkfSlam::divergence() const {
  const HealthOptions& ho = options_.health;
  if (!state_.x().allFinite() || !state_.P().allFinite()) return "diverged: state or covariance not finite";
  if ((state_.P().diagonal().array() < -1e-9).any()) return "diverged: negative variance";
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 13, 13>> camera_eig(state_.P().topLeftCorner<13, 13>(),
                                                                                Eigen::EigenvaluesOnly);
  if (camera_eig.eigenvalues()(0) < -1e-9 * std::max(1.0, camera_eig.eigenvalues()(12)))
    return "diverged: camera covariance not positive semi-definite";
  const double position_sigma = largestStd(state_.P().topLeftCorner<3, 3>());
  if (position_sigma > ho.max_position_sigma) return "diverged: camera position std " + fixed(position_sigma, 2) + " m";
  if (state_.v().norm() > ho.max_speed) return "diverged: speed " + fixed(state_.v().norm(), 1) + " m/s";
  if (state_.w().norm() > ho.max_angular_speed)
    return "diverged: angular speed " + fixed(state_.w().norm(), 1) + " rad/s";
  return "";
}

PoseCovariance EkfSlam::poseCovariance() const {
  // e = log(R(q') R(q)^T) for q' near q: its 3x4 Jacobian by central differences (the quaternion
  // is normalised inside R, so the direction along q itself maps to zero, as it should).
  const Vec4 q = state_.q();
  const Mat3 R_t = rotationOf(q).transpose();
  Eigen::Matrix<double, 3, 4> J;
  const double h = 1e-6;
  for (int i = 0; i < 4; ++i) {
    Vec4 dq = Vec4::Zero();
    dq(i) = h;
    J.col(i) = (rotvecFromRotation(rotationOf(q + dq) * R_t) - rotvecFromRotation(rotationOf(q - dq) * R_t)) / (2 * h);
  }
  Eigen::Matrix<double, 6, 7> G = Eigen::Matrix<double, 6, 7>::Zero();
  G.topLeftCorner<3, 3>().setIdentity();
  G.bottomRightCorner<3, 4>() = J;
  const PoseCovariance P = G * state_.P().topLeftCorner<7, 7>() * G.transpose();
  return 0.5 * (P + P.transpose());
}

namespace {

struct RelocalisationPoint {
  Vec3 p_world;
  Mat3 P_world;  // its covariance
};

// A feature's point for relocalisation; none for a ray, a feature without a descriptor, or an
// inverse-depth one whose depth is still unknown (rho within two std of 0).
std::optional<RelocalisationPoint> relocalisationPoint(const EkfState& state, const MapFeature& f) {
  if (f.is_ray || f.descriptor.empty()) return std::nullopt;
  if (f.inverse_depth) {
    const double rho = state.x()(f.offset + 5), var = state.P()(f.offset + 5, f.offset + 5);
    if (!(rho > 2 * std::sqrt(std::max(0.0, var)))) return std::nullopt;
  }
  const Vec3 p = featurePoint(state.x(), f);
  if (!p.allFinite()) return std::nullopt;
  return RelocalisationPoint{p, featurePointCovariance(state, f)};
}

}  // namespace

void EkfSlam::rememberPosedMap() {
  if (!relocaliser_) return;  // only relocalisation reads it: no copy a frame for the others
  if (posed_map_ && relocaliser_->options().retired_points > 0) {
    // Both in id order (features are appended as ids grow): the last map's features now gone.
    auto now = features_.begin();
    for (const MapFeature& f : posed_map_->features) {
      while (now != features_.end() && now->id < f.id) ++now;
      if (now != features_.end() && now->id == f.id) continue;
      if (const std::optional<RelocalisationPoint> point = relocalisationPoint(posed_map_->state, f))
        retired_.push_front(RetiredPoint{point->p_world, point->P_world, f.descriptor});
    }
    while (static_cast<int>(retired_.size()) > relocaliser_->options().retired_points) retired_.pop_back();
  }
  if (!posed_map_) posed_map_.emplace();
  posed_map_->state = state_;  // into the storage of the last copy: no allocation while the map keeps its size
  posed_map_->features = features_;
}

std::optional<SE3> EkfSlam::relocalise(const cv::Mat& grey, int below_id, int* inliers) const {
  *inliers = 0;
  const EkfState& state = posed_map_ ? posed_map_->state : state_;
  if (!relocaliser_ || !state.x().allFinite() || !state.P().allFinite()) return std::nullopt;
  std::vector<Vec3> p_world;
  std::vector<Mat3> P_points;  // each point's world covariance
  cv::Mat descriptors;
  for (const MapFeature& f : posed_map_ ? posed_map_->features : features_) {
    if (f.id >= below_id) continue;
    if (const std::optional<RelocalisationPoint> point = relocalisationPoint(state, f)) {
      p_world.push_back(point->p_world);
      P_points.push_back(point->P_world);
      descriptors.push_back(f.descriptor);
    }
  }
  for (const RetiredPoint& r : retired_) {
    p_world.push_back(r.p_world);
    P_points.push_back(r.P_world);
    descriptors.push_back(r.descriptor);
  }
  // The filter runs on while lost: its own pose (the last frame's, not yet predicted to this one)
  // guides a second search.
  const SE3 T_world_camera_guess = state_.T_world_camera();
  const bool guided = state_.x().head<7>().allFinite();
  return relocaliser_->relocalise(grey, camera_, p_world, P_points, descriptors, inliers,
                                  guided ? &T_world_camera_guess : nullptr);
}

void EkfSlam::relocate(const SE3& T_world_camera, const Eigen::Matrix<double, 13, 13>& P_camera, int below_id) {
  if (posed_map_) {
    state_ = posed_map_->state;
    features_ = posed_map_->features;
  }
  for (size_t i = features_.size(); i-- > 0;)
    if (features_[i].id >= below_id) removeFeature(i);
  for (MapFeature& f : features_) f.attempts = f.successes, f.misses_in_a_row = 0;
  Eigen::VectorXd& x = state_.x();
  x.segment<3>(EkfState::kR) = T_world_camera.t();
  x.segment<4>(EkfState::kQ) = quatVector(T_world_camera.quat());
  x.segment<6>(EkfState::kV).setZero();
  Eigen::MatrixXd& P = state_.P();
  P.topRows<EkfState::kCameraDim>().setZero();
  P.leftCols<EkfState::kCameraDim>().setZero();
  P.topLeftCorner<EkfState::kCameraDim, EkfState::kCameraDim>() = P_camera;
  motion_noise_.restart();
}

std::vector<MapPoint> EkfSlam::mapPoints() const {
  std::vector<MapPoint> points;
  for (const MapFeature& f : features_) {
    if (f.dim() != 3) continue;  // rays and inverse-depth features are not points yet
    MapPoint p;
    p.id = f.id;
    p.p_world = state_.x().segment<3>(f.offset);
    p.observations = f.successes;
    p.sigma = largestStd(state_.P().block<3, 3>(f.offset, f.offset));  // its ellipsoid's largest semi-axis
    points.push_back(p);
  }
  return points;
}

FrameOverlay EkfSlam::overlay(const FrameMeasurement& measurement, const ChessboardTarget& target) const {
  return ekfOverlay(state_, features_, measurement, camera_, target, options_.search.patch_size);
}

}  // namespace slamcmp
