#pragma once
// A lost filter's camera found again against its own map (RelocalisationOptions, ekf_options.h):
// the ORB descriptor of each feature's first view matched among the frame's corners described
// alike, and the PnP RANSAC pose of the matched map points.
#include <optional>
#include <vector>

#include <opencv2/features2d.hpp>

#include "core/camera.h"
#include "core/geometry.h"
#include "ekf/ekf_options.h"

namespace slamcmp {

class Relocaliser {
 public:
  explicit Relocaliser(const RelocalisationOptions& options);

  // The ORB descriptor (1 x 32 bytes) of the corner at uv, steered by its intensity centroid as
  // ORB's own keypoints are; empty within ORB's 31-pixel patch of the image border.
  cv::Mat describe(const cv::Mat& grey, const Vec2& uv) const;
  // T_world_camera from the map points p_world, with P_points their world covariances (one a
  // point) and row k of `descriptors` describing point k, matched in `grey`: nullopt when too few
  // agree (min_inliers of those known to within max_error_px where they project,
  // min_inlier_ratio of all), a pose puts them behind the camera, or the sizes differ. *inliers:
  // how many agreed and were known that well.
  std::optional<SE3> relocalise(const cv::Mat& grey, const CameraModel& camera, const std::vector<Vec3>& p_world,
                                const std::vector<Mat3>& P_points, const cv::Mat& descriptors, int* inliers) const;

 private:
  // ORB descriptors of the corners at `uv_distorted` (rows of the returned matrix); corners too
  // near the border are dropped from it.
  cv::Mat describeAll(const cv::Mat& grey, std::vector<cv::Point2f>* uv_distorted) const;

  RelocalisationOptions options_;
  cv::Ptr<cv::ORB> orb_;
};

}  // namespace slamcmp
