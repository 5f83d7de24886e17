#pragma once
// The EKF update from the matched points of a frame, in one batch.
#include <vector>

#include "monoslam_ekf/ekf_state.h"
#include "monoslam_ekf/measurement_model.h"

namespace slamcmp {

struct PointObservation {
  int offset = 0;          // state offset of the point's 3 coordinates
  Vec2 z = Vec2::Zero();   // measured pixel (distorted)
  PointMeasurement h;      // prediction and Jacobians at the prior state
};

// The joint innovation covariance H P H^T + pixel_sigma^2 I of the stacked predictions
// (2m x 2m, observation i at rows 2i, 2i+1); H is non-zero only over r, q and each point.
Eigen::MatrixXd innovationCovariance(const EkfState& state, const std::vector<PointObservation>& observations,
                                     double pixel_sigma);

// K = P H^T S^-1, x += K (z - h), P -= K S K^T (symmetrised; the Joseph form would cost O(n^3)),
// then q renormalised with its Jacobian applied to P.
void batchUpdate(EkfState& state, const std::vector<PointObservation>& observations, double pixel_sigma);

}  // namespace slamcmp
