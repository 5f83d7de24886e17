#include "monoslam_ekf/monoslam_tracker.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <sstream>
#include <iomanip>

#include "core/chessboard.h"
#include "core/error.h"
#include "core/image.h"
#include "ekf/corner_selection.h"
#include "ekf/measurement_model.h"
#include "ekf/ekf_overlay.h"
#include "ekf/motion_model.h"
#include "geometry/homography_pose.h"

namespace slamcmp {

namespace {

std::string fixed(double value, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

// The four outer inner corners' pixels (ChessboardTarget::outerCornersWorld order) among all the
// inner corners (SPEC section 2 order).
std::vector<Vec2> outerCornerPixels(const ChessboardTarget& target, const std::vector<cv::Point2f>& uv_distorted) {
  const int c = target.cols, r = target.rows;
  const int index[4] = {0, c - 1, (r - 1) * c + c - 1, (r - 1) * c};
  std::vector<Vec2> out;
  for (int i : index) out.emplace_back(uv_distorted[i].x, uv_distorted[i].y);
  return out;
}

}  // namespace

MonoslamTracker::MonoslamTracker(const TrackerContext& context, const MonoslamOptions& options)
    : options_(options), init_(context.init), want_overlay_(context.want_overlay) {
  if (!context.camera)
    throw InputError("--camera", "the monoslam back-end needs a calibrated camera (camera.yaml)");
  if (!context.target)
    throw InputError("--target", "the monoslam back-end needs the board (target.yaml): its corners start the map");
  camera_ = *context.camera;
  target_ = *context.target;
  if (init_ != InitSource::Board) {
    if (!context.T_world_camera_init)
      throw InputError("--init", "groundtruth and manual initialisation need the first camera pose");
    T_world_camera_init_ = context.T_world_camera_init;
  }
}

nlohmann::json MonoslamTracker::options() const { return optionsToJson(options_); }

void MonoslamTracker::finish() {
  if (!ever_started_)
    throw InputError("", "monoslam never started: no frame showed the " + std::to_string(target_.cols) + "x" +
                             std::to_string(target_.rows) + " chessboard (--init board needs it in view)");
}

bool MonoslamTracker::start(const Frame& frame, std::string* reason) {
  std::vector<cv::Point2f> corners;
  const bool board_seen = detectChessboard(frame.grey, target_, &corners, options_.board);
  // A symmetric board's origin: the one nearest where the given pose, or the last pose before a
  // loss, puts it (else chooseSymmetricOrder's convention).
  const bool use_given_pose = init_ != InitSource::Board && !ever_started_;
  if (board_seen && target_.symmetric() && (use_given_pose || last_pose_))
    chooseSymmetricOrder(target_, corners,
                         projectBoardCorners(camera_, target_, use_given_pose ? *T_world_camera_init_ : *last_pose_));
  start_corners_.clear();
  if (board_seen)
    for (const cv::Point2f& c : corners) start_corners_.emplace_back(c.x, c.y);
  SE3 T_world_camera;
  // The given pose starts the run; every restart after a loss needs the board.
  if (use_given_pose) {
    T_world_camera = *T_world_camera_init_;
  } else if (board_seen) {
    std::vector<Vec2> xy_normalised;
    for (const Vec2& uv : start_corners_) xy_normalised.push_back(camera_.undistortPixel(uv));
    T_world_camera = boardPose(target_.cornersWorld(), xy_normalised, 0.5 * (camera_.fx + camera_.fy), {})
                         .T_camera_board.inverse();
  } else {
    *reason = "no board seen";
    return false;
  }

  const StartOptions& s = options_.start;
  const bool manual = init_ == InitSource::Manual && !ever_started_;
  const double sigma_r = manual ? s.manual_position_sigma : s.position_sigma;
  const double sigma_q = manual ? s.manual_orientation_sigma : s.orientation_sigma;
  Eigen::Matrix<double, 13, 13> P0 = Eigen::Matrix<double, 13, 13>::Zero();
  P0.diagonal() << Vec3::Constant(sigma_r * sigma_r), Vec4::Constant(sigma_q * sigma_q),
      Vec3::Constant(s.velocity_sigma * s.velocity_sigma),
      Vec3::Constant(s.angular_velocity_sigma * s.angular_velocity_sigma);
  state_.reset(T_world_camera, P0);
  features_.clear();

  // The known features: the board's outer inner corners, exact, with patches from this frame (at
  // the detected corners, or where the given pose projects them when the board is not detected).
  const std::vector<Vec3> corners_world = target_.outerCornersWorld();
  const std::vector<Vec2> detected = board_seen ? outerCornerPixels(target_, corners) : std::vector<Vec2>{};
  for (size_t k = 0; k < corners_world.size(); ++k) {
    Vec2 uv;
    if (board_seen) {
      uv = detected[k];
    } else {
      const Vec3 p_camera = T_world_camera.inverse() * corners_world[k];
      if (p_camera.z() <= 0) continue;
      uv = camera_.project(p_camera);
    }
    MapFeature f;
    if (!makePatchSource(frame.grey, uv, options_.search.source_size, T_world_camera, &f.source)) continue;
    f.source.normal_world = Vec3(0, 0, -1);  // the board plane z = 0, printed face towards -z
    f.id = next_id_++;
    f.known = true;
    f.offset = state_.append(corners_world[k], Mat3::Zero(), Eigen::MatrixXd::Zero(3, state_.size()));
    features_.push_back(std::move(f));
  }
  running_ = true;
  ever_started_ = true;
  frames_unmeasured_ = 0;
  last_timestamp_ = frame.timestamp;
  return true;
}

void MonoslamTracker::removeFeature(size_t index) {
  const int offset = features_[index].offset;
  const int dim = features_[index].is_ray ? 6 : 3;
  state_.remove(offset, dim);
  for (MapFeature& f : features_)
    if (f.offset > offset) f.offset -= dim;
  features_.erase(features_.begin() + static_cast<long>(index));
}

void MonoslamTracker::updateRays(const Frame& frame) {
  const FeatureInitOptions& fo = options_.feature_init;
  for (size_t i = 0; i < features_.size();) {
    MapFeature& f = features_[i];
    if (!f.is_ray) {
      ++i;
      continue;
    }
    ++f.ray_frames;
    updateDepthParticles(state_, f.offset, camera_, frame.grey, f.ray_template, options_.search,
                         fo.prune_threshold, &f.particles);
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

void MonoslamTracker::manageMap(const Frame& frame) {
  const MapManagementOptions& mo = options_.map;
  for (size_t i = 0; i < features_.size();) {
    const MapFeature& f = features_[i];
    if (!f.is_ray && f.attempts >= mo.min_attempts && f.successes < mo.min_success_ratio * f.attempts)
      removeFeature(i);
    else
      ++i;
  }

  const FeatureInitOptions& fo = options_.feature_init;
  const int rays = static_cast<int>(std::count_if(features_.begin(), features_.end(),
                                                  [](const MapFeature& f) { return f.is_ray; }));
  if (visible_ >= fo.min_visible || rays >= fo.max_initialising ||
      static_cast<int>(features_.size()) >= mo.max_features)
    return;
  std::vector<Vec2> occupied;
  for (const MapFeature& f : features_) {
    const Vec3 y = f.is_ray ? Vec3(state_.x().segment<3>(f.offset) + f.particles.mean() * state_.x().segment<3>(f.offset + 3))
                            : Vec3(state_.x().segment<3>(f.offset));
    PointMeasurement m;
    if (predictMeasurement(camera_, state_.r(), state_.q(), y, &m)) occupied.push_back(m.uv_distorted);
  }
  Vec2 uv;
  const int margin = options_.search.source_size / 2 + 1;
  if (!findCornerInFreeBox(frame.grey, occupied, fo, margin, rng_, &uv)) return;
  MapFeature f;
  if (!makePatchSource(frame.grey, uv, options_.search.source_size, state_.T_world_camera(), &f.source) ||
      !sourceTemplate(f.source, options_.search.patch_size, &f.ray_template) ||
      patchStdDev(f.ray_template) < options_.search.min_patch_stddev)
    return;
  f.id = next_id_++;
  f.is_ray = true;
  f.offset = appendRay(state_, camera_, uv, options_.search.pixel_sigma);
  f.particles = uniformParticles(fo.particles, fo.min_depth, fo.max_depth);
  features_.push_back(std::move(f));
}

std::string MonoslamTracker::divergence() const {
  const HealthOptions& ho = options_.health;
  if (!state_.x().allFinite() || !state_.P().allFinite()) return "diverged: state or covariance not finite";
  if ((state_.P().diagonal().array() < -1e-9).any()) return "diverged: negative variance";
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 13, 13>> camera_eig(
      state_.P().topLeftCorner<13, 13>(), Eigen::EigenvaluesOnly);
  if (camera_eig.eigenvalues()(0) < -1e-9 * std::max(1.0, camera_eig.eigenvalues()(12)))
    return "diverged: camera covariance not positive semi-definite";
  const double position_sigma = std::sqrt(
      Eigen::SelfAdjointEigenSolver<Mat3>(state_.P().topLeftCorner<3, 3>(), Eigen::EigenvaluesOnly).eigenvalues()(2));
  if (position_sigma > ho.max_position_sigma)
    return "diverged: camera position std " + fixed(position_sigma, 2) + " m";
  if (state_.v().norm() > ho.max_speed) return "diverged: speed " + fixed(state_.v().norm(), 1) + " m/s";
  if (state_.w().norm() > ho.max_angular_speed)
    return "diverged: angular speed " + fixed(state_.w().norm(), 1) + " rad/s";
  if (frames_unmeasured_ >= ho.max_frames_unmeasured)
    return "no feature matched for " + std::to_string(frames_unmeasured_) + " frames";
  return "";
}

FrameResult MonoslamTracker::track(const Frame& frame) {
  FrameResult result;
  if (!running_) {
    std::string reason;
    if (!start(frame, &reason)) {
      result.status = ever_started_ ? TrackStatus::Lost : TrackStatus::Initialising;
      result.reason = ever_started_ ? lost_reason_ + "; " + reason : reason;
      return result;
    }
    manageMap(frame);
    if (want_overlay_) {
      result.overlay = ekfOverlay(state_, features_, FrameMeasurement(), camera_, target_, options_.search.patch_size);
      result.overlay->board_corners = start_corners_;
    }
  } else {
    double dt = frame.timestamp - last_timestamp_;
    if (!(dt > 0)) dt = options_.motion.default_dt;
    last_timestamp_ = frame.timestamp;
    predict(state_, dt, options_.motion);
    const FrameMeasurement measurement = measureFeatures(state_, features_, camera_, frame.grey, options_.search);
    visible_ = measurement.visible;
    result.measured = measurement.matched;
    // Before updateRays and manageMap, which may remove features `measurement` points into.
    if (want_overlay_)
      result.overlay = ekfOverlay(state_, features_, measurement, camera_, target_, options_.search.patch_size);
    frames_unmeasured_ = result.measured > 0 ? 0 : frames_unmeasured_ + 1;
    updateRays(frame);
    manageMap(frame);
    const std::string why = divergence();
    if (!why.empty()) {
      running_ = false;
      lost_reason_ = why;
      features_.clear();
      result.status = TrackStatus::Lost;
      result.reason = why;
      return result;
    }
  }
  result.status = TrackStatus::Tracked;
  result.source = "ekf";
  result.T_world_camera = last_pose_ = state_.T_world_camera();
  result.features = static_cast<int>(features_.size());
  if (result.measured == 0 && frames_unmeasured_ > 0) result.reason = "no feature matched: prediction only";
  return result;
}

std::vector<MapPoint> MonoslamTracker::mapPoints() const {
  std::vector<MapPoint> points;
  if (!running_) return points;
  for (const MapFeature& f : features_) {
    if (f.is_ray) continue;
    MapPoint p;
    p.id = f.id;
    p.p_world = state_.x().segment<3>(f.offset);
    p.observations = f.successes;
    // The ellipsoid's largest semi-axis: sqrt of the largest eigenvalue of the point's covariance.
    const Mat3 P_y = state_.P().block<3, 3>(f.offset, f.offset);
    p.sigma = std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Mat3>(P_y, Eigen::EigenvaluesOnly).eigenvalues()(2)));
    points.push_back(p);
  }
  return points;
}

BackendRegistration monoslamBackend() {
  return makeRegistration<MonoslamOptions>(
      "monoslam", "the MonoSLAM baseline (Davison 2007, SceneLib defaults): EKF, particle depths, 11x11 patches",
      {{"ekf", "monoslam", "#000000", "MonoSLAM"}}, /*takes_init=*/true,
      [](const TrackerContext& context, const MonoslamOptions& options) {
        return std::make_unique<MonoslamTracker>(context, options);
      });
}

}  // namespace slamcmp
