#include "eval/metrics/nees.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <stdexcept>

#include <Eigen/Cholesky>

#include "core/error.h"
#include "core/statistics.h"
#include "core/text_file.h"
#include "eval/metrics/associate.h"

namespace slamcmp {

std::optional<NeesResult> poseNees(const Trajectory& groundtruth, const std::vector<CovariantPose>& estimate,
                                   double max_diff, const Similarity3& fitted, bool gauge_at_first) {
  if (groundtruth.empty() || estimate.empty()) return std::nullopt;
  Trajectory poses;
  for (const CovariantPose& c : estimate) poses.push_back({c.timestamp, c.T_world_camera});
  const PosePairs pairs = associateByTime(groundtruth, poses, max_diff);
  if (pairs.size() == 0) return std::nullopt;
  Similarity3 T_gt_estimate = fitted;
  size_t first = pairs.size();  // the gauge's pose: on its truth by construction, not scored
  if (gauge_at_first) {
    first = 0;
    for (size_t k = 1; k < pairs.size(); ++k)
      if (estimate[pairs.estimate[k]].timestamp < estimate[pairs.estimate[first]].timestamp) first = k;
    const SE3& gt = groundtruth[pairs.groundtruth[first]].T_world_camera;
    const SE3& est = estimate[pairs.estimate[first]].T_world_camera;
    T_gt_estimate.R = gt.R() * est.R().transpose();
    T_gt_estimate.t = gt.t() - fitted.scale * (T_gt_estimate.R * est.t());
  }
  NeesResult r;
  double sum = 0, position_sum = 0, orientation_sum = 0;
  for (size_t k = 0; k < pairs.size(); ++k) {
    if (k == first) continue;
    const SE3& gt = groundtruth[pairs.groundtruth[k]].T_world_camera;
    const CovariantPose& est = estimate[pairs.estimate[k]];
    // p' = s R p + t, R' = R R_est: the world-frame rotation error turns with R.
    const SE3 T_gt_est(T_gt_estimate.R * est.T_world_camera.R(), T_gt_estimate * est.T_world_camera.t());
    Eigen::Matrix<double, 6, 6> G = Eigen::Matrix<double, 6, 6>::Zero();
    G.topLeftCorner<3, 3>() = T_gt_estimate.scale * T_gt_estimate.R;
    G.bottomRightCorner<3, 3>() = T_gt_estimate.R;
    Eigen::Matrix<double, 6, 1> e;
    e << gt.t() - T_gt_est.t(), rotvecFromRotation(gt.R() * T_gt_est.R().transpose());
    const PoseCovariance P = G * est.covariance * G.transpose();
    const Eigen::LLT<PoseCovariance> llt(P);
    if (llt.info() != Eigen::Success) continue;
    const double nees = e.dot(llt.solve(e));
    // Each part over its own block: the marginal of the other part's error (ov_eval's NEES pos / ori).
    const Vec3 e_p = e.head<3>(), e_r = e.tail<3>();
    const NeesParts parts{e_p.dot(P.topLeftCorner<3, 3>().llt().solve(e_p)),
                          e_r.dot(P.bottomRightCorner<3, 3>().llt().solve(e_r))};
    r.per_frame.push_back({est.timestamp, nees});
    r.per_frame_parts.push_back(parts);
    sum += nees;
    position_sum += parts.position;
    orientation_sum += parts.orientation;
  }
  const int n = r.frames();
  if (n == 0) return std::nullopt;
  const auto bounded = [n](double sum_of_nees, int dof) {
    return NeesMean{sum_of_nees / n, dof, chiSquaredQuantile(1.0 * dof * n, 0.025) / n,
                    chiSquaredQuantile(1.0 * dof * n, 0.975) / n};
  };
  static_cast<NeesMean&>(r) = bounded(sum, 6);
  r.position = bounded(position_sum, 3);
  r.orientation = bounded(orientation_sum, 3);
  return r;
}

nlohmann::json neesToJson(const NeesResult& nees) {
  const auto bounded = [](const NeesMean& m) {
    return nlohmann::json{{"mean", m.mean}, {"dof", m.dof}, {"lower", m.lower}, {"upper", m.upper}};
  };
  nlohmann::json j = bounded(nees);
  j["frames"] = nees.frames();
  j["position"] = bounded(nees.position);
  j["orientation"] = bounded(nees.orientation);
  return j;
}

void writeNeesCsv(const std::string& path, const NeesResult& nees) {
  if (nees.per_frame_parts.size() != nees.per_frame.size()) throw std::logic_error("nees.csv: a part per pose");
  std::ofstream out(path);
  if (!out) throw InputError(path, "cannot be written");
  out << "timestamp,nees,position,orientation\n" << std::setprecision(17);
  for (size_t k = 0; k < nees.per_frame.size(); ++k)
    out << nees.per_frame[k].timestamp << "," << nees.per_frame[k].nees << "," << nees.per_frame_parts[k].position
        << "," << nees.per_frame_parts[k].orientation << "\n";
  if (!out) throw InputError(path, "cannot be written");
}

std::vector<TimedNees> readNeesCsv(const std::string& path) {
  std::ifstream in = openTextFile(path);  // a folder would have the wrong header
  std::string line;
  if (std::getline(in, line) && !line.empty() && line.back() == '\r') line.pop_back();
  const char* const kEarlier = "timestamp,nees";  // before the parts were written
  const char* const kHeader = "timestamp,nees,position,orientation";
  if (line != kEarlier && line != kHeader)
    throw InputError(atLine(path, 1), std::string("header is not ") + kHeader + " (or an earlier " + kEarlier + ")");
  const std::vector<const char*> fields = line == kHeader ? std::vector<const char*>{"timestamp", "nees", "position", "orientation"}
                                                          : std::vector<const char*>{"timestamp", "nees"};
  std::vector<TimedNees> rows;
  for (int n = 2; std::getline(in, line); ++n) {
    if (!line.empty() && line.back() == '\r') line.pop_back();  // written on Windows
    if (line.empty()) continue;
    const std::string where = atLine(path, n);
    std::vector<double> values;
    size_t begin = 0;
    for (const char* field : fields) {
      const size_t comma = line.find(',', begin);
      const bool last = values.size() + 1 == fields.size();
      if (last != (comma == std::string::npos)) throw InputError(where, std::string("expected ") + (fields.size() == 2 ? kEarlier : kHeader));
      const std::string text = line.substr(begin, last ? std::string::npos : comma - begin);
      size_t used = 0;
      double v = NAN;
      try {
        v = std::stod(text, &used);
      } catch (const std::exception&) {
      }
      if (used != text.size() || !std::isfinite(v)) throw InputError(where, std::string(field) + " is not a finite number");
      if (values.size() > 0 && v < 0) throw InputError(where, std::string(field) + " is negative");
      values.push_back(v);
      begin = comma + 1;
    }
    rows.push_back({values[0], values[1]});
  }
  return rows;
}

}  // namespace slamcmp
