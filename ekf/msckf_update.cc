#include "ekf/msckf_update.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/QR>

#include "core/statistics.h"
#include "ekf/data_snooping.h"
#include "ekf/ekf_update.h"
#include "ekf/measurement_model.h"

namespace slamcmp {

int cloneCameraPose(EkfState& state) {
  const Eigen::MatrixXd P_pose_rest = state.P().topRows(kCloneDim);
  return state.appendToTail(state.x().head(kCloneDim), P_pose_rest.leftCols(kCloneDim), P_pose_rest);
}

namespace {

Vec3 clonePosition(const EkfState& state, int offset) { return state.x().segment<3>(offset); }
Vec4 cloneQuat(const EkfState& state, int offset) { return state.x().segment<4>(offset + 3); }

}  // namespace

std::optional<Vec3> triangulateTrack(const EkfState& state, const CameraModel& camera,
                                     const std::vector<CloneObservation>& track, const MsckfOptions& options) {
  if (track.size() < 2) return std::nullopt;
  const auto ray = [&](const CloneObservation& o) {
    return rotateByQuat(cloneQuat(state, o.clone_offset), camera.undistortPixel(o.uv).homogeneous().normalized());
  };
  const Vec3 d1 = ray(track.front()), d2 = ray(track.back());
  if (std::acos(std::clamp(d1.dot(d2), -1.0, 1.0)) < options.min_parallax_deg * M_PI / 180) return std::nullopt;
  // Midpoint of the closest points of the two rays r1 + s d1 and r2 + t d2.
  const Vec3 r1 = clonePosition(state, track.front().clone_offset), r2 = clonePosition(state, track.back().clone_offset);
  Mat2 A;
  A << d1.dot(d1), -d1.dot(d2), d1.dot(d2), -d2.dot(d2);
  const Vec2 st = A.fullPivLu().solve(Vec2((r2 - r1).dot(d1), (r2 - r1).dot(d2)));
  Vec3 p = 0.5 * (r1 + st.x() * d1 + r2 + st.y() * d2);
  // Gauss-Newton on the pixel residuals of every clone.
  PointMeasurement m;
  for (int iteration = 0; iteration < 5; ++iteration) {
    Mat3 H = Mat3::Zero();
    Vec3 g = Vec3::Zero();
    for (const CloneObservation& o : track) {
      if (!predictMeasurement(camera, clonePosition(state, o.clone_offset), cloneQuat(state, o.clone_offset), p, &m))
        return std::nullopt;
      const Mat23 J = m.H_y;
      H += J.transpose() * J;
      g += J.transpose() * (o.uv - m.uv_distorted);
    }
    const Vec3 step = H.ldlt().solve(g);
    if (!step.allFinite()) return std::nullopt;
    p += step;
    if (step.norm() < 1e-9 * p.norm()) break;
  }
  for (const CloneObservation& o : track) {
    if (!predictMeasurement(camera, clonePosition(state, o.clone_offset), cloneQuat(state, o.clone_offset), p, &m) ||
        (o.uv - m.uv_distorted).norm() > options.max_triangulation_px)
      return std::nullopt;
  }
  return p;
}

MsckfResult msckfUpdate(EkfState& state, const CameraModel& camera,
                        const std::vector<std::vector<CloneObservation>>& tracks, const MsckfOptions& options) {
  MsckfResult result;
  // The clones the tracks saw, each a block of the measurement's columns.
  std::map<int, int> block_of;  // clone offset -> block index
  for (const auto& track : tracks)
    for (const CloneObservation& o : track) block_of.emplace(o.clone_offset, 0);
  std::vector<int> columns;  // state index of each measurement column
  for (auto& [offset, block] : block_of) {
    block = static_cast<int>(columns.size()) / kCloneDim;
    for (int k = 0; k < kCloneDim; ++k) columns.push_back(offset + k);
  }
  const int c = static_cast<int>(columns.size());
  const Eigen::MatrixXd P_cc = state.P()(columns, columns);

  const double sigma2 = options.pixel_sigma * options.pixel_sigma;
  std::vector<Eigen::MatrixXd> accepted;  // whitened [H | r] rows of each track that passed
  for (const auto& track : tracks) {
    const std::optional<Vec3> p_world = triangulateTrack(state, camera, track, options);
    if (!p_world) {
      ++result.untriangulated;
      continue;
    }
    const int m = static_cast<int>(track.size());
    Eigen::MatrixXd Hr = Eigen::MatrixXd::Zero(2 * m, c + 1);  // [H_clones | residual]
    Eigen::Matrix<double, Eigen::Dynamic, 3> H_point(2 * m, 3);
    PointMeasurement h;
    for (int j = 0; j < m; ++j) {
      const CloneObservation& o = track[j];
      predictMeasurement(camera, clonePosition(state, o.clone_offset), cloneQuat(state, o.clone_offset), *p_world, &h);
      const int col = kCloneDim * block_of.at(o.clone_offset);
      Hr.block<2, 3>(2 * j, col) = h.H_r;
      Hr.block<2, 4>(2 * j, col + 3) = h.H_q;
      Hr.block<2, 1>(2 * j, c) = o.uv - h.uv_distorted;
      H_point.middleRows<2>(2 * j) = h.H_y;
    }
    // Left null space of H_point: the last 2m - 3 rows of Q^T.
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(H_point);
    const Eigen::MatrixXd projected = (qr.householderQ().adjoint() * Hr).bottomRows(2 * m - 3);
    const Eigen::MatrixXd H = projected.leftCols(c);
    const Eigen::VectorXd r = projected.col(c);
    Eigen::MatrixXd S = H * P_cc * H.transpose();
    S.diagonal().array() += sigma2;
    if (r.dot(S.ldlt().solve(r)) > chiSquaredQuantile(2 * m - 3, options.gate_probability)) {
      ++result.rejected;
      continue;
    }
    accepted.push_back(projected / options.pixel_sigma);
  }
  if (options.snooping_probability > 0) result.snooped = snoopBlocks(P_cc, options.snooping_probability, &accepted);
  result.used = static_cast<int>(accepted.size());
  if (accepted.empty()) return result;
  Eigen::MatrixXd stacked = stackRows(accepted);
  // More rows than columns: the QR factor's first c rows carry the same information.
  if (stacked.rows() > c) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(stacked);
    stacked = qr.matrixQR().topRows(c).triangularView<Eigen::Upper>();
  }
  const Eigen::MatrixXd H = stacked.leftCols(c);
  Eigen::MatrixXd PH = state.P()(Eigen::all, columns) * H.transpose();  // P H^T over the state
  Eigen::MatrixXd S = H * P_cc * H.transpose();
  S.diagonal().array() += 1.0;  // whitened
  result.applied = kalmanUpdate(state, std::move(PH), S, stacked.col(c));
  if (result.applied)
    for (const auto& [offset, block] : block_of) state.renormaliseQuaternion(offset + 3);
  return result;
}

}  // namespace slamcmp
