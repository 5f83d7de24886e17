#include "hybrid/tracked_points.h"

#include <algorithm>
#include <cmath>

#include <opencv2/video/tracking.hpp>

#include "core/error.h"
#include "core/statistics.h"
#include "ekf/ekf_update.h"
#include "ekf/inverse_depth.h"
#include "ekf/rolling_shutter.h"

namespace slamcmp {

namespace {
constexpr TailLayout::Kind kPoint = TailLayout::Kind::kPoint;
}  // namespace

void TrackedPointsOptions::check() const {
  if (max < 0) throw OptionError("max", "must not be negative");
  if (!(pixel_sigma > 0)) throw OptionError("pixel_sigma", "must be positive");
  if (!(rho >= 0 && rho < 1e3)) throw OptionError("rho", "must be in [0, 1000)");
  if (!(rho_sigma > 0 && rho_sigma < 1e3)) throw OptionError("rho_sigma", "must be in (0, 1000)");
  if (!(max_anchor_px > 0)) throw OptionError("max_anchor_px", "must be positive");
  if (!(max_deformation_px > 0)) throw OptionError("max_deformation_px", "must be positive");
}

TrackedPoints::TrackedPoints(const CameraModel& camera, const TrackedPointsOptions& options, double gate_probability,
                             cv::Size lk_window, int lk_levels, double rolling_shutter_readout)
    : camera_(camera),
      options_(options),
      gate_(chiSquaredQuantile(2, gate_probability)),
      readout_(rolling_shutter_readout),
      lk_window_(lk_window),
      lk_levels_(lk_levels) {}

double TrackedPoints::patchDeformation(const EkfState& state, int offset, const Point& point,
                                       double half_diagonal) const {
  // Scaled by s and turned by a small roll, the patch moves its corners by about
  // (|s - 1| + |roll|) times the half diagonal.
  const Vec6 y = state.x().segment<6>(offset);
  // Now over then distance: |x0 + m / rho - r| / (1 / rho), with no clamp on rho (at 0, a point at
  // infinity, it is 1).
  const double scale = (y(5) * (y.head<3>() - state.r()) + inverseDepthDirection(y(3), y(4))).norm();
  const Mat3 R_first_now = point.R_world_first.transpose() * rotationFromQuat(state.q());
  const double roll = std::atan2(R_first_now(1, 0), R_first_now(0, 0));  // about the optical axis
  return (std::abs(scale - 1) + std::abs(roll)) * half_diagonal;
}

int TrackedPoints::measure(EkfState& state, TailLayout& tail, const std::vector<Feature>& features,
                            const std::vector<cv::Mat>& pyramid) {
  // Where each track is now, for the points that still look like their first image.
  const double half_diagonal = 0.5 * std::hypot(lk_window_.width, lk_window_.height);
  std::unordered_map<int, cv::Point2f> tracked;
  std::map<int, std::vector<int>> by_first;  // a batch per first image
  for (const Feature& f : features) {
    const auto it = points_.find(f.id);
    if (it == points_.end() ||
        patchDeformation(state, tail.offset(state, kPoint, f.id), it->second, half_diagonal) >
            options_.max_deformation_px)
      continue;
    tracked.emplace(f.id, f.uv);
    by_first[it->second.first].push_back(f.id);
  }
  // Found again from the first image, begun at the track.
  std::unordered_map<int, Vec2> found;
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 20, 0.01);
  const float max2 = static_cast<float>(options_.max_anchor_px * options_.max_anchor_px);
  for (const auto& [first, ids] : by_first) {
    std::vector<cv::Point2f> from, to;
    for (const int id : ids) {
      from.push_back(points_.at(id).first_uv);
      to.push_back(tracked.at(id));
    }
    std::vector<uchar> status;
    cv::calcOpticalFlowPyrLK(first_images_.at(first), pyramid, from, to, status, cv::noArray(), lk_window_, lk_levels_,
                             criteria, cv::OPTFLOW_USE_INITIAL_FLOW);
    for (size_t k = 0; k < ids.size(); ++k) {
      const cv::Point2f d = to[k] - tracked.at(ids[k]);
      const Vec2 uv(to[k].x, to[k].y);  // in the image: LK's status does not say so without its error output
      if (status[k] && d.dot(d) <= max2 && camera_.inImage(uv)) found.emplace(ids[k], uv);
    }
  }
  std::vector<int> drop;
  std::vector<PointObservation> observations;
  for (const auto& entry : points_) {
    const int id = entry.first;
    const auto it = found.find(id);
    PointObservation o;
    o.offset = tail.offset(state, kPoint, id);
    if (it == found.end() ||  // track ended, first image no longer alike (it starts again), or behind
        !predictAtRowTime(
            camera_, readout_, state.x().head<13>(),
            [&](const Vec3& r, const Vec4& q, PointMeasurement* h) {
              return predictInverseDepthMeasurement(camera_, r, q, state.x().segment<6>(o.offset), h);
            },
            &o.h)) {
      drop.push_back(id);
      continue;
    }
    o.z = it->second;
    const Vec2 nu = o.z - o.h.uv_distorted;
    const Mat2 S = pointInnovationCovariance(state, o.h, o.offset, options_.pixel_sigma);
    if (nu.dot(S.ldlt().solve(nu)) > gate_) {
      drop.push_back(id);
      refused_.insert(id);  // not a point again (its steps still go to the window, gated there)
      continue;
    }
    observations.push_back(o);
  }
  if (!observations.empty() && !batchUpdate(state, observations, options_.pixel_sigma)) observations.clear();
  for (const int id : drop) {
    tail.remove(state, kPoint, id);
    points_.erase(id);
  }
  return static_cast<int>(observations.size());
}

std::vector<int> TrackedPoints::start(EkfState& state, TailLayout& tail, const std::vector<Feature>& features,
                                      const std::vector<cv::Mat>& pyramid) {
  std::vector<int> started;
  for (const Feature& f : features) {
    if (static_cast<int>(points_.size()) >= options_.max) break;
    if (holds(f.id) || refused_.count(f.id)) continue;
    const StateBlock block =
        inverseDepthFeature(state, camera_, pixelAtFrameTime(camera_, readout_, state.w(), Vec2(f.uv.x, f.uv.y)),
                            options_.pixel_sigma, options_.rho, options_.rho_sigma);
    state.appendToTail(block.value, block.P_block, block.P_block_rest);
    tail.push(kPoint, f.id, static_cast<int>(block.value.size()));
    points_[f.id] = {frame_, f.uv, rotationFromQuat(state.q())};
    first_images_.emplace(frame_, pyramid);
    started.push_back(f.id);
  }
  // First images no point started in any more.
  for (auto it = first_images_.begin(); it != first_images_.end();) {
    const bool used = std::any_of(points_.begin(), points_.end(), [&](const auto& p) { return p.second.first == it->first; });
    it = used ? std::next(it) : first_images_.erase(it);
  }
  ++frame_;
  return started;
}

void TrackedPoints::forget(const std::vector<int>& ended) {
  for (const int id : ended) refused_.erase(id);
}

void TrackedPoints::clear() {
  points_.clear();
  first_images_.clear();
  refused_.clear();
}

}  // namespace slamcmp
