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
  const RelocalisationOptions& options() const { return options_; }

  // The ORB descriptor (1 x 32 bytes) of the corner at uv, steered by its intensity centroid as
  // ORB's own keypoints are; empty within ORB's 31-pixel patch of the image border.
  cv::Mat describe(const cv::Mat& grey, const Vec2& uv) const;
  // ORB descriptors of the corners at `uv_distorted` (rows of the returned matrix); corners too
  // near the border are dropped from it, and *uv_distorted keeps only the corners described.
  cv::Mat describeAll(const cv::Mat& grey, std::vector<cv::Point2f>* uv_distorted) const;
  // T_world_camera from the map points p_world, with P_points their world covariances (one a
  // point) and row k of `descriptors` describing point k, matched in `grey`: nullopt when too few
  // agree (min_inliers of those known to within max_error_px where they project,
  // min_inlier_ratio of all), a pose puts them behind the camera, or the sizes differ. *inliers:
  // how many agreed and were known that well. Matched among all the frame's corners; where that
  // finds no pose and a guess is given (the lost filter's own pose), among the corners within
  // guided_radius_px of where the guess projects each point.
  std::optional<SE3> relocalise(const cv::Mat& grey, const CameraModel& camera, const std::vector<Vec3>& p_world,
                                const std::vector<Mat3>& P_points, const cv::Mat& descriptors, int* inliers,
                                const SE3* T_world_camera_guess = nullptr) const;

 private:
  // Each map descriptor's nearest frame descriptor, kept when it passes Lowe's ratio test
  // (queryIdx: the map point, trainIdx: the frame corner).
  std::vector<cv::DMatch> matchAll(const cv::Mat& descriptors, const cv::Mat& frame_descriptors) const;
  // The same among the corners near where T_world_camera projects each point, and within
  // guided_max_hamming (a point with one candidate has no second best to test against).
  std::vector<cv::DMatch> matchNear(const cv::Mat& descriptors, const cv::Mat& frame_descriptors,
                                    const std::vector<cv::Point2f>& uv_distorted, const CameraModel& camera,
                                    const std::vector<Vec3>& p_world, const SE3& T_world_camera) const;
  // The PnP RANSAC pose of the matched points and its checks (relocalise()).
  std::optional<SE3> poseFromMatches(const std::vector<cv::DMatch>& matches,
                                     const std::vector<cv::Point2f>& uv_distorted, const CameraModel& camera,
                                     const std::vector<Vec3>& p_world, const std::vector<Mat3>& P_points,
                                     int* inliers) const;

  RelocalisationOptions options_;
  cv::Ptr<cv::ORB> orb_;
};

}  // namespace slamcmp
