#pragma once
// Shi-Tomasi features over the whole image, tracked frame to frame by pyramidal Lucas-Kanade
// (thesis eqs. 3.18 to 3.26, Bouguet's algorithm) with a forward-backward check, and replenished
// in empty image regions when too few survive.
#include <vector>

#include <opencv2/core.hpp>

namespace slamcmp {

struct FeatureTrackerOptions {
  int max_features = 150;         // detected up to this many
  int min_features = 90;          // replenish when fewer survive
  double quality_level = 0.01;    // Shi-Tomasi: fraction of the best corner's response
  double min_distance_px = 12;    // between features (also the mask radius around existing ones)
  int block_size = 5;             // Shi-Tomasi window, pixels
  double max_forward_backward_px = 0.5;  // tracked back, a feature must land this close to its start
  int border_px = 8;              // features this close to the image border are dropped
  template <class V>
  void visit(V& v) {
    v("max_features", max_features, "Shi-Tomasi features held at most");
    v("min_features", min_features, "new features are detected when fewer than this survive");
    v("quality_level", quality_level, "Shi-Tomasi quality, fraction of the strongest corner response");
    v("min_distance_px", min_distance_px, "minimum distance between features, pixels");
    v("block_size", block_size, "Shi-Tomasi window side, pixels");
    v("max_forward_backward_px", max_forward_backward_px,
      "forward-backward check: a feature tracked back must land this close to where it was, pixels");
    v("border_px", border_px, "features closer to the image border are dropped, pixels");
  }
  void check() const;
  void checkImage(cv::Size image) const;  // the windows, border and spacing fit in the image
};

struct Feature {
  int id = 0;
  cv::Point2f uv;  // distorted pixels in the current frame
};

class FeatureTracker {
 public:
  explicit FeatureTracker(const FeatureTrackerOptions& options);

  // Moves the features from the previous pyramid to the current one; features failing LK, the
  // forward-backward check or the border are dropped. predicted_uv (one per features(), distorted
  // pixels, e.g. from a motion model) starts Lucas-Kanade there instead of at the old positions:
  // motions beyond the pyramid's reach (a fast turn) are then still tracked.
  void track(const std::vector<cv::Mat>& pyramid_prev, const std::vector<cv::Mat>& pyramid,
             cv::Size lk_window, int lk_levels, const std::vector<cv::Point2f>* predicted_uv = nullptr);
  // Drops the features whose id is flagged (e.g. epipolar outliers): keep[i] for features()[i].
  void keepOnly(const std::vector<char>& keep);
  // Adds features the caller found again (e.g. map points matched where the camera pose projects
  // them), with their old ids.
  void add(const std::vector<Feature>& found);
  // Detects new features away from the existing ones, and from the points `avoid` (what is
  // measured otherwise, e.g. a board's corners), when fewer than min_features are held. Returns
  // the number added.
  int replenish(const cv::Mat& grey, const std::vector<cv::Point2f>& avoid = {});
  void clear() { features_.clear(); }

  const std::vector<Feature>& features() const { return features_; }
  // The features dropped since the last track() by Lucas-Kanade, the forward-backward check or
  // keepOnly, at their last position (for drawing).
  const std::vector<Feature>& dropped() const { return dropped_; }
  // The ids of every feature that ended since the last track(): dropped, or left the image.
  const std::vector<int>& ended() const { return ended_; }

 private:
  FeatureTrackerOptions options_;
  std::vector<Feature> features_;
  std::vector<Feature> dropped_;
  std::vector<int> ended_;
  int next_id_ = 0;
};

}  // namespace slamcmp
