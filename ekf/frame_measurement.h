#pragma once
// One frame's measurement of the map (SPEC section 5, Davison et al. 2007 section 3.5): predict
// every point and its innovation covariance, search the ellipses of the most uncertain ones with
// their warped templates, choose jointly compatible matches and update the EKF in one batch.
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "ekf/ekf_state.h"
#include "ekf/map_feature.h"
#include "ekf/ekf_options.h"

namespace slamcmp {

enum class SearchOutcome {
  Unmeasured,  // predicted in the image, not selected (or its ellipse was too large)
  Matched,     // searched, and its match was used in the update
  Failed,      // searched (or selected but its template was unusable), no match kept
};

struct FeatureSearch {
  size_t index = 0;                    // into the feature list
  Vec2 uv_predicted = Vec2::Zero();    // prior prediction, distorted pixels
  Mat2 S = Mat2::Identity();           // its innovation covariance, pixels^2
  SearchOutcome outcome = SearchOutcome::Unmeasured;
  Vec2 uv_matched = Vec2::Zero();      // the measurement, when Matched
};

struct FrameMeasurement {
  int visible = 0;  // points predicted inside the image
  int matched = 0;  // points used in the update
  std::vector<FeatureSearch> features;  // every visible point, in feature-list order
};

// Measures the points (rays are skipped) and updates `state`; counts attempts and successes in
// `features`. Each point's S is read from its own blocks of P (O(1)); the joint S of the searched
// ones is O(m^2); the update is O(n^2 m).
FrameMeasurement measureFeatures(EkfState& state, std::vector<MapFeature>& features, const CameraModel& camera,
                                 const cv::Mat& grey, const ActiveSearchOptions& options);

}  // namespace slamcmp
