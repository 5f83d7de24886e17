#include "geometry/bundle_adjustment.h"

#include <cassert>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include "core/error.h"

namespace slamcmp {

void BundleAdjustmentOptions::check() const {
  if (max_iterations < 0) throw OptionError("max_iterations", "must be >= 0");
  if (huber_sigmas < 0) throw OptionError("huber_sigmas", "must be >= 0");
  if (!(min_relative_decrease >= 0)) throw OptionError("min_relative_decrease", "must be >= 0");
}

namespace {

using Mat63 = Eigen::Matrix<double, 6, 3>;
using Mat26 = Eigen::Matrix<double, 2, 6>;

constexpr double kMinDepth = 1e-6;
// An observation behind its camera costs as a residual of this many sigmas: a step that moves a
// point behind a camera is rejected (Levenberg-Marquardt only accepts lower costs).
constexpr double kBehindSigmas = 100;
// A point on a ray is kept nearer than 1 / this (metres for a unit direction).
constexpr double kMinInverseDepth = 1e-4;

// Huber's rho of a squared whitened residual, and its IRLS weight.
double huberCost(double e2, double k) {
  if (k <= 0 || e2 <= k * k) return e2;
  return 2 * k * std::sqrt(e2) - k * k;
}
double huberWeight(double e2, double k) {
  if (k <= 0 || e2 <= k * k) return 1.0;
  return k / std::sqrt(e2);
}

}  // namespace

int BundleAdjustment::addCamera(const SE3& T_camera_world, bool fixed) {
  cameras_.push_back({T_camera_world, fixed});
  return numCameras() - 1;
}

int BundleAdjustment::addPoint(const Vec3& p_world, bool fixed) {
  points_.push_back({p_world, fixed, {}});
  return numPoints() - 1;
}

int BundleAdjustment::addPointOnRay(const Vec3& origin, const Vec3& direction, double inverse_depth) {
  assert(inverse_depth > 0);
  Point p{origin + direction / inverse_depth, false, {}};
  p.on_ray = true;
  p.ray_origin = origin;
  p.ray_direction = direction;
  p.inverse_depth = inverse_depth;
  points_.push_back(p);
  return numPoints() - 1;
}

void BundleAdjustment::addObservation(int camera, int point, const Vec2& xy_normalised, double sigma_px) {
  assert(camera >= 0 && camera < numCameras() && point >= 0 && point < numPoints() && sigma_px > 0);
  points_[point].observations.push_back(static_cast<int>(observations_.size()));
  observations_.push_back({camera, point, xy_normalised, 1.0 / (sigma_px * sigma_px)});
}

void BundleAdjustment::addPointPrior(int point, const Vec3& p_world, double sigma_m) {
  assert(point >= 0 && point < numPoints() && sigma_m > 0);
  points_[point].prior = p_world;
  points_[point].prior_weight = 1.0 / (sigma_m * sigma_m);
}

double BundleAdjustment::errorPx(int k, double focal_px) const {
  const Observation& o = observations_[k];
  const Vec3 p = cameras_[o.camera].T_camera_world * points_[o.point].p_world;
  if (p.z() <= kMinDepth) return std::numeric_limits<double>::infinity();
  return focal_px * (p.head<2>() / p.z() - o.xy).norm();
}

double BundleAdjustment::cost(const std::vector<SE3>& cameras, const std::vector<Vec3>& points, double huber) const {
  double total = 0;
  for (const Observation& o : observations_) {
    const Vec3 p = cameras[o.camera] * points[o.point];
    if (p.z() <= kMinDepth) {
      total += huberCost(kBehindSigmas * kBehindSigmas, huber);
      continue;
    }
    total += huberCost(o.weight * (p.head<2>() / p.z() - o.xy).squaredNorm(), huber);
  }
  for (size_t j = 0; j < points_.size(); ++j)
    if (points_[j].prior_weight > 0) total += points_[j].prior_weight * (points[j] - points_[j].prior).squaredNorm();
  return total;
}

void BundleAdjustment::normalEquations(const Estimate& x, double huber, NormalEquations* eq) const {
  for (auto& u : eq->U) u.setZero();
  for (auto& g : eq->gc) g.setZero();
  for (auto& v : eq->V) v.setZero();
  for (auto& g : eq->gp) g.setZero();
  eq->observations = 0;
  for (size_t m = 0; m < observations_.size(); ++m) {
    const Observation& o = observations_[m];
    const Camera& cam = cameras_[o.camera];
    const bool point_free = !points_[o.point].fixed;
    eq->used[m] = 0;
    if (cam.fixed && !point_free) continue;
    const Vec3 p = x.T[o.camera] * x.P[o.point];
    if (p.z() <= kMinDepth) continue;
    eq->used[m] = 1;
    ++eq->observations;
    const double iz = 1.0 / p.z();
    const Vec2 r = p.head<2>() * iz - o.xy;
    const double w = o.weight * huberWeight(o.weight * r.squaredNorm(), huber);
    const Mat26 Jc = projectionPoseJacobian(p);
    const Mat23 Jp = pinholeJacobian(p) * x.T[o.camera].R();
    if (cam.block >= 0) {
      eq->U[cam.block] += w * Jc.transpose() * Jc;
      eq->gc[cam.block] += w * Jc.transpose() * r;
    }
    if (point_free) {
      eq->V[o.point] += w * Jp.transpose() * Jp;
      eq->gp[o.point] += w * Jp.transpose() * r;
    }
    if (cam.block >= 0 && point_free) eq->W[m] = w * Jc.transpose() * Jp;
  }
  for (size_t j = 0; j < points_.size(); ++j) {
    if (points_[j].fixed || points_[j].prior_weight <= 0) continue;
    eq->V[j].diagonal().array() += points_[j].prior_weight;
    eq->gp[j] += points_[j].prior_weight * (x.P[j] - points_[j].prior);
  }
}

bool BundleAdjustment::dampedStep(const NormalEquations& eq, const Estimate& x, double lambda, int n_free,
                                  Estimate* next) const {
  // Marquardt damping of the diagonals; the points are eliminated (Schur complement).
  const int nc = 6 * n_free;
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(nc, nc);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(nc);
  for (int i = 0; i < n_free; ++i) {
    Mat6 Ui = eq.U[i];
    Ui.diagonal() += lambda * eq.U[i].diagonal().cwiseMax(1e-9);
    S.block<6, 6>(6 * i, 6 * i) = Ui;
    b.segment<6>(6 * i) = -eq.gc[i];
  }
  std::vector<Mat3> V_inv(points_.size());
  for (size_t j = 0; j < points_.size(); ++j) {
    if (points_[j].fixed) continue;
    if (points_[j].on_ray) {
      // One parameter: dp/d(inverse depth) = -direction / rho^2; V_inv eliminates it alone.
      const Vec3 B = -points_[j].ray_direction / (x.rho[j] * x.rho[j]);
      const double v = B.dot(eq.V[j] * B);
      const double damped = v + lambda * std::max(v, 1e-9) + 1e-12;
      V_inv[j] = B * B.transpose() / damped;
    } else {
      Mat3 Vj = eq.V[j];
      Vj.diagonal() += lambda * eq.V[j].diagonal().cwiseMax(1e-9);
      Vj.diagonal().array() += 1e-12;
      V_inv[j] = Vj.inverse();
    }
    if (!V_inv[j].allFinite()) V_inv[j].setZero();
    const std::vector<int>& obs = points_[j].observations;
    for (size_t a = 0; a < obs.size(); ++a) {
      if (!eq.used[obs[a]]) continue;
      const int ca = cameras_[observations_[obs[a]].camera].block;
      if (ca < 0) continue;
      const Mat63 WaVinv = eq.W[obs[a]] * V_inv[j];
      b.segment<6>(6 * ca) += WaVinv * eq.gp[j];
      for (size_t c = 0; c < obs.size(); ++c) {
        if (!eq.used[obs[c]]) continue;
        const int cc = cameras_[observations_[obs[c]].camera].block;
        if (cc < 0) continue;
        S.block<6, 6>(6 * ca, 6 * cc) -= WaVinv * eq.W[obs[c]].transpose();
      }
    }
  }
  Eigen::VectorXd dc = Eigen::VectorXd::Zero(nc);
  if (nc > 0) {
    Eigen::LDLT<Eigen::MatrixXd> ldlt(S);
    dc = ldlt.solve(b);
  }
  if (!dc.allFinite()) return false;
  // Back-substitution: the cameras' step, then each point's.
  *next = x;
  for (size_t i = 0; i < cameras_.size(); ++i)
    if (cameras_[i].block >= 0) next->T[i] = applyPoseDelta(x.T[i], dc.segment<6>(6 * cameras_[i].block));
  for (size_t j = 0; j < points_.size(); ++j) {
    if (points_[j].fixed) continue;
    Vec3 rhs = -eq.gp[j];
    for (int m : points_[j].observations) {
      const int cm = cameras_[observations_[m].camera].block;
      if (eq.used[m] && cm >= 0) rhs -= eq.W[m].transpose() * dc.segment<6>(6 * cm);
    }
    if (points_[j].on_ray) {
      // The step along B = dp/d(rho), taken in inverse depth.
      const Vec3 B = -points_[j].ray_direction / (x.rho[j] * x.rho[j]);
      const Vec3 step = V_inv[j] * rhs;
      next->rho[j] = std::max(x.rho[j] + B.dot(step) / B.squaredNorm(), kMinInverseDepth);
      next->P[j] = points_[j].ray_origin + points_[j].ray_direction / next->rho[j];
    } else {
      next->P[j] = x.P[j] + V_inv[j] * rhs;
    }
  }
  return true;
}

BundleAdjustmentSummary BundleAdjustment::solve(const BundleAdjustmentOptions& options, double focal_px) {
  BundleAdjustmentSummary summary;
  // Weights in normalised coordinates: residual (xy - xy_obs) * focal / sigma is in sigmas.
  const double f2 = focal_px * focal_px;
  for (Observation& o : observations_) o.weight *= f2;
  int n_free = 0;
  for (Camera& c : cameras_) c.block = c.fixed ? -1 : n_free++;
  const double k = options.huber_sigmas;

  Estimate x{std::vector<SE3>(cameras_.size()), std::vector<Vec3>(points_.size()),
             std::vector<double>(points_.size(), 0)};
  for (size_t i = 0; i < cameras_.size(); ++i) x.T[i] = cameras_[i].T_camera_world;
  for (size_t j = 0; j < points_.size(); ++j) x.P[j] = points_[j].p_world, x.rho[j] = points_[j].inverse_depth;
  double current = cost(x.T, x.P, k);
  summary.initial_cost = summary.final_cost = current;

  NormalEquations eq;
  eq.U.resize(n_free);
  eq.gc.resize(n_free);
  eq.V.resize(points_.size());
  eq.gp.resize(points_.size());
  eq.W.resize(observations_.size());
  eq.used.resize(observations_.size());
  Estimate next;
  double lambda = 1e-4;
  for (int it = 0; it < options.max_iterations; ++it) {
    normalEquations(x, k, &eq);
    summary.observations = eq.observations;
    summary.iterations = it + 1;
    bool accepted = false;
    for (int attempt = 0; attempt < 10 && !accepted; ++attempt) {
      if (!dampedStep(eq, x, lambda, n_free, &next)) {
        lambda *= 10;
        continue;
      }
      const double candidate = cost(next.T, next.P, k);
      if (std::isfinite(candidate) && candidate < current) {
        const double decrease = current - candidate;
        std::swap(x, next);
        current = candidate;
        lambda = std::max(lambda * 0.1, 1e-10);
        accepted = true;
        if (decrease < options.min_relative_decrease * current) it = options.max_iterations;  // converged
      } else {
        lambda *= 10;
      }
    }
    if (!accepted) break;
  }
  for (Observation& o : observations_) o.weight /= f2;
  for (size_t i = 0; i < cameras_.size(); ++i) cameras_[i].T_camera_world = x.T[i];
  for (size_t j = 0; j < points_.size(); ++j) points_[j].p_world = x.P[j], points_[j].inverse_depth = x.rho[j];
  summary.final_cost = current;
  return summary;
}

}  // namespace slamcmp
