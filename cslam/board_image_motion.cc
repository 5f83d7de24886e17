#include "cslam/board_image_motion.h"

#include <cmath>

#include <opencv2/calib3d.hpp>

#include "core/error.h"
#include "geometry/homography_pose.h"

namespace slamcmp {

void BoardImageMotionOptions::check() const {
  if (min_matches < 4) throw OptionError("min_matches", "must be >= 4 (a homography)");
  if (!(max_error_px > 0)) throw OptionError("max_error_px", "must be positive");
}

BoardImageMotion::BoardImageMotion(const BoardImageMotionOptions& options, double focal_px)
    : options_(options), focal_px_(focal_px) {}

void BoardImageMotion::seen(const std::vector<Vec3>& p_world, const std::vector<Vec2>& xy) {
  std::vector<Vec2> plane;
  plane.reserve(p_world.size());
  for (const Vec3& p : p_world) plane.push_back(p.head<2>());
  H_image_board_ = homographyDlt(plane, xy);
}

void BoardImageMotion::advance(const std::unordered_map<int, Vec2>& xy_previous,
                               const std::unordered_map<int, Vec2>& xy_current) {
  if (!H_image_board_) return;
  std::vector<cv::Point2d> previous, current;
  for (const auto& [id, xy] : xy_current) {
    const auto it = xy_previous.find(id);
    if (it == xy_previous.end()) continue;
    previous.emplace_back(it->second.x(), it->second.y());
    current.emplace_back(xy.x(), xy.y());
  }
  if (static_cast<int>(previous.size()) < options_.min_matches) return forget();
  cv::Mat inliers;
  const cv::Mat H = cv::findHomography(previous, current, cv::RANSAC, options_.max_error_px / focal_px_, inliers);
  if (H.empty() || cv::countNonZero(inliers) < options_.min_matches) return forget();
  Mat3 H_current_previous;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) H_current_previous(r, c) = H.at<double>(r, c);
  H_image_board_ = H_current_previous * *H_image_board_;
  H_image_board_->normalize();  // kept at unit norm over a long chain (the sign stays)
}

std::vector<cv::Point2f> BoardImageMotion::corners(const CameraModel& camera,
                                                   const std::vector<Vec3>& corners_world) const {
  if (!H_image_board_) return {};
  std::vector<cv::Point2f> uv;
  uv.reserve(corners_world.size());
  // The sign homographyDlt fixes puts the plane's seen side at w > 0.
  for (const Vec3& p : corners_world) {
    const Vec3 x = *H_image_board_ * Vec3(p.x(), p.y(), 1.0);
    const Vec2 q = x.z() > 0 ? camera.project(x) : Vec2::Constant(std::nan(""));
    uv.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()));
  }
  return uv;
}

}  // namespace slamcmp
