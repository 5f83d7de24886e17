#pragma once
// The camera pose from the detected chessboard: the start (and restart) of the EKF with
// `--init board`.
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/target.h"

namespace slamcmp {

// T_world_camera from the board's inner corners (distorted pixels, SPEC section 2 order), by
// cv::solvePnP (iterative, minimising the reprojection error through the full camera model).
SE3 boardPose(const CameraModel& camera, const ChessboardTarget& target,
              const std::vector<cv::Point2f>& uv_distorted);

// The four outer inner corners' pixels (ChessboardTarget::outerCornersWorld order) among them.
std::vector<Vec2> outerCornerPixels(const ChessboardTarget& target,
                                    const std::vector<cv::Point2f>& uv_distorted);

}  // namespace slamcmp
