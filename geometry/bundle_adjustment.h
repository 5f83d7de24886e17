#pragma once
// Bundle adjustment: camera poses and 3D points refined together on their reprojection errors
// (Triggs et al. 2000), Levenberg-Marquardt on the normal equations with the points eliminated by
// the Schur complement (the reduced camera system is dense and small: a sliding window of
// keyframes), Huber-weighted residuals. Cameras and points may be held fixed: fixed points are
// known world positions (board corners), fixed cameras hold the gauge (position, orientation and,
// for a monocular map without known points, scale).
#include <vector>

#include "core/geometry.h"
#include "geometry/pose_refinement.h"

namespace slamcmp {

struct BundleAdjustmentOptions {
  int max_iterations = 8;
  double huber_sigmas = 2.0;         // Huber threshold on a residual, in its observation's standard deviations
  double min_relative_decrease = 1e-5;  // stop when an accepted step lowers the cost by less than this fraction
  template <class V>
  void visit(V& v) {
    v("max_iterations", max_iterations, "Levenberg-Marquardt iterations at most");
    v("huber_sigmas", huber_sigmas,
      "Huber threshold on a reprojection error, in standard deviations of its observation; 0 = plain least squares");
    v("min_relative_decrease", min_relative_decrease,
      "stop when an accepted step lowers the cost by less than this fraction of it");
  }
  void check() const;
};

struct BundleAdjustmentSummary {
  double initial_cost = 0;  // robust cost, squared sigmas
  double final_cost = 0;
  int iterations = 0;
  int observations = 0;     // used (in front of their camera)
};

class BundleAdjustment {
 public:
  // Poses as T_camera_world (geometry's convention). Returns the index to refer to it.
  int addCamera(const SE3& T_camera_world, bool fixed);
  int addPoint(const Vec3& p_world, bool fixed);
  // A free point held to the ray origin + direction / inverse_depth (e.g. through its first
  // observation) and refined in inverse depth: for a point seen with too little parallax to
  // place, whose depth is nearly free while its direction holds the cameras' rotations (inverse
  // depth stays well-behaved as the depth goes to infinity). inverse_depth > 0, 1 / metres for a
  // unit direction.
  int addPointOnRay(const Vec3& origin, const Vec3& direction, double inverse_depth);
  // Point `point` seen from camera `camera` at undistorted normalised coordinates, with a
  // standard deviation of sigma_px pixels.
  void addObservation(int camera, int point, const Vec2& xy_normalised, double sigma_px);
  // A prior on a free point's position: p_world with sigma_m metres per axis (what earlier data,
  // no longer in the problem, said about it).
  void addPointPrior(int point, const Vec3& p_world, double sigma_m);

  // focal_px converts normalised residuals to pixels.
  BundleAdjustmentSummary solve(const BundleAdjustmentOptions& options, double focal_px);

  const SE3& camera(int i) const { return cameras_[i].T_camera_world; }
  const Vec3& point(int i) const { return points_[i].p_world; }
  int numCameras() const { return static_cast<int>(cameras_.size()); }
  int numPoints() const { return static_cast<int>(points_.size()); }
  // Reprojection error of observation k (in the order added), pixels; +inf when behind its camera.
  double errorPx(int k, double focal_px) const;

 private:
  struct Camera {
    SE3 T_camera_world;
    bool fixed;
    int block = -1;  // index among the free cameras
  };
  struct Point {
    Vec3 p_world;
    bool fixed;
    std::vector<int> observations;
    Vec3 prior = Vec3::Zero();
    double prior_weight = 0;  // 1 / sigma^2, 0: no prior
    bool on_ray = false;      // p_world = ray_origin + ray_direction / inverse_depth
    Vec3 ray_origin = Vec3::Zero(), ray_direction = Vec3::Zero();
    double inverse_depth = 0;
  };
  struct Observation {
    int camera, point;
    Vec2 xy;
    double weight;  // 1 / sigma^2 in normalised units (focal_px^2 / sigma_px^2)
  };
  // The Gauss-Newton normal equations (IRLS Huber weights) in blocks: U, gc per free camera, V, gp
  // per free point, W per observation coupling a free camera and a free point.
  struct NormalEquations {
    std::vector<Mat6> U;
    std::vector<Vec6> gc;
    std::vector<Mat3> V;
    std::vector<Vec3> gp;
    std::vector<Eigen::Matrix<double, 6, 3>> W;
    std::vector<char> used;  // per observation: in front of its camera, and something in it free
    int observations = 0;
  };
  struct Estimate {
    std::vector<SE3> T;       // T_camera_world per camera
    std::vector<Vec3> P;      // p_world per point
    std::vector<double> rho;  // the inverse depths of the points on rays
  };
  double cost(const std::vector<SE3>& cameras, const std::vector<Vec3>& points, double huber) const;
  void normalEquations(const Estimate& x, double huber, NormalEquations* eq) const;
  // The Levenberg-Marquardt step damped by lambda, the points eliminated (Schur complement);
  // false when the reduced camera system gives no finite step.
  bool dampedStep(const NormalEquations& eq, const Estimate& x, double lambda, int n_free, Estimate* next) const;

  std::vector<Camera> cameras_;
  std::vector<Point> points_;
  std::vector<Observation> observations_;
};

}  // namespace slamcmp
