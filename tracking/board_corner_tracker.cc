#include "tracking/board_corner_tracker.h"

#include <cmath>

#include <opencv2/video/tracking.hpp>

#include "core/error.h"
#include "geometry/homography_pose.h"

namespace slamcmp {

void BoardCornerTrackerOptions::check() const {
  if (!(max_grid_error_px > 0)) throw OptionError("max_grid_error_px", "must be positive");
  if (!(max_refine_shift_px > 0)) throw OptionError("max_refine_shift_px", "must be positive");
  if (search_margin_px < 0) throw OptionError("search_margin_px", "must be >= 0");
  if (search_interval_when_lost < 1) throw OptionError("search_interval_when_lost", "must be >= 1");
}

BoardCornerTracker::BoardCornerTracker(const ChessboardTarget& target, const BoardCornerTrackerOptions& options)
    : target_(target), options_(options) {}

bool BoardCornerTracker::confirm(const cv::Mat& grey, std::vector<cv::Point2f>& uv,
                                 const CameraModel& camera) const {
  const std::vector<cv::Point2f> tracked = uv;
  refineChessboardCorners(grey, target_, uv, options_.detector);
  for (size_t i = 0; i < uv.size(); ++i)
    if (cv::norm(uv[i] - tracked[i]) > options_.max_refine_shift_px) return false;
  // The grid must still be a plane seen through the lens: a homography from the board to the
  // undistorted corners fits them all.
  std::vector<Vec2> plane, undistorted;
  for (int j = 0; j < target_.rows; ++j)
    for (int i = 0; i < target_.cols; ++i) plane.emplace_back(i, j);
  for (const auto& p : uv) undistorted.push_back(camera.undistortToPixel(Vec2(p.x, p.y)));
  double sum = 0;
  for (double e : homographyErrors(homographyDlt(plane, undistorted), plane, undistorted)) sum += e * e;
  if (std::sqrt(sum / static_cast<double>(uv.size())) > options_.max_grid_error_px) return false;
  // A whole-grid slip by one square keeps the grid consistent but swaps the square colours.
  std::vector<cv::Point2f> ordered = uv;
  return orderChessboardCorners(grey, target_, ordered) && ordered.front() == uv.front();
}

std::optional<std::vector<cv::Point2f>> BoardCornerTracker::find(const cv::Mat& grey,
                                                                 const std::vector<cv::Mat>& pyramid_prev,
                                                                 const std::vector<cv::Mat>& pyramid,
                                                                 cv::Size lk_window, int lk_levels,
                                                                 const CameraModel* camera, bool allow_search,
                                                                 const SE3* T_world_camera_last) {
  last_tracked_ = false;
  if (options_.track && camera && !corners_.empty() && !pyramid_prev.empty()) {
    std::vector<cv::Point2f> uv;
    std::vector<uchar> status;
    std::vector<float> error;
    // Coarse convergence is enough: the corners are refined by cornerSubPix next.
    cv::calcOpticalFlowPyrLK(pyramid_prev, pyramid, corners_, uv, status, error, lk_window, lk_levels,
                             cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 10, 0.1));
    bool all = true;
    for (size_t i = 0; i < uv.size() && all; ++i)
      all = status[i] && uv[i].x >= 0 && uv[i].y >= 0 && uv[i].x <= grey.cols - 1 && uv[i].y <= grey.rows - 1;
    if (all && confirm(grey, uv, *camera)) {
      corners_ = last_seen_ = uv;
      last_tracked_ = true;
      return corners_;
    }
  }
  // Full search: at once when tracking fails, then every search_interval_when_lost frames.
  corners_.clear();
  if (!allow_search) return std::nullopt;
  if (frames_until_search_ > 0) {
    --frames_until_search_;
    return std::nullopt;
  }
  frames_until_search_ = options_.search_interval_when_lost - 1;
  std::vector<cv::Point2f> uv;
  if (!detectChessboard(grey, target_, &uv, options_.detector)) return std::nullopt;
  if (target_.symmetric()) {
    std::vector<cv::Point2f> predicted;
    if (camera && T_world_camera_last) predicted = projectBoardCorners(*camera, target_, *T_world_camera_last);
    chooseSymmetricOrder(target_, uv, predicted.empty() ? last_seen_ : predicted);
  }
  corners_ = last_seen_ = uv;
  frames_until_search_ = 0;
  return corners_;
}

}  // namespace slamcmp
