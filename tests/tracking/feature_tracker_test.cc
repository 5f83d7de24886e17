// tracking/feature_tracker: Shi-Tomasi features moved by pyramidal Lucas-Kanade on images whose
// true motion is known exactly (a texture shifted by a sub-pixel translation), features leaving
// the image dropped, and the forward-backward check rejecting a patch that is not in the other
// image.
#include "tracking/feature_tracker.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

#include "tests/tracking/blob_texture.h"

namespace slamcmp {
namespace {

using test::BlobTexture;

const cv::Size kImage(320, 240);
const cv::Size kWindow(15, 15);  // Lucas-Kanade window, pixels
constexpr int kLevels = 3;       // pyramid levels above the image: motions up to ~7 * 2^3 px
// Near the border the window reaches past the image at the coarse pyramid levels, where
// Lucas-Kanade may converge to a wrong minimum: features this close are not judged.
constexpr double kJudgedMarginPx = 20;

bool judged(double x, double y) {
  return x >= kJudgedMarginPx && y >= kJudgedMarginPx && x <= kImage.width - 1 - kJudgedMarginPx &&
         y <= kImage.height - 1 - kJudgedMarginPx;
}

std::vector<cv::Mat> pyramid(const cv::Mat& grey) {
  std::vector<cv::Mat> p;
  cv::buildOpticalFlowPyramid(grey, p, kWindow, kLevels);
  return p;
}

std::map<int, cv::Point2f> byId(const std::vector<Feature>& features) {
  std::map<int, cv::Point2f> m;
  for (const Feature& f : features) m[f.id] = f.uv;
  return m;
}

// Tracks the features detected on texture(0, 0) into texture(dx, dy); returns them before and after.
struct TrackedPair {
  std::map<int, cv::Point2f> before, after;
  std::vector<int> ended, dropped;
};

TrackedPair trackShift(const FeatureTrackerOptions& options, const cv::Mat& first, const cv::Mat& second) {
  FeatureTracker tracker(options);
  tracker.replenish(first);
  TrackedPair t;
  t.before = byId(tracker.features());
  tracker.track(pyramid(first), pyramid(second), kWindow, kLevels);
  t.after = byId(tracker.features());
  t.ended = tracker.ended();
  for (const Feature& f : tracker.dropped()) t.dropped.push_back(f.id);
  return t;
}

class FeatureTrackerShift : public ::testing::TestWithParam<cv::Point2d> {};

// Every feature (away from the border, before and after) moves by the true shift. Lucas-Kanade
// stops when its update is under 0.03 px (feature_tracker.cc) and the images are rounded to 8
// bits, so a feature lands within 0.1 px of the truth, 0.03 px in the median (measured: 0.045 px
// at worst, 0.01 px median); and all survive.
TEST_P(FeatureTrackerShift, FeaturesMoveByTheShift) {
  const cv::Point2d shift = GetParam();
  const BlobTexture texture(3, kImage);
  const TrackedPair t = trackShift(FeatureTrackerOptions{}, texture.image(kImage), texture.image(kImage, shift.x, shift.y));
  ASSERT_GE(t.before.size(), 60u);
  int expected = 0;
  std::vector<double> errors;
  for (const auto& [id, uv] : t.before) {
    const cv::Point2f moved(static_cast<float>(uv.x + shift.x), static_cast<float>(uv.y + shift.y));
    if (!judged(uv.x, uv.y) || !judged(moved.x, moved.y)) continue;
    ++expected;
    const auto it = t.after.find(id);
    if (it == t.after.end()) {
      ADD_FAILURE() << "feature " << id << " at (" << uv.x << ", " << uv.y << ") lost";
      continue;
    }
    errors.push_back(std::hypot(it->second.x - moved.x, it->second.y - moved.y));
    EXPECT_LT(errors.back(), 0.1) << "feature " << id;
  }
  ASSERT_GT(expected, 40);
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  EXPECT_LT(errors[errors.size() / 2], 0.03);
}

INSTANTIATE_TEST_SUITE_P(Shifts, FeatureTrackerShift,
                         ::testing::Values(cv::Point2d(0.37, -0.21), cv::Point2d(-2.64, 1.18),
                                           cv::Point2d(6.5, 4.25), cv::Point2d(-11.3, -7.7)));

// A shift of 30.4 px to the right: features that end up within border_px (8) of the right edge or
// beyond it end (ended(), gone from features()); those away from every border are kept where they
// moved. Features within 1 px of the border line either way are not judged (tracking error).
TEST(FeatureTracker, FeaturesLeavingTheImageAreDropped) {
  const BlobTexture texture(5, kImage);
  const double dx = 30.4;
  const FeatureTrackerOptions options;
  const TrackedPair t = trackShift(options, texture.image(kImage), texture.image(kImage, dx, 0));
  const std::set<int> ended(t.ended.begin(), t.ended.end());
  const double right = kImage.width - 1 - options.border_px;
  int leaving = 0, staying = 0;
  for (const auto& [id, uv] : t.before) {
    const double x = uv.x + dx;
    if (x > right + 1) {
      ++leaving;
      EXPECT_FALSE(t.after.count(id)) << "feature " << id << " moved to x = " << x;
      EXPECT_TRUE(ended.count(id)) << "feature " << id;
    } else if (x < right - 1 && judged(uv.x, uv.y) && judged(x, uv.y)) {
      ++staying;
      ASSERT_TRUE(t.after.count(id)) << "feature " << id << " moved to x = " << x;
      EXPECT_NEAR(t.after.at(id).x, x, 0.1);
      EXPECT_FALSE(ended.count(id)) << "feature " << id;
    }
  }
  EXPECT_GT(leaving, 5);
  EXPECT_GT(staying, 40);
  // Whatever else happened, nothing is held within border_px of the edges.
  for (const auto& [id, uv] : t.after) {
    EXPECT_GE(uv.x, options.border_px);
    EXPECT_LE(uv.x, right);
    EXPECT_GE(uv.y, options.border_px);
    EXPECT_LE(uv.y, kImage.height - 1 - options.border_px);
  }
}

// In the second image the patch around one feature is replaced by another part of the texture
// (turned a quarter): Lucas-Kanade forward converges somewhere, but tracked back it does not come
// home, so the forward-backward check drops it (dropped() and ended()), while its neighbours
// outside the patch are kept. With the check switched off (a threshold of 1e6 px) the same
// feature is kept: it is the check that rejects it.
TEST(FeatureTracker, ForwardBackwardCheckRejectsACorruptedPatch) {
  const BlobTexture texture(7, kImage);
  const cv::Point2d shift(1.3, -0.8);
  const cv::Mat first = texture.image(kImage);
  cv::Mat second = texture.image(kImage, shift.x, shift.y);

  FeatureTracker detector{FeatureTrackerOptions{}};
  detector.replenish(first);
  // The feature nearest the image centre.
  const cv::Point2f centre(kImage.width / 2.0f, kImage.height / 2.0f);
  const Feature victim = *std::min_element(detector.features().begin(), detector.features().end(),
                                           [&](const Feature& a, const Feature& b) {
                                             return cv::norm(a.uv - centre) < cv::norm(b.uv - centre);
                                           });
  const int half = 12;  // the patch: 25 x 25 px, wider than the 15 px window
  const cv::Point moved(cvRound(victim.uv.x + shift.x), cvRound(victim.uv.y + shift.y));
  const cv::Rect patch(moved.x - half, moved.y - half, 2 * half + 1, 2 * half + 1);
  cv::Mat other = texture.image(cv::Size(2 * half + 1, 2 * half + 1), -200.5, -150.5);
  cv::rotate(other, other, cv::ROTATE_90_CLOCKWISE);
  other.copyTo(second(patch));

  const TrackedPair checked = trackShift(FeatureTrackerOptions{}, first, second);
  EXPECT_FALSE(checked.after.count(victim.id));
  EXPECT_TRUE(std::count(checked.dropped.begin(), checked.dropped.end(), victim.id));
  EXPECT_TRUE(std::count(checked.ended.begin(), checked.ended.end(), victim.id));
  // Features whose window cannot reach the patch (patch half-width plus a window) and not near
  // the border are all kept.
  const double reach = half + kWindow.width;
  int kept_far = 0, far = 0;
  for (const auto& [id, uv] : checked.before) {
    const cv::Point2f p(static_cast<float>(uv.x + shift.x), static_cast<float>(uv.y + shift.y));
    if (std::abs(p.x - moved.x) <= reach && std::abs(p.y - moved.y) <= reach) continue;
    if (!judged(uv.x, uv.y) || !judged(p.x, p.y)) continue;
    ++far;
    kept_far += checked.after.count(id) > 0;
  }
  EXPECT_GT(far, 40);
  EXPECT_EQ(kept_far, far);

  FeatureTrackerOptions unchecked_options;
  unchecked_options.max_forward_backward_px = 1e6;
  const TrackedPair unchecked = trackShift(unchecked_options, first, second);
  EXPECT_TRUE(unchecked.after.count(victim.id)) << "Lucas-Kanade itself failed on the corrupted patch";
}

// New features keep min_distance_px from the points given to avoid (what is measured otherwise:
// cslam's board corners) as from the features held, and start elsewhere as before: on the same
// texture, the features found without them that lie farther from every avoided point are found
// again, at the same pixels, and none is found nearer.
TEST(FeatureTracker, NewFeaturesAvoidTheGivenPoints) {
  const BlobTexture texture(11, kImage);
  const cv::Mat grey = texture.image(kImage);
  FeatureTrackerOptions options;
  options.max_features = 60;
  FeatureTracker plain(options);
  plain.replenish(grey);
  // A third of the features found, as if they were a board's corners.
  std::vector<cv::Point2f> avoid;
  for (size_t k = 0; k < plain.features().size(); k += 3) avoid.push_back(plain.features()[k].uv);
  ASSERT_GE(avoid.size(), 10u);
  FeatureTracker avoiding(options);
  EXPECT_GT(avoiding.replenish(grey, avoid), 0);
  const auto nearest = [&](const cv::Point2f& p) {
    double d = 1e9;
    for (const cv::Point2f& a : avoid) d = std::min<double>(d, cv::norm(p - a));
    return d;
  };
  std::set<std::pair<float, float>> found;
  for (const Feature& f : avoiding.features()) {
    EXPECT_GE(nearest(f.uv), options.min_distance_px - 1) << f.uv;  // the mask's disc is drawn in whole pixels
    found.insert({f.uv.x, f.uv.y});
  }
  int far = 0;
  for (const Feature& f : plain.features())
    if (nearest(f.uv) > 2 * options.min_distance_px) {
      ++far;
      EXPECT_TRUE(found.count({f.uv.x, f.uv.y})) << f.uv;
    }
  EXPECT_GT(far, 5);
}

}  // namespace
}  // namespace slamcmp
