#include "ekf/pose_reporting.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include <Eigen/Eigenvalues>

namespace slamcmp {

std::string PoseReporting::weakness(int measured, bool anchored, const EkfState& state) {
  if (anchored) reset();
  if (!lost_.empty()) return lost_ + "; not anchored since";
  weak_frames_ = measured < options_.min_measured ? weak_frames_ + 1 : 0;
  if (weak_frames_ >= options_.max_weak_frames) {
    lost_ = "fewer than " + std::to_string(options_.min_measured) + " measurements a frame for " +
            std::to_string(weak_frames_) + " frames";
    return lost_;
  }
  const double position_sigma = std::sqrt(std::max(
      0.0, Eigen::SelfAdjointEigenSolver<Mat3>(state.P().topLeftCorner<3, 3>(), Eigen::EigenvaluesOnly).eigenvalues()(2)));
  if (position_sigma > options_.max_position_sigma) {
    std::ostringstream out;
    out << "camera position std " << std::fixed << std::setprecision(3) << position_sigma << " m";
    lost_ = out.str();
    return lost_;
  }
  return "";
}

}  // namespace slamcmp
