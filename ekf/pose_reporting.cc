#include "ekf/pose_reporting.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <vector>

#include <Eigen/Eigenvalues>

#include "core/statistics.h"

namespace slamcmp {

std::string PoseReporting::innovationJump(double nis, int nis_dof, bool test) {
  if (nis_dof <= 0 || !std::isfinite(nis)) return "";
  const double level = nis / nis_dof;
  std::string why;
  if (test && options_.max_innovation_jump > 0 &&
      nis_per_dof_.size() >= static_cast<size_t>(ReportingOptions::kMinInnovationHistory)) {
    const double run_level = median(std::vector<double>(nis_per_dof_.begin(), nis_per_dof_.end()));
    if (level > options_.max_innovation_jump * run_level) {
      std::ostringstream out;
      out << "matches " << std::fixed << std::setprecision(0) << level / run_level
          << " times the run's innovation level (NIS per dof " << std::setprecision(3) << level << " against "
          << run_level << "): a mismatch moved the filter";
      why = out.str();
    }
  }
  nis_per_dof_.push_back(level);
  if (nis_per_dof_.size() > static_cast<size_t>(options_.innovation_window)) nis_per_dof_.pop_front();
  return why;
}

std::string PoseReporting::weakness(int measured, double nis, int nis_dof, bool anchored, const EkfState& state) {
  if (anchored) lost_.clear();
  if (!lost_.empty()) return lost_ + "; not anchored since";
  // A frame something absolute anchored is not a weak one, whatever else it measured.
  weak_frames_ = !anchored && measured < options_.min_measured ? weak_frames_ + 1 : 0;
  if (weak_frames_ >= options_.max_weak_frames) {
    lost_ = "fewer than " + std::to_string(options_.min_measured) + " measurements a frame for " +
            std::to_string(weak_frames_) + " frames";
    return lost_;
  }
  const double position_sigma = largestStd(state.P().topLeftCorner<3, 3>());
  if (position_sigma > options_.max_position_sigma) {
    std::ostringstream out;
    out << "camera position std " << std::fixed << std::setprecision(3) << position_sigma << " m";
    lost_ = out.str();
    return lost_;
  }
  // Nothing measured (a blank frame, a frame from elsewhere): the pose would be the motion model's
  // alone. Lost this frame; unlike the rules above not until an anchor, as nothing moved the filter.
  if (!anchored && measured == 0) return "nothing measured in this frame: the pose would be the motion model's";
  // A frame the board anchors is posed from it whatever one room feature did; its level still counts.
  lost_ = innovationJump(nis, nis_dof, !anchored);
  return lost_;
}

}  // namespace slamcmp
