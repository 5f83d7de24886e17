#include "monoslam_ekf/two_view_orientation.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <opencv2/video/tracking.hpp>

#include "core/error.h"
#include "core/options.h"
#include "ekf/ekf_update.h"

namespace slamcmp {

void TwoViewOrientationOptions::check() const {
  if (!(sigma_deg > 0)) throw OptionError("sigma_deg", "must be positive");
  if (lk_window_px < 5 || lk_window_px % 2 == 0) throw OptionError("lk_window_px", "must be odd and >= 5");
  if (lk_levels < 0 || lk_levels > 6) throw OptionError("lk_levels", "must be in [0, 6]");
}

void TwoViewOrientationOptions::checkImage(cv::Size image) const {
  requireWithinImage("lk_window_px", lk_window_px, std::min(image.width, image.height), image);
}

TwoViewOrientation::TwoViewOrientation(const CameraModel& camera, const TwoViewOrientationOptions& options)
    : camera_(camera), options_(options), tracker_(options.tracks), rotation_(options.rotation, camera.fx) {}

void TwoViewOrientation::update(const cv::Mat& grey, EkfState& state) {
  track(grey);
  const std::optional<Mat3> R_world_camera = rotation_.measure(tracks_);
  if (!R_world_camera) return;
  const double sigma = options_.sigma_deg * M_PI / 180.0;
  orientationUpdate(state, *R_world_camera, std::sqrt(sigma * sigma + reference_variance_));
}

void TwoViewOrientation::track(const cv::Mat& grey) {
  const cv::Size window(options_.lk_window_px, options_.lk_window_px);
  std::vector<cv::Mat> pyramid;
  cv::buildOpticalFlowPyramid(grey, pyramid, window, options_.lk_levels);
  if (!pyramid_.empty()) tracker_.track(pyramid_, pyramid, window, options_.lk_levels);
  tracker_.replenish(grey);
  pyramid_ = std::move(pyramid);
  tracks_.clear();
  for (const Feature& f : tracker_.features())  // in the tracker's order: ids ascending
    tracks_.emplace_back(f.id, camera_.undistortPixel(Vec2(f.uv.x, f.uv.y)));
}

void TwoViewOrientation::remember(const Mat3& R_world_camera, double rotation_variance) {
  rotation_.remember(std::move(tracks_), R_world_camera);  // update() makes this frame's afresh
  reference_variance_ = rotation_variance;
}

}  // namespace slamcmp
