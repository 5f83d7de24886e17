#pragma once
// One frame's measurement of the map (SPEC section 5, Davison et al. 2007 section 3.5): predict
// every point and its innovation covariance, search the ellipses of the most uncertain ones with
// their warped templates, choose jointly compatible matches and update the EKF in one batch.
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "ekf/ekf_state.h"
#include "ekf/map_feature.h"
#include "ekf/ekf_options.h"
#include "ekf/measurement_model.h"

namespace slamcmp {

enum class SearchOutcome {
  Unmeasured,  // predicted in the image, not selected (or its ellipse was too large)
  Matched,     // searched, and its match was used in the update
  Failed,      // searched (or selected but its template was unusable), no match kept
};

struct FeatureSearch {
  size_t index = 0;                    // into the feature list
  Vec2 uv_predicted = Vec2::Zero();    // prior prediction at the frame's time, distorted pixels
  Vec2 rolling_shift = Vec2::Zero();   // pixels its row's read moves it (rolling_shutter.h): searched at the sum
  Mat2 S = Mat2::Identity();           // its innovation covariance, pixels^2
  double half_axis = 0;                // its search ellipse's half major axis (sigma_gate), pixels
  SearchOutcome outcome = SearchOutcome::Unmeasured;
  Vec2 uv_matched = Vec2::Zero();      // the measurement, when Matched (in the image, shift included)
};

struct FrameMeasurement {
  int visible = 0;  // points predicted inside the image
  int matched = 0;  // points used in the update
  // The matches' joint NIS before the update, nu^T S^-1 nu with the prior's S, and its dof
  // (2 * matched); both 0 without a match.
  double nis = 0;
  int nis_dof = 0;
  std::vector<FeatureSearch> features;  // every visible point, in feature-list order
};

// A feature's prediction from the state vector x (the camera's r and q at its head): a 3D point
// (measurement_model.h) or an inverse-depth feature (inverse_depth.h); false for a ray.
bool predictFeature(const CameraModel& camera, const Eigen::VectorXd& x, const MapFeature& feature,
                    PointMeasurement* h);
// The same seen from a camera at (r, q) rather than x's own (a rolling shutter's row: rolling_shutter.h).
bool predictFeature(const CameraModel& camera, const Vec3& r, const Vec4& q, const Eigen::VectorXd& x,
                    const MapFeature& feature, PointMeasurement* h);
// Where the feature is in the world: a point, an inverse-depth feature's x0 + m / rho (far when
// rho <= 0), a ray at its particles' mean depth.
Vec3 featurePoint(const Eigen::VectorXd& x, const MapFeature& feature);
// Its covariance, P_point, for a point or an inverse-depth feature (J P_y J^T, J = d p / d y of
// inverseDepthToPoint); not for a ray.
Mat3 featurePointCovariance(const EkfState& state, const MapFeature& feature);

// Measures the points and inverse-depth features (rays are skipped) and updates `state`; counts
// attempts, successes and misses in a row in `features`. Each feature's S is read from its own
// blocks of P (O(1)); the update is O(n^2 m). The matches are chosen by joint compatibility among
// each feature's candidates (O(m^2) per test), or with `ransac` by 1-point RANSAC over each one's
// best-correlating candidate (one_point_ransac.h; its draws from `rng`).
FrameMeasurement measureFeatures(EkfState& state, std::vector<MapFeature>& features, const CameraModel& camera,
                                 const cv::Mat& grey, const ActiveSearchOptions& options,
                                 const OnePointRansacOptions* ransac = nullptr, std::mt19937* rng = nullptr);

}  // namespace slamcmp
