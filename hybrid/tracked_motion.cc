#include "hybrid/tracked_motion.h"

#include "core/error.h"
#include "ekf/rolling_shutter.h"

namespace slamcmp {

void TrackedMotionOptions::check() const {
  if (window < 2 || window > 30) throw OptionError("window", "must be in [2, 30]");
  if (min_track_length < 2 || min_track_length > window)
    throw OptionError("min_track_length", "must be in [2, window]");
  if (!(pixel_sigma > 0)) throw OptionError("pixel_sigma", "must be positive");
  if (!(gate_probability > 0 && gate_probability < 1)) throw OptionError("gate_probability", "must be in (0, 1)");
  if (!(snooping_probability >= 0 && snooping_probability < 1))
    throw OptionError("snooping_probability", "must be in [0, 1) (0: off)");
  if (!(min_parallax_deg >= 0 && min_parallax_deg < 90)) throw OptionError("min_parallax_deg", "must be in [0, 90)");
  if (!(max_triangulation_px > 0)) throw OptionError("max_triangulation_px", "must be positive");
  if (points.max > tracks.max_features) throw OptionError("points.max", "must be at most tracks.max_features");
}

namespace {
constexpr TailLayout::Kind kClone = TailLayout::Kind::kClone;
}  // namespace

TrackedMotion::TrackedMotion(const CameraModel& camera, const TrackedMotionOptions& options, cv::Size lk_window,
                             int lk_levels, double rolling_shutter_readout)
    : camera_(camera),
      options_(options),
      lk_window_(lk_window),
      lk_levels_(lk_levels),
      readout_(rolling_shutter_readout),
      tracker_(options.tracks),
      points_(camera, options.points, options.gate_probability, lk_window, lk_levels, rolling_shutter_readout) {}

Vec2 TrackedMotion::atFrameTime(const EkfState& state, const Feature& f) const {
  return pixelAtFrameTime(camera_, readout_, state.w(), Vec2(f.uv.x, f.uv.y));
}

void TrackedMotion::reset(EkfState& state) {
  tail_.clear(state);
  tracker_.clear();
  pyramid_previous_.clear();
  clones_.clear();
  seen_.clear();
  points_.clear();
}

int TrackedMotion::update(EkfState& state, const cv::Mat& grey, const std::vector<cv::Mat>& pyramid,
                                  bool anchored) {
  if (!options_.enabled) return 0;
  if (!tail_.matches(state)) reset(state);  // the filter restarted
  const bool tracked = !clones_.empty() && !tracker_.features().empty();
  if (tracked) {
    // Where the filter's rotation since the last clone puts each feature (at infinity): a fast
    // turn moves the image beyond the pyramid's reach.
    const int last = tail_.offset(state, kClone, clones_.back());
    const Mat3 R_current_last = rotationFromQuat(state.q()).transpose() *
                                rotationFromQuat(state.x().segment<4>(last + 3));
    std::vector<cv::Point2f> predicted;
    for (const Feature& f : tracker_.features()) {
      const Vec3 ray = R_current_last * camera_.undistortPixel(Vec2(f.uv.x, f.uv.y)).homogeneous();
      const Vec2 uv = ray.z() > 0 ? camera_.pixelFromNormalised(camera_.distort(ray.hnormalized())) : Vec2(f.uv.x, f.uv.y);
      predicted.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    }
    tracker_.track(pyramid_previous_, pyramid, lk_window_, lk_levels_, &predicted);
    points_.forget(tracker_.ended());
  } else {
    tracker_.clear();
  }
  const int points_measured = points_.measure(state, tail_, tracker_.features(), pyramid);
  for (const int clone : clones_)  // the points' update moved them through their correlations
    state.renormaliseQuaternion(tail_.offset(state, kClone, clone) + 3);
  cloneCameraPose(state);
  clones_.push_back(next_clone_++);
  tail_.push(kClone, clones_.back(), kCloneDim);
  for (const Feature& f : tracker_.features())
    if (!points_.holds(f.id)) seen_[f.id].emplace_back(clones_.back(), atFrameTime(state, f));

  // The tracks that ended, and those as long as the window (their next frame would lose the
  // oldest clone). A track that goes on starts its next stretch at its last observation: each
  // frame-to-frame step of a track is used once (the shared observation's noise correlates
  // consecutive stretches, as in frame-to-frame odometry).
  std::vector<std::vector<CloneObservation>> tracks;
  const auto use = [&](std::vector<std::pair<int, Vec2>>& seen) {
    if (static_cast<int>(seen.size()) < options_.min_track_length) return;
    std::vector<CloneObservation> track;
    for (const auto& [clone, uv] : seen) track.push_back({tail_.offset(state, kClone, clone), uv});
    tracks.push_back(std::move(track));
  };
  for (int id : tracked ? tracker_.ended() : std::vector<int>{}) {  // ended(): since the last track()
    const auto it = seen_.find(id);
    if (it == seen_.end()) continue;
    use(it->second);
    seen_.erase(it);
  }
  for (const Feature& f : tracker_.features()) {
    if (points_.holds(f.id)) continue;
    std::vector<std::pair<int, Vec2>>& seen = seen_[f.id];
    if (static_cast<int>(seen.size()) < options_.window) continue;
    use(seen);
    seen.erase(seen.begin(), seen.end() - 1);
  }
  if ((anchored || options_.without_board) && !tracks.empty())
    msckfUpdate(state, camera_, tracks, options_.msckf());

  if (static_cast<int>(clones_.size()) >= options_.window) {
    tail_.remove(state, kClone, clones_.front());
    clones_.pop_front();
  }
  const size_t before = tracker_.features().size();
  tracker_.replenish(grey);
  for (size_t k = before; k < tracker_.features().size(); ++k) {
    const Feature& f = tracker_.features()[k];
    seen_[f.id].emplace_back(clones_.back(), atFrameTime(state, f));
  }
  for (const int id : points_.start(state, tail_, tracker_.features(), pyramid))
    seen_.erase(id);  // its observations are the point's from now on
  pyramid_previous_ = pyramid;  // shares the images
  return points_measured;
}

}  // namespace slamcmp
