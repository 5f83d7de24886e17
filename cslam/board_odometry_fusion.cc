#include "cslam/board_odometry_fusion.h"

#include <algorithm>

#include "core/error.h"

namespace slamcmp {

void BoardOdometryFusionOptions::check() const {
  if (!(min_pixel_sigma > 0)) throw OptionError("min_pixel_sigma", "must be positive");
  if (!(motion_noise_scale > 0)) throw OptionError("motion_noise_scale", "must be positive");
  if (!(max_mahalanobis2 > 0)) throw OptionError("max_mahalanobis2", "must be positive");
  if (!(fast_rotation_deg > 0)) throw OptionError("fast_rotation_deg", "must be positive");
  if (!(max_motion_residual_px > 0)) throw OptionError("max_motion_residual_px", "must be positive");
  if (max_held_frames < 0) throw OptionError("max_held_frames", "must be 0 or more");
  if (!(map_drift_fraction >= 0 && map_drift_fraction <= 1))
    throw OptionError("map_drift_fraction", "must be between 0 and 1");
}

PoseWithCovariance poseWithCovariance(const SE3& T_camera_world, const std::vector<Vec3>& p_world,
                                      const std::vector<Vec2>& xy_normalised, double focal_px, double rms_px,
                                      double min_sigma_px) {
  // rms_px is the RMS of the 2-D residual: 2n coordinates, 6 pose parameters fitted.
  const double n = static_cast<double>(p_world.size());
  const double sigma2 = std::max(rms_px * rms_px * n / std::max(2 * n - 6, 1.0), min_sigma_px * min_sigma_px);
  const Mat6 H = reprojectionHessian(T_camera_world, p_world, xy_normalised, focal_px);
  return {T_camera_world, sigma2 * H.completeOrthogonalDecomposition().pseudoInverse()};
}

void BoardOdometryFusion::reset() {
  fused_.reset();
  held_ = 0;
}

SE3 BoardOdometryFusion::update(const PoseWithCovariance& board, const std::optional<MapMotion>& map_motion,
                                const PoseWithCovariance* start) {
  if (!fused_ || !map_motion) {
    restartFrom(start ? *start : board);
    return fused_->T_camera_world;
  }
  const PoseWithCovariance* map_prev = &map_motion->previous;
  const PoseWithCovariance* map_pose = &map_motion->current;
  // Prediction: the previous fused pose moved by the features' motion (both map poses hold the
  // map's error alike, so it cancels in their difference). The covariance is carried over without
  // the motion's adjoint: frame-to-frame motion is small.
  const SE3 motion = map_pose->T_camera_world * map_prev->T_camera_world.inverse();
  const double fast = rotationAngle(motion.R()) * 180 / M_PI / options_.fast_rotation_deg;
  PoseWithCovariance predicted{motion * fused_->T_camera_world,
                               fused_->covariance + options_.motion_noise_scale * (1 + fast * fast) * map_pose->covariance};
  const double s = options_.motion_scale_sigma;
  predicted.covariance.bottomRightCorner<3, 3>() += s * s * motion.t() * motion.t().transpose();
  // Update with the board pose as the measurement (Kalman, in the tangent space of the prediction).
  const Vec6 innovation = poseDifference(board.T_camera_world, predicted.T_camera_world);
  // An innovation beyond the gate: in its first frame(s) the board pose is taken for the outlier
  // and the prediction stands; past max_held_frames the prediction is worse than its covariance
  // says (the map moved, a missed frame): its covariance is inflated until the innovation fits (a
  // fading memory), so a jump hands the pose to the board without losing the filter.
  Eigen::LDLT<Mat6> S_ldlt(predicted.covariance + board.covariance);
  double m2 = innovation.dot(S_ldlt.solve(innovation));
  if (m2 > options_.max_mahalanobis2 && held_ < options_.max_held_frames) {
    ++held_;
    fused_ = predicted;
    return fused_->T_camera_world;
  }
  held_ = 0;
  for (int i = 0; i < 20 && m2 > options_.max_mahalanobis2; ++i) {
    predicted.covariance *= m2 / options_.max_mahalanobis2;
    S_ldlt.compute(predicted.covariance + board.covariance);
    m2 = innovation.dot(S_ldlt.solve(innovation));
  }
  const Mat6 K = predicted.covariance * S_ldlt.solve(Mat6::Identity());
  const Mat6 P = (Mat6::Identity() - K) * predicted.covariance;
  fused_ = PoseWithCovariance{applyPoseDelta(predicted.T_camera_world, K * innovation), 0.5 * (P + P.transpose())};
  return fused_->T_camera_world;
}

}  // namespace slamcmp
