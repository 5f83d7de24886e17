#pragma once
// Camera pose from a planar target (thesis eqs. 3.1 to 3.17, Zhang 2000): a normalised DLT
// homography H = K [r1 r2 t], then lambda = 1/|K^-1 h1|, r1 = lambda K^-1 h1, r2 = lambda K^-1 h2,
// r3 = r1 x r2, t = lambda K^-1 h3, and the nearest rotation to [r1 r2 r3] by SVD.
// Pose direction (geometry/'s convention, camera from world, the board being the world):
// T_camera_board, p_camera = R p_board + t. A FrameResult's T_world_camera is its inverse.
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/geometry.h"
#include "core/target.h"
#include "geometry/pose_refinement.h"

namespace slamcmp {

// Normalised DLT (Hartley): H maps src to dst, dst ~ H (src, 1). Needs >= 4 points, not all on a
// line. H is scaled to unit Frobenius norm, its sign such that H (src, 1) has a positive third
// coordinate (a point beyond the plane's horizon, then, has a negative one).
Mat3 homographyDlt(const std::vector<Vec2>& src, const std::vector<Vec2>& dst);

// Whether the points determine a homography (homographyDlt and boardPose need it): four of them
// with no three on a line. Their DLT onto themselves then has a one-dimensional null space: its
// second smallest singular value is above 1e-6 of the largest (Hartley-normalised). A partial
// board's single row gives a homography and a pose that are anything (a review: 180 degrees off,
// its translation NaN), and a row with one corner off it too (up to 180 degrees).
bool determinesAHomography(const std::vector<Vec2>& points);

// Transfer error |dst - H src| per point, in the units of dst.
std::vector<double> homographyErrors(const Mat3& H, const std::vector<Vec2>& src, const std::vector<Vec2>& dst);

// Thesis eqs. 3.11 to 3.17 for H = K [r1 r2 t] (plane Z = 0 to undistorted pixels): the board
// frame in the camera frame, T_camera_board. The sign of lambda puts the board in front.
SE3 poseFromHomography(const Mat3& H, const Mat3& K);

struct BoardPoseOptions {
  bool refine = true;  // Levenberg-Marquardt on the reprojection error after the homography
  PoseRefinementOptions refinement;
  template <class V>
  void visit(V& v) {
    v("refine", refine, "refine the homography pose by Levenberg-Marquardt on the reprojection error");
    v("refinement", refinement, "the refinement");
  }
  void check() const {}  // the refinement checks itself (checkOptions)
};

struct BoardPose {
  SE3 T_camera_board;
  double rms_px = 0;  // reprojection error of the corners, pixels
};

// Pose of the plane Z = 0 (points p_board, z ignored) seen at xy_normalised (undistorted
// normalised coordinates): homography in those coordinates (K = identity), decomposition, then the
// optional refinement. focal_px converts errors to pixels.
BoardPose boardPose(const std::vector<Vec3>& p_board, const std::vector<Vec2>& xy_normalised,
                    double focal_px, const BoardPoseOptions& options);

// boardPose of a whole board's corners as detected (every corner, SPEC section 2 order, distorted
// pixels), undistorted with `camera` and weighed at its mean focal length.
BoardPose wholeBoardPose(const CameraModel& camera, const ChessboardTarget& target,
                         const std::vector<cv::Point2f>& uv_distorted, const BoardPoseOptions& options);

}  // namespace slamcmp
