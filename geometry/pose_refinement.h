#pragma once
// Levenberg-Marquardt over the 6 pose parameters: minimises the reprojection error of known 3D
// points, optionally with Huber weights (map points may hold outliers; board corners do not).
// Pose direction (geometry/'s convention): T_camera_world, p_camera = R p_world + t.
#include <vector>

#include "core/geometry.h"

namespace slamcmp {

struct PoseRefinementOptions {
  int max_iterations = 10;
  double huber_px = 0.0;  // Huber threshold in pixels; 0 = plain least squares
  template <class V>
  void visit(V& v) {
    v("max_iterations", max_iterations, "Levenberg-Marquardt iterations at most");
    v("huber_px", huber_px, "Huber threshold on the reprojection error, pixels; 0 = plain least squares");
  }
  void check() const;
};

struct PoseRefinementResult {
  SE3 T_camera_world;
  double rms_px = 0;  // reprojection error after refinement (unweighted)
  int iterations = 0;
};

// p_world[i] projects to xy_normalised[i] (undistorted normalised coordinates). focal_px scales
// normalised residuals to pixels (for the Huber threshold and the reported error). Points behind
// the camera are ignored. Needs at least 3 points in front.
PoseRefinementResult refinePose(const SE3& T_camera_world, const std::vector<Vec3>& p_world,
                                const std::vector<Vec2>& xy_normalised, double focal_px,
                                const PoseRefinementOptions& options);

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

// Gauss-Newton Hessian J^T J of the reprojection errors (pixels) at T_camera_world over the left
// perturbation (rotation vector, translation) that refinePose uses: divided by the pixel noise
// variance it is the pose's information matrix.
Mat6 reprojectionHessian(const SE3& T_camera_world, const std::vector<Vec3>& p_world,
                         const std::vector<Vec2>& xy_normalised, double focal_px);

// The left perturbation delta with T_to = exp(delta) T_from (rotation vector, translation), and
// its inverse: T_from moved by delta.
Vec6 poseDifference(const SE3& T_to, const SE3& T_from);
SE3 applyPoseDelta(const SE3& T, const Vec6& delta);

// The Jacobian of the normalised projection times `scale` (focal_px: pixels) over that
// perturbation, at p_camera = T p_world in front: applyPoseDelta moves p_camera to
// p_camera + omega x p_camera + v, so it is scale pinholeJacobian(p_camera) [-[p_camera]x, I].
Eigen::Matrix<double, 2, 6> projectionPoseJacobian(const Vec3& p_camera, double scale = 1);

// Reprojection errors in pixels (normalised residual times focal_px); +inf for a point behind.
std::vector<double> reprojectionErrorsPx(const SE3& T_camera_world, const std::vector<Vec3>& p_world,
                                         const std::vector<Vec2>& xy_normalised, double focal_px);

}  // namespace slamcmp
