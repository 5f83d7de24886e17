#include "cslam/map_point_search.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "core/error.h"

namespace slamcmp {

void MapPointSearchOptions::check() const {
  if (radius_px < 1) throw OptionError("radius_px", "must be >= 1");
  if (!(min_ncc > 0 && min_ncc <= 1)) throw OptionError("min_ncc", "must be in (0, 1]");
  if (min_patch_stddev < 0) throw OptionError("min_patch_stddev", "must be >= 0");
  if (!(max_view_angle_deg > 0 && max_view_angle_deg < 90)) throw OptionError("max_view_angle_deg", "must be in (0, 90)");
  if (!(max_distance_ratio >= 1)) throw OptionError("max_distance_ratio", "must be >= 1");
  if (max_per_frame < 0) throw OptionError("max_per_frame", "must be >= 0");
  if (below_map_points < 0) throw OptionError("below_map_points", "must be >= 0");
}

namespace {

constexpr int kTemplateSize = 11;  // the correlation's template: the patch's centre
constexpr int kLkWindow = 9;       // the sub-pixel alignment's window (inside the patch)

}  // namespace

cv::Mat mapPointPatch(const cv::Mat& grey, const cv::Point2f& uv) {
  cv::Mat patch;
  cv::getRectSubPix(grey, cv::Size(kMapPatchSize, kMapPatchSize), uv, patch);
  return patch;
}

std::vector<Feature> searchMapPoints(const cv::Mat& grey, const CameraModel& camera, const SE3& T_world_camera,
                                     std::vector<MapPointCandidate> candidates, const std::vector<Feature>& existing,
                                     double min_distance_px, const MapPointSearchOptions& options) {
  std::vector<Feature> found;
  if (!options.enabled || candidates.empty()) return found;
  const SE3 T_camera_world = T_world_camera.inverse();
  const double max_cos = std::cos(options.max_view_angle_deg * M_PI / 180);
  const double min_d2 = min_distance_px * min_distance_px;
  const auto crowded = [&](const Vec2& uv) {
    const auto near = [&](const Feature& f) {
      const double dx = f.uv.x - uv.x(), dy = f.uv.y - uv.y();
      return dx * dx + dy * dy < min_d2;
    };
    return std::any_of(existing.begin(), existing.end(), near) || std::any_of(found.begin(), found.end(), near);
  };
  // The best-established points first.
  std::sort(candidates.begin(), candidates.end(), [](const MapPointCandidate& a, const MapPointCandidate& b) {
    return a.observations != b.observations ? a.observations > b.observations : a.id < b.id;
  });
  const int reach = options.radius_px + kTemplateSize / 2 + 1;
  int searched = 0;
  cv::Mat score;
  for (const MapPointCandidate& c : candidates) {
    if (searched >= options.max_per_frame) break;
    const Vec3 p_camera = T_camera_world * c.p_world;
    if (p_camera.z() <= 0) continue;
    // Seen from about the same direction and distance as when its patch was taken.
    const Vec3 now = c.p_world - T_world_camera.t(), then = c.p_world - c.seen_from;
    const double ratio = now.norm() / then.norm();
    if (now.normalized().dot(then.normalized()) < max_cos || ratio > options.max_distance_ratio ||
        ratio * options.max_distance_ratio < 1)
      continue;
    const Vec2 uv = camera.project(p_camera);
    if (!camera.inImage(uv, reach + 1) || crowded(uv)) continue;
    ++searched;
    const cv::Mat templ = (*c.patch)(cv::Rect((kMapPatchSize - kTemplateSize) / 2, (kMapPatchSize - kTemplateSize) / 2,
                                              kTemplateSize, kTemplateSize));
    cv::Scalar mean, stddev;
    cv::meanStdDev(templ, mean, stddev);
    if (stddev[0] < options.min_patch_stddev) continue;
    const cv::Point centre(static_cast<int>(std::lround(uv.x())), static_cast<int>(std::lround(uv.y())));
    const cv::Rect roi(centre.x - reach + 1, centre.y - reach + 1, 2 * reach - 1, 2 * reach - 1);
    cv::matchTemplate(grey(roi), templ, score, cv::TM_CCOEFF_NORMED);
    double best = 0;
    cv::Point at;
    cv::minMaxLoc(score, nullptr, &best, nullptr, &at);
    if (best < options.min_ncc) continue;
    // The correlation's peak to sub-pixel: Lucas-Kanade from the patch to the same patch of the
    // image around the peak.
    const cv::Point2f peak(static_cast<float>(roi.x + at.x + kTemplateSize / 2),
                           static_cast<float>(roi.y + at.y + kTemplateSize / 2));
    const cv::Mat around = mapPointPatch(grey, peak);
    const cv::Point2f middle(kMapPatchSize / 2, kMapPatchSize / 2);
    std::vector<cv::Point2f> from{middle}, to{middle};
    std::vector<uchar> status;
    cv::calcOpticalFlowPyrLK(*c.patch, around, from, to, status, cv::noArray(), cv::Size(kLkWindow, kLkWindow), 0,
                             cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 20, 0.01),
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    const cv::Point2f shift = to[0] - middle;
    if (!status[0] || cv::norm(shift) > 1.5) continue;
    const cv::Point2f uv_found = peak + shift;
    if (!camera.inImage(Vec2(uv_found.x, uv_found.y), kLkWindow)) continue;
    found.push_back({c.id, uv_found});
  }
  return found;
}

}  // namespace slamcmp
