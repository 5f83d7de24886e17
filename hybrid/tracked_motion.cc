#include "hybrid/tracked_motion.h"

#include <algorithm>
#include <cmath>

#include <opencv2/video/tracking.hpp>

#include "core/error.h"
#include "ekf/ekf_update.h"
#include "ekf/inverse_depth.h"
#include "ekf/joint_compatibility.h"

namespace slamcmp {

void TrackedMotionOptions::check() const {
  if (window < 2 || window > 30) throw OptionError("window", "must be in [2, 30]");
  if (min_track_length < 2 || min_track_length > window)
    throw OptionError("min_track_length", "must be in [2, window]");
  if (!(pixel_sigma > 0)) throw OptionError("pixel_sigma", "must be positive");
  if (!(gate_probability > 0 && gate_probability < 1)) throw OptionError("gate_probability", "must be in (0, 1)");
  if (!(min_parallax_deg >= 0 && min_parallax_deg < 90)) throw OptionError("min_parallax_deg", "must be in [0, 90)");
  if (!(max_triangulation_px > 0)) throw OptionError("max_triangulation_px", "must be positive");
  if (points < 0 || points > tracks.max_features) throw OptionError("points", "must be in [0, tracks.max_features]");
  if (!(point_pixel_sigma > 0)) throw OptionError("point_pixel_sigma", "must be positive");
  if (!(point_rho >= 0 && point_rho < 1e3)) throw OptionError("point_rho", "must be in [0, 1000)");
  if (!(point_rho_sigma > 0 && point_rho_sigma < 1e3)) throw OptionError("point_rho_sigma", "must be in (0, 1000)");
  if (!(point_max_anchor_px > 0)) throw OptionError("point_max_anchor_px", "must be positive");
  if (!(point_max_deformation_px > 0)) throw OptionError("point_max_deformation_px", "must be positive");
  tracks.check();
}

TrackedMotion::TrackedMotion(const CameraModel& camera, const TrackedMotionOptions& options, cv::Size lk_window,
                             int lk_levels)
    : camera_(camera), options_(options), lk_window_(lk_window), lk_levels_(lk_levels), tracker_(options.tracks) {}

void TrackedMotion::reset(EkfState& state) {
  if (state.tailSize() > 0) state.remove(state.size() - state.tailSize(), state.tailSize());
  tracker_.clear();
  pyramid_previous_.clear();
  clones_.clear();
  seen_.clear();
  tail_.clear();
  points_.clear();
  refused_.clear();
  anchors_.clear();
}

int TrackedMotion::offsetOf(const EkfState& state, bool point, int id) const {
  int offset = state.size() - state.tailSize();
  for (const TailBlock& b : tail_) {
    if (b.point == point && b.id == id) return offset;
    offset += b.dim;
  }
  return -1;
}

void TrackedMotion::removeBlock(EkfState& state, bool point, int id) {
  const int offset = offsetOf(state, point, id);
  const auto it = std::find_if(tail_.begin(), tail_.end(), [&](const TailBlock& b) { return b.point == point && b.id == id; });
  state.remove(offset, it->dim);
  tail_.erase(it);
  if (point) points_.erase(id);
}

double TrackedMotion::patchDeformation(const EkfState& state, int offset, const TrackedPoint& point,
                                       double half_diagonal) const {
  // The first view's patch, scaled by the change of the point's distance and turned by the roll
  // since, moves its window's corners by about (|scale - 1| + |roll|) times the half diagonal.
  const Vec6 y = state.x().segment<6>(offset);
  const double scale = (inverseDepthPoint(y) - state.r()).norm() * y(5);  // now / first distance
  const Mat3 R_first_now = point.R_world_first.transpose() * rotationFromQuat(state.q());
  const double roll = std::atan2(R_first_now(1, 0), R_first_now(0, 0));  // about the optical axis
  return (std::abs(scale - 1) + std::abs(roll)) * half_diagonal;
}

void TrackedMotion::measurePoints(EkfState& state, const std::vector<cv::Mat>& pyramid) {
  // Each point from its first view, started where its track is now, a batch per first view.
  std::unordered_map<int, Vec2> found;  // track id -> pixel
  std::map<int, std::vector<int>> by_anchor;
  std::unordered_map<int, cv::Point2f> tracked;
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 20, 0.01);
  const float max2 = static_cast<float>(options_.point_max_anchor_px * options_.point_max_anchor_px);
  const double half_diagonal = 0.5 * std::hypot(lk_window_.width, lk_window_.height);
  for (const Feature& f : tracker_.features()) {
    if (!points_.count(f.id)) continue;
    // Its first view no longer looks like it (TrackedMotionOptions): it starts again.
    const TrackedPoint& point = points_.at(f.id);
    if (patchDeformation(state, offsetOf(state, true, f.id), point, half_diagonal) > options_.point_max_deformation_px) continue;
    tracked.emplace(f.id, f.uv);
    by_anchor[point.anchor].push_back(f.id);
  }
  for (const auto& [anchor, ids] : by_anchor) {
    std::vector<cv::Point2f> from, to;
    for (const int id : ids) {
      from.push_back(points_.at(id).anchor_uv);
      to.push_back(tracked.at(id));
    }
    std::vector<uchar> status;
    std::vector<float> error;
    cv::calcOpticalFlowPyrLK(anchors_.at(anchor), pyramid, from, to, status, error, lk_window_, lk_levels_, criteria,
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    for (size_t k = 0; k < ids.size(); ++k) {
      const cv::Point2f d = to[k] - tracked.at(ids[k]);
      if (status[k] && d.dot(d) <= max2) found.emplace(ids[k], Vec2(to[k].x, to[k].y));
    }
  }
  std::vector<int> drop;
  std::vector<PointObservation> observations;
  const double gate = chiSquaredQuantile(2, options_.gate_probability);
  for (const auto& [id, point] : points_) {
    const auto it = found.find(id);
    PointObservation o;
    o.offset = offsetOf(state, true, id);
    if (it == found.end() ||  // its track ended, or its first view no longer matches (it starts again)
        !predictInverseDepthMeasurement(camera_, state.r(), state.q(), state.x().segment<6>(o.offset), &o.h)) {
      drop.push_back(id);
      continue;
    }
    o.z = it->second;
    const Vec2 nu = o.z - o.h.uv_distorted;
    const Mat2 S = pointInnovationCovariance(state, o.h, o.offset, options_.point_pixel_sigma);
    if (nu.dot(S.ldlt().solve(nu)) > gate) {
      drop.push_back(id);  // a track gone astray, or a point that moves (an occluding edge): not restarted
      refused_.insert(id);
      continue;
    }
    observations.push_back(o);
  }
  if (!observations.empty()) batchUpdate(state, observations, options_.point_pixel_sigma);
  for (const int id : drop) removeBlock(state, true, id);
}

void TrackedMotion::startPoints(EkfState& state, const std::vector<cv::Mat>& pyramid) {
  for (const Feature& f : tracker_.features()) {
    if (static_cast<int>(points_.size()) >= options_.points) break;
    if (points_.count(f.id) || refused_.count(f.id)) continue;
    const StateBlock block = inverseDepthFeature(state, camera_, Vec2(f.uv.x, f.uv.y), options_.point_pixel_sigma,
                                                 options_.point_rho, options_.point_rho_sigma);
    state.appendToTail(block.value, block.P_block, block.P_block_rest);
    tail_.push_back({true, f.id, static_cast<int>(block.value.size())});
    points_[f.id] = {frame_, f.uv, rotationFromQuat(state.q())};
    anchors_.emplace(frame_, pyramid);
    seen_.erase(f.id);  // its observations are the point's from now on
  }
  // First views no point is anchored in any more.
  for (auto it = anchors_.begin(); it != anchors_.end();) {
    const bool used = std::any_of(points_.begin(), points_.end(), [&](const auto& p) { return p.second.anchor == it->first; });
    it = used ? std::next(it) : anchors_.erase(it);
  }
}

MsckfResult TrackedMotion::update(EkfState& state, const cv::Mat& grey, const std::vector<cv::Mat>& pyramid,
                                  bool anchored) {
  MsckfResult result;
  if (!options_.enabled) return result;
  int tail_dim = 0;
  for (const TailBlock& b : tail_) tail_dim += b.dim;
  if (state.tailSize() != tail_dim) reset(state);  // the filter restarted
  const bool tracked = !clones_.empty() && !tracker_.features().empty();
  if (tracked) {
    // Where the filter's rotation since the last clone puts each feature (at infinity): a fast
    // turn moves the image beyond the pyramid's reach.
    const int last = cloneOffset(state, clones_.back());
    const Mat3 R_current_last = rotationFromQuat(state.q()).transpose() *
                                rotationFromQuat(state.x().segment<4>(last + 3));
    std::vector<cv::Point2f> predicted;
    for (const Feature& f : tracker_.features()) {
      const Vec3 ray = R_current_last * camera_.undistortPixel(Vec2(f.uv.x, f.uv.y)).homogeneous();
      const Vec2 uv = ray.z() > 0 ? camera_.pixelFromNormalised(camera_.distort(ray.hnormalized())) : Vec2(f.uv.x, f.uv.y);
      predicted.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    }
    tracker_.track(pyramid_previous_, pyramid, lk_window_, lk_levels_, &predicted);
  } else {
    tracker_.clear();
  }
  measurePoints(state, pyramid);
  cloneCameraPose(state);
  clones_.push_back(next_clone_++);
  tail_.push_back({false, clones_.back(), kCloneDim});
  for (const Feature& f : tracker_.features())
    if (!points_.count(f.id)) seen_[f.id].emplace_back(clones_.back(), Vec2(f.uv.x, f.uv.y));

  // The tracks that ended, and those as long as the window (their next frame would lose the
  // oldest clone). A track that goes on starts its next stretch at its last observation: each
  // frame-to-frame step of a track is used once (the shared observation's noise correlates
  // consecutive stretches, as in frame-to-frame odometry).
  std::vector<std::vector<CloneObservation>> tracks;
  const auto use = [&](std::vector<std::pair<int, Vec2>>& seen) {
    if (static_cast<int>(seen.size()) < options_.min_track_length) return;
    std::vector<CloneObservation> track;
    for (const auto& [clone, uv] : seen) track.push_back({cloneOffset(state, clone), uv});
    tracks.push_back(std::move(track));
  };
  for (int id : tracked ? tracker_.ended() : std::vector<int>{}) {  // ended(): since the last track()
    const auto it = seen_.find(id);
    if (it == seen_.end()) continue;
    use(it->second);
    seen_.erase(it);
  }
  for (const Feature& f : tracker_.features()) {
    if (points_.count(f.id)) continue;
    std::vector<std::pair<int, Vec2>>& seen = seen_[f.id];
    if (static_cast<int>(seen.size()) < options_.window) continue;
    use(seen);
    seen.erase(seen.begin(), seen.end() - 1);
  }
  if ((anchored || options_.without_board) && !tracks.empty())
    result = msckfUpdate(state, camera_, tracks, options_.msckf());

  if (static_cast<int>(clones_.size()) >= options_.window) {
    removeBlock(state, false, clones_.front());
    clones_.pop_front();
  }
  const size_t before = tracker_.features().size();
  tracker_.replenish(grey);
  for (size_t k = before; k < tracker_.features().size(); ++k) {
    const Feature& f = tracker_.features()[k];
    seen_[f.id].emplace_back(clones_.back(), Vec2(f.uv.x, f.uv.y));
  }
  startPoints(state, pyramid);
  ++frame_;
  pyramid_previous_ = pyramid;  // shares the images
  return result;
}

}  // namespace slamcmp
