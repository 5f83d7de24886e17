#include "tracking/feature_tracker.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "core/error.h"
#include "core/options.h"

namespace slamcmp {

void FeatureTrackerOptions::check() const {
  if (max_features < 8) throw OptionError("max_features", "must be >= 8");
  if (min_features < 0 || min_features > max_features)
    throw OptionError("min_features", "must be in [0, max_features]");
  if (!(quality_level > 0 && quality_level < 1)) throw OptionError("quality_level", "must be in (0, 1)");
  if (!(min_distance_px >= 1)) throw OptionError("min_distance_px", "must be >= 1");
  if (block_size < 3 || block_size % 2 == 0) throw OptionError("block_size", "must be odd and >= 3");
  if (!(max_forward_backward_px > 0)) throw OptionError("max_forward_backward_px", "must be positive");
  if (border_px < 0) throw OptionError("border_px", "must be >= 0");
}

void FeatureTrackerOptions::checkImage(cv::Size image) const {
  const int side = std::min(image.width, image.height);
  requireWithinImage("block_size", block_size, side, image);
  requireWithinImage("border_px", border_px, (side - 1) / 2, image);  // the detection mask keeps a pixel
  requireWithinImage("min_distance_px", min_distance_px, std::max(image.width, image.height), image);
}

FeatureTracker::FeatureTracker(const FeatureTrackerOptions& options) : options_(options) {}

void FeatureTracker::track(const std::vector<cv::Mat>& pyramid_prev, const std::vector<cv::Mat>& pyramid,
                           cv::Size lk_window, int lk_levels, const std::vector<cv::Point2f>* predicted_uv) {
  dropped_.clear();
  ended_.clear();
  if (features_.empty()) return;
  std::vector<cv::Point2f> prev, next, back;
  prev.reserve(features_.size());
  for (const auto& f : features_) prev.push_back(f.uv);
  std::vector<uchar> status, status_back;
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 20, 0.03);
  int flags = 0;
  if (predicted_uv && predicted_uv->size() == features_.size()) {
    next = *predicted_uv;
    flags = cv::OPTFLOW_USE_INITIAL_FLOW;
  }
  // Without the per-point error, LK's status no longer drops a point ending outside the image: the
  // border test below does.
  cv::calcOpticalFlowPyrLK(pyramid_prev, pyramid, prev, next, status, cv::noArray(), lk_window, lk_levels, criteria,
                           flags);
  // Backward from the tracked position, started at the original one over one pyramid level (as
  // VINS-Mono does): a consistent track returns within a fraction of a pixel. It costs two thirds
  // of the forward pass (250 tum_fr1_rpy tracks, 21 px, one core: 1.3 against 2.1 ms): each level's
  // window is set up afresh whatever the motion. Over the image alone (0.7 ms) the check lets more
  // wrong tracks through (docs/findings.md, session 35).
  back = prev;
  cv::calcOpticalFlowPyrLK(pyramid, pyramid_prev, next, back, status_back, cv::noArray(), lk_window,
                           std::min(lk_levels, 1), criteria, cv::OPTFLOW_USE_INITIAL_FLOW);
  const cv::Size size = pyramid[0].size();
  const float b = static_cast<float>(options_.border_px);
  const double fb2 = options_.max_forward_backward_px * options_.max_forward_backward_px;
  std::vector<Feature> kept;
  kept.reserve(features_.size());
  for (size_t i = 0; i < features_.size(); ++i) {
    const cv::Point2f& p = next[i];
    const cv::Point2f d = back[i] - prev[i];
    if (!status[i] || !status_back[i] || d.dot(d) > fb2) {
      dropped_.push_back(features_[i]);
      ended_.push_back(features_[i].id);
      continue;
    }
    if (p.x < b || p.y < b || p.x > size.width - 1 - b || p.y > size.height - 1 - b) {
      ended_.push_back(features_[i].id);
      continue;
    }
    kept.push_back({features_[i].id, p});
  }
  features_ = std::move(kept);
}

void FeatureTracker::keepOnly(const std::vector<char>& keep) {
  CV_Assert(keep.size() == features_.size());
  std::vector<Feature> kept;
  for (size_t i = 0; i < features_.size(); ++i) {
    if (keep[i]) {
      kept.push_back(features_[i]);
    } else {
      dropped_.push_back(features_[i]);
      ended_.push_back(features_[i].id);
    }
  }
  features_ = std::move(kept);
}

void FeatureTracker::add(const std::vector<Feature>& found) {
  features_.insert(features_.end(), found.begin(), found.end());
}

int FeatureTracker::replenish(const cv::Mat& grey, const std::vector<cv::Point2f>& avoid) {
  const int held = static_cast<int>(features_.size());
  if (held >= options_.min_features) return 0;
  // Only the empty regions: a disc around every existing feature is masked out.
  cv::Mat mask(grey.size(), CV_8UC1, cv::Scalar(0));
  const int b = options_.border_px;
  mask(cv::Rect(b, b, grey.cols - 2 * b, grey.rows - 2 * b)).setTo(255);
  const int radius = static_cast<int>(options_.min_distance_px);
  for (const auto& f : features_) cv::circle(mask, f.uv, radius, cv::Scalar(0), -1);
  for (const cv::Point2f& p : avoid) cv::circle(mask, p, radius, cv::Scalar(0), -1);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(grey, corners, options_.max_features - held, options_.quality_level,
                          options_.min_distance_px, mask, options_.block_size);
  for (const auto& c : corners) features_.push_back({next_id_++, c});
  return static_cast<int>(corners.size());
}

}  // namespace slamcmp
