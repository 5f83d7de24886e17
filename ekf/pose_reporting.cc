#include "ekf/pose_reporting.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <vector>

#include <Eigen/Eigenvalues>

namespace slamcmp {

namespace {

// Frames with matches before the run's innovation level is a yardstick.
constexpr size_t kMinInnovationHistory = 10;

}  // namespace

std::string PoseReporting::innovationJump(double nis, int nis_dof) {
  if (nis_dof <= 0 || !std::isfinite(nis)) return "";
  const double level = nis / nis_dof;
  std::string why;
  if (options_.max_innovation_jump > 0 && nis_per_dof_.size() >= kMinInnovationHistory) {
    std::vector<double> history(nis_per_dof_.begin(), nis_per_dof_.end());
    std::nth_element(history.begin(), history.begin() + history.size() / 2, history.end());
    const double median = history[history.size() / 2];
    if (level > options_.max_innovation_jump * median) {
      std::ostringstream out;
      out << "matches " << std::fixed << std::setprecision(0) << level / median
          << " times the run's innovation level (NIS per dof " << std::setprecision(3) << level << " against "
          << median << "): a mismatch moved the filter";
      why = out.str();
    }
  }
  nis_per_dof_.push_back(level);
  if (nis_per_dof_.size() > static_cast<size_t>(options_.innovation_window)) nis_per_dof_.pop_front();
  return why;
}

std::string PoseReporting::weakness(int measured, double nis, int nis_dof, bool anchored, const EkfState& state) {
  if (anchored) {
    weak_frames_ = 0;
    lost_.clear();
  }
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
  lost_ = innovationJump(nis, nis_dof);
  return lost_;
}

}  // namespace slamcmp
