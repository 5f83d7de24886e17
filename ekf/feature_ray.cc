#include "ekf/feature_ray.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include "ekf/measurement_model.h"
#include "ekf/patch_search.h"

namespace slamcmp {

int appendRay(EkfState& state, const CameraModel& camera, const Vec2& uv_distorted, double pixel_sigma) {
  Mat34 J_q;
  Eigen::Matrix<double, 3, 2> J_uv;
  const Vec3 h = rayFromPixel(camera, state.q(), uv_distorted, &J_q, &J_uv);
  // d(r0, h) / d(camera state): r0 = r, h depends on q.
  Eigen::Matrix<double, 6, EkfState::kCameraDim> J_x = Eigen::Matrix<double, 6, EkfState::kCameraDim>::Zero();
  J_x.block<3, 3>(0, EkfState::kR) = Mat3::Identity();
  J_x.block<3, 4>(3, EkfState::kQ) = J_q;
  const Eigen::MatrixXd& P = state.P();
  const Eigen::MatrixXd P_ray_rest = J_x * P.topRows<EkfState::kCameraDim>();
  Eigen::Matrix<double, 6, 6> P_ray = P_ray_rest.leftCols<EkfState::kCameraDim>() * J_x.transpose();
  P_ray.bottomRightCorner<3, 3>() += J_uv * J_uv.transpose() * pixel_sigma * pixel_sigma;
  Eigen::Matrix<double, 6, 1> value;
  value << state.r(), h;
  return state.append(value, P_ray, P_ray_rest);
}

int promoteRay(EkfState& state, int ray_offset, double depth_mean, double depth_var) {
  const Vec3 r0 = state.x().segment<3>(ray_offset);
  const Vec3 h = state.x().segment<3>(ray_offset + 3);
  Eigen::Matrix<double, 3, 6> J;
  J << Mat3::Identity(), depth_mean * Mat3::Identity();
  const Eigen::MatrixXd P_rest = J * state.P().middleRows<6>(ray_offset);  // 3 x n
  const Eigen::Matrix<double, 6, 6> P_ray = state.P().block<6, 6>(ray_offset, ray_offset);
  const Mat3 P_point = J * P_ray * J.transpose() + depth_var * h * h.transpose();
  const int point_offset = state.append(r0 + depth_mean * h, P_point, P_rest);
  state.remove(ray_offset, 6);
  return point_offset - 6;  // the ray was before it
}

double DepthParticles::mean() const {
  double m = 0;
  for (int i = 0; i < size(); ++i) m += weight[i] * depth[i];
  return m;
}

double DepthParticles::stddev() const {
  const double m = mean();
  double var = 0;
  for (int i = 0; i < size(); ++i) var += weight[i] * (depth[i] - m) * (depth[i] - m);
  return std::sqrt(var);
}

DepthParticles uniformParticles(int n, double min_depth, double max_depth) {
  DepthParticles p;
  for (int i = 0; i < n; ++i) {
    p.depth.push_back(min_depth + (max_depth - min_depth) * i / (n - 1));
    p.weight.push_back(1.0 / n);
  }
  return p;
}

bool updateDepthParticles(const EkfState& state, int ray_offset, const CameraModel& camera,
                          const cv::Mat& grey, const cv::Mat& templ, const ActiveSearchOptions& search,
                          double prune_threshold, DepthParticles* particles) {
  const Vec3 r0 = state.x().segment<3>(ray_offset);
  const Vec3 h = state.x().segment<3>(ray_offset + 3);
  const Eigen::MatrixXd& P = state.P();
  // Covariance over (r, q, r0, h): the blocks the particles' predictions depend on.
  Eigen::Matrix<double, 13, 13> P_sub;
  const int idx[13] = {0, 1, 2, 3, 4, 5, 6, ray_offset, ray_offset + 1, ray_offset + 2,
                       ray_offset + 3, ray_offset + 4, ray_offset + 5};
  for (int i = 0; i < 13; ++i)
    for (int j = 0; j < 13; ++j) P_sub(i, j) = P(idx[i], idx[j]);

  std::vector<SearchEllipse> ellipses(particles->size());
  std::vector<bool> visible(particles->size(), false);
  std::vector<SearchEllipse> searched;
  for (int i = 0; i < particles->size(); ++i) {
    const double d = particles->depth[i];
    PointMeasurement m;
    if (!predictMeasurement(camera, state.r(), state.q(), r0 + d * h, &m)) continue;
    Eigen::Matrix<double, 2, 13> H;
    H << m.H_r, m.H_q, m.H_y, d * m.H_y;  // y = r0 + d h
    ellipses[i].centre = m.uv_distorted;
    ellipses[i].S = H * P_sub * H.transpose() + Mat2::Identity() * search.pixel_sigma * search.pixel_sigma;
    if (!camera.inImage(m.uv_distorted)) continue;
    visible[i] = true;
    searched.push_back(ellipses[i]);
  }
  if (searched.empty()) return false;
  const cv::Rect box = ellipsesBoundingBox(searched, search.sigma_gate);
  // Early on the particles can spread over much of the image: wait for a smaller spread.
  if (static_cast<double>(box.width) * box.height > 0.25 * grey.cols * grey.rows) return false;
  const std::vector<PatchMatch> matches = searchEllipses(grey, templ, searched, search.sigma_gate, search.min_ncc);
  if (matches.empty()) return false;
  const PatchMatch& match = matches.front();

  std::vector<double> weight(particles->size(), 0.0);
  double best = 0, total = 0;
  for (int i = 0; i < particles->size(); ++i) {
    if (!visible[i]) continue;
    const Mat2& S = ellipses[i].S;
    const Vec2 nu = match.uv - ellipses[i].centre;
    const double likelihood =
        std::exp(-0.5 * nu.dot(S.inverse() * nu)) / (2 * M_PI * std::sqrt(S.determinant()));
    weight[i] = particles->weight[i] * likelihood;
    total += weight[i];
    best = std::max(best, weight[i]);
  }
  if (!(total > 0)) return false;  // the match fits no particle: keep the old weights
  DepthParticles kept;
  for (int i = 0; i < particles->size(); ++i) {
    if (weight[i] < prune_threshold * best) continue;
    kept.depth.push_back(particles->depth[i]);
    kept.weight.push_back(weight[i]);
  }
  double kept_total = 0;
  for (double w : kept.weight) kept_total += w;
  for (double& w : kept.weight) w /= kept_total;
  *particles = std::move(kept);
  return true;
}

}  // namespace slamcmp

