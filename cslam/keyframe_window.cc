#include "cslam/keyframe_window.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/error.h"
#include "core/statistics.h"
#include "geometry/pose_graph.h"
#include "geometry/pose_refinement.h"
#include "geometry/triangulation.h"

namespace slamcmp {

void KeyframeWindowOptions::check() const {
  if (window_keyframes < 2) throw OptionError("window_keyframes", "must be >= 2");
  if (max_fixed_keyframes < 0) throw OptionError("max_fixed_keyframes", "must be >= 0");
  if (max_keyframes < window_keyframes) throw OptionError("max_keyframes", "must be >= window_keyframes");
  if (max_frames_between < 1) throw OptionError("max_frames_between", "must be >= 1");
  if (!(min_tracked_fraction >= 0 && min_tracked_fraction <= 1))
    throw OptionError("min_tracked_fraction", "must be in [0, 1]");
  if (!(min_rotation_deg > 0)) throw OptionError("min_rotation_deg", "must be positive");
  if (!(min_parallax_deg > 0 && min_parallax_deg < 90)) throw OptionError("min_parallax_deg", "must be in (0, 90)");
  if (!(feature_sigma_px > 0)) throw OptionError("feature_sigma_px", "must be positive");
  if (!(board_sigma_px > 0)) throw OptionError("board_sigma_px", "must be positive");
  if (!(max_error_px > 0)) throw OptionError("max_error_px", "must be positive");
  if (!(anchor_board_fraction > 0 && anchor_board_fraction <= 1))
    throw OptionError("anchor_board_fraction", "must be in (0, 1]");
  if (board_point_sigma_m < 0) throw OptionError("board_point_sigma_m", "must be >= 0");
}

namespace {

// At most this many of a gap's newest keyframes are refined whole when the board returns
// (refine_gap; the reduced camera system is dense, 6 unknowns a keyframe); older ones keep the
// pose graph's correction.
constexpr int kMaxGapKeyframesRefined = 64;
constexpr int kMinPointsToReanchor = 8;  // map points the returning keyframe must see to measure the drift
constexpr int kMinSharedToFix = 5;       // an older keyframe joins the refinement (fixed) when it sees this many
// A feature with too little parallax is placed no nearer and no farther than these (metres).
constexpr double kMinWeakDepth = 0.1;
constexpr double kMaxWeakDepth = 50;

}  // namespace

KeyframeWindow::KeyframeWindow(const KeyframeWindowOptions& options, double focal_px, std::vector<Vec3> corners_world)
    : options_(options), focal_px_(focal_px), corners_world_(std::move(corners_world)) {}

bool KeyframeWindow::anchors(int board_corners) const {
  return static_cast<double>(board_corners) >=
         std::max(1.0, options_.anchor_board_fraction * static_cast<double>(corners_world_.size()));
}

bool KeyframeWindow::wantsKeyframe(int frame_index, const SE3& T_world_camera, const std::vector<int>& tracked_ids,
                                   int board_corners) const {
  if (keyframes_.empty()) return true;
  const Keyframe& last = keyframes_.back();
  Keyframe probe;
  probe.board_ids.resize(board_corners);
  if (anchors(probe) && !anchors(last)) return true;  // the board is back: re-anchor at once
  if (frame_index - last.frame_index >= options_.max_frames_between) return true;
  if (rotationAngle(last.T_world_camera.R().transpose() * T_world_camera.R()) * 180 / M_PI >= options_.min_rotation_deg)
    return true;
  int points = 0, still = 0;
  std::vector<int> sorted = tracked_ids;
  std::sort(sorted.begin(), sorted.end());
  for (const auto& [id, xy] : last.features) {
    const auto it = tracks_.find(id);
    if (it == tracks_.end() || !it->second.valid) continue;
    ++points;
    still += std::binary_search(sorted.begin(), sorted.end(), id);
  }
  return points > 0 && still < options_.min_tracked_fraction * points;
}

void KeyframeWindow::triangulate(int id, Track& track) const {
  const double min_cos = std::cos(options_.min_parallax_deg * M_PI / 180);
  RayLeastSquares ls;
  Vec3 first = Vec3::Zero();
  double smallest_cos = 1;
  for (int serial : track.keyframes) {
    const Keyframe& kf = keyframe(serial);
    const Ray ray = rayFromObservation(kf.T_world_camera, kf.features.at(id));
    if (ls.size() == 0) first = ray.direction;
    smallest_cos = std::min(smallest_cos, first.dot(ray.direction));
    ls.add(ray);
  }
  const auto p = ls.solve();
  const auto consistent = [&](const Vec3& point) {
    for (int serial : track.keyframes) {
      const Keyframe& kf = keyframe(serial);
      const Vec3 p_camera = kf.T_world_camera.inverse() * point;
      if (p_camera.z() <= 0) return false;
      if (focal_px_ * (p_camera.head<2>() / p_camera.z() - kf.features.at(id)).norm() > options_.max_error_px)
        return false;
    }
    return true;
  };
  if (smallest_cos <= min_cos) {
    // Enough parallax: a map point (the rays' least-squares point, or the refined one it had).
    if (p && consistent(*p)) {
      track.p_world = *p;
      track.initialised = track.valid = true;
    } else if (track.initialised && consistent(track.p_world)) {
      track.valid = true;
    }
    return;
  }
  if (track.initialised) return;
  // Too little parallax to place it: the refinement still uses its direction (it holds the
  // rotation of a fast turn, where the new features are all distant or barely moved), from a
  // depth the rays allow or the typical depth of the map when they allow none.
  const Keyframe& newest = keyframe(track.keyframes.back());
  const Vec3 p_camera_ls = p ? newest.T_world_camera.inverse() * *p : Vec3(0, 0, -1);
  if (p && p_camera_ls.z() > kMinWeakDepth && p_camera_ls.z() < kMaxWeakDepth && consistent(*p)) {
    track.p_world = *p;
  } else {
    track.p_world = newest.T_world_camera * (typical_depth_ * newest.features.at(id).homogeneous());
    if (!consistent(track.p_world)) return;
  }
  track.initialised = true;
}

KeyframeWindow::Added KeyframeWindow::add(Keyframe kf) {
  keyframes_.push_back(std::move(kf));
  const int serial = newestSerial();
  for (const auto& [id, xy] : keyframes_.back().features) tracks_[id].keyframes.push_back(serial);
  for (const auto& [id, xy] : keyframes_.back().features) {
    Track& track = tracks_[id];
    if (!track.valid && track.keyframes.size() >= 2) triangulate(id, track);
  }
  Added added;
  const std::optional<int> gap =
      options_.reanchor && anchors(keyframes_.back()) ? reanchorGap() : std::optional<int>();
  added.reanchored = gap.has_value();
  const int newest = newestSerial();
  const int window_start = std::max(first_serial_, newest - options_.window_keyframes + 1);
  // refine_gap: a re-anchored gap refined whole, its ends held by the board (the pose graph
  // spreads the drift evenly along the gap, which is not where the odometry made it).
  refine(gap && options_.refine_gap ? std::min(window_start, std::max(*gap, newest - kMaxGapKeyframesRefined + 1))
                                    : window_start);
  added.T_world_camera = keyframes_.back().T_world_camera;
  while (numKeyframes() > options_.max_keyframes) dropOldest();
  return added;
}

void KeyframeWindow::dropOldest() {
  for (const auto& [id, xy] : keyframes_.front().features) {
    const auto it = tracks_.find(id);
    if (it == tracks_.end()) continue;
    auto& serials = it->second.keyframes;
    serials.erase(std::remove(serials.begin(), serials.end(), first_serial_), serials.end());
    if (serials.empty()) tracks_.erase(it);
  }
  keyframes_.pop_front();
  ++first_serial_;
}

std::vector<int> KeyframeWindow::pointsSeenFrom(int first_free) const {
  std::vector<int> point_ids;
  for (int s = first_free; s <= newestSerial(); ++s)
    for (const auto& [id, xy] : keyframe(s).features)
      if (tracks_.at(id).initialised) point_ids.push_back(id);
  std::sort(point_ids.begin(), point_ids.end());
  point_ids.erase(std::unique(point_ids.begin(), point_ids.end()), point_ids.end());
  return point_ids;
}

std::vector<int> KeyframeWindow::olderKeyframesToFix(const std::vector<int>& point_ids, int first_free) const {
  std::map<int, int> shared;  // older keyframe serial -> points of the window it sees
  for (int id : point_ids)
    for (int o : tracks_.at(id).keyframes)
      if (o < first_free) ++shared[o];
  // Those sharing most points join (newest first on ties).
  std::vector<std::pair<int, int>> candidates;  // (shared points, serial)
  for (const auto& [s, n] : shared)
    if (n >= kMinSharedToFix) candidates.emplace_back(n, s);
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second > b.second;
  });
  if (static_cast<int>(candidates.size()) > options_.max_fixed_keyframes) candidates.resize(options_.max_fixed_keyframes);
  std::vector<int> serials;
  for (const auto& [n, s] : candidates) serials.push_back(s);
  return serials;
}

void KeyframeWindow::refine(int first_free) {
  const int newest = newestSerial();
  bool board = false;
  for (int s = first_free; s <= newest; ++s) board = board || keyframe(s).hasBoard();
  const std::vector<int> point_ids = pointsSeenFrom(first_free);
  const std::vector<int> fixed_older = olderKeyframesToFix(point_ids, first_free);
  // Gauge: board corners in the window fix it; else at least two fixed keyframes (position,
  // orientation and scale), the window's oldest if there are too few older ones.
  int extra_fixed = board ? 0 : std::max(0, 2 - static_cast<int>(fixed_older.size()));

  BundleAdjustment ba;
  std::map<int, int> camera_of;  // keyframe serial -> BA camera
  for (int s : fixed_older) camera_of[s] = ba.addCamera(keyframe(s).T_world_camera.inverse(), true);
  for (int s = first_free; s <= newest; ++s)
    camera_of[s] = ba.addCamera(keyframe(s).T_world_camera.inverse(), s - first_free < extra_fixed);
  struct Obs {
    int serial, id;
  };
  std::vector<Obs> feature_obs;  // BA observation k (feature observations come first)
  std::vector<std::pair<int, int>> point_of;  // (feature id, BA point)
  for (int id : point_ids) {
    const Track& track = tracks_.at(id);
    int seen = 0;
    for (int s : track.keyframes) seen += camera_of.count(s);
    if (seen < 2) continue;
    int p;
    if (track.valid) {
      p = ba.addPoint(track.p_world, false);
    } else {
      // Too little parallax to place it: refined in inverse depth along its first keyframe's ray.
      const Keyframe& anchor = keyframe(track.keyframes.front());
      const Vec3 origin = anchor.T_world_camera.t();
      const Vec3 direction = (anchor.T_world_camera.R() * anchor.features.at(id).homogeneous()).normalized();
      const double depth = (track.p_world - origin).dot(direction);
      p = ba.addPointOnRay(origin, direction, 1.0 / std::max(depth, kMinWeakDepth));
    }
    point_of.emplace_back(id, p);
    // Without the board in the window, a point it once anchored keeps what it said (the board
    // keyframes have left; their information would otherwise leave with them).
    if (!board && track.board_prior && options_.board_point_sigma_m > 0)
      ba.addPointPrior(p, *track.board_prior, options_.board_point_sigma_m);
    for (int s : track.keyframes) {
      const auto c = camera_of.find(s);
      if (c == camera_of.end()) continue;
      ba.addObservation(c->second, p, keyframe(s).features.at(id), options_.feature_sigma_px);
      feature_obs.push_back({s, id});
    }
  }
  if (board) {
    std::vector<int> corner_point(corners_world_.size(), -1);
    for (int s = first_free; s <= newest; ++s) {
      const Keyframe& kf = keyframe(s);
      for (size_t k = 0; k < kf.board_ids.size(); ++k) {
        int& p = corner_point[kf.board_ids[k]];
        if (p < 0) p = ba.addPoint(corners_world_[kf.board_ids[k]], true);
        ba.addObservation(camera_of.at(s), p, kf.board_xy[k], options_.board_sigma_px);
      }
    }
  }
  if (point_of.empty() && !board) return;
  ba.solve(options_.bundle_adjustment, focal_px_);

  for (int s = first_free; s <= newest; ++s) keyframe(s).T_world_camera = ba.camera(camera_of.at(s)).inverse();
  for (const auto& [id, p] : point_of) {
    Track& track = tracks_.at(id);
    track.p_world = ba.point(p);
    if (board && track.valid) track.board_prior = track.p_world;
  }
  updateTypicalDepth();
  // Observations the refined map does not explain are dropped; a point left with fewer than two
  // is no longer used.
  for (size_t k = 0; k < feature_obs.size(); ++k) {
    if (ba.errorPx(static_cast<int>(k), focal_px_) <= options_.max_error_px) continue;
    const auto [s, id] = feature_obs[k];
    keyframe(s).features.erase(id);
    Track& track = tracks_.at(id);
    track.keyframes.erase(std::remove(track.keyframes.begin(), track.keyframes.end(), s), track.keyframes.end());
    if (track.keyframes.size() < 2) track.valid = track.initialised = false;
  }
}

void KeyframeWindow::updateTypicalDepth() {
  std::vector<double> depths;
  const SE3 T_newest_world = keyframes_.back().T_world_camera.inverse();
  for (const auto& [id, xy] : keyframes_.back().features) {
    const Track& track = tracks_.at(id);
    if (track.valid) depths.push_back((T_newest_world * track.p_world).z());
  }
  if (depths.size() >= 5) typical_depth_ = std::clamp(median(depths), kMinWeakDepth, kMaxWeakDepth);
}

std::optional<int> KeyframeWindow::reanchorGap() {
  const int newest = newestSerial();
  int last_board = newest - 1;
  while (last_board >= first_serial_ && !anchors(keyframe(last_board))) --last_board;
  if (last_board < first_serial_ || last_board == newest - 1) return std::nullopt;  // no gap, or its start is gone
  // Where the map alone (as it drifted over the gap) puts the returning keyframe: the points the
  // gap's keyframes saw (not those found again from before the gap).
  const Keyframe& back = keyframes_.back();
  std::vector<Vec3> p_world;
  std::vector<Vec2> xy;
  for (const auto& [id, obs] : back.features) {
    const Track& track = tracks_.at(id);
    const bool seen_in_gap = std::any_of(track.keyframes.begin(), track.keyframes.end(),
                                         [&](int s) { return s > last_board && s < newest; });
    if (track.valid && seen_in_gap) p_world.push_back(track.p_world), xy.push_back(obs);
  }
  if (static_cast<int>(p_world.size()) < kMinPointsToReanchor) return std::nullopt;
  const SE3 T_world_camera_by_map =
      refinePose(back.T_world_camera.inverse(), p_world, xy, focal_px_, PoseRefinementOptions{10, 2.0})
          .T_camera_world.inverse();
  // The chain last board keyframe -> gap keyframes -> returning keyframe, held at both ends, the
  // relative motions as the odometry measured them.
  std::vector<SE3> nodes;
  std::vector<char> fixed;
  std::vector<PoseGraphEdge> edges;
  for (int s = last_board; s <= newest; ++s) {
    nodes.push_back(keyframe(s).T_world_camera);
    if (s == newest) nodes.back() = keyframe(s).T_world_camera_by_board;  // the board's word on where it is
    fixed.push_back(s == last_board || s == newest);
    if (s == last_board) continue;
    PoseGraphEdge e;
    e.from = static_cast<int>(nodes.size()) - 2;
    e.to = e.from + 1;
    e.T_from_to = nodes[e.from].inverse() * (s == newest ? T_world_camera_by_map : nodes[e.to]);
    edges.push_back(e);
  }
  const std::vector<SE3> corrected = optimisePoseGraph(nodes, fixed, edges);
  keyframe(newest).T_world_camera = keyframe(newest).T_world_camera_by_board;
  // Each gap keyframe's correction (world frame); a point moves with the newest gap keyframe
  // that saw it.
  std::unordered_map<int, SE3> correction;
  for (int s = last_board + 1; s < newest; ++s) {
    correction[s] = corrected[s - last_board] * keyframe(s).T_world_camera.inverse();
    keyframe(s).T_world_camera = corrected[s - last_board];
  }
  for (auto& [id, track] : tracks_) {
    if (!track.initialised) continue;
    for (auto it = track.keyframes.rbegin(); it != track.keyframes.rend(); ++it) {
      const auto c = correction.find(*it);
      if (c == correction.end()) continue;
      track.p_world = c->second * track.p_world;
      break;
    }
  }
  return last_board + 1;
}

std::vector<KeyframePose> KeyframeWindow::keyframePoses() const {
  std::vector<KeyframePose> out;
  for (const Keyframe& kf : keyframes_) out.push_back({kf.frame_index, kf.T_world_camera});
  return out;
}

std::optional<Vec3> KeyframeWindow::position(int id, bool barely_triangulated) const {
  const auto it = tracks_.find(id);
  if (it == tracks_.end() || !(barely_triangulated ? it->second.initialised : it->second.valid)) return std::nullopt;
  return it->second.p_world;
}

void KeyframeWindow::setPatch(int id, cv::Mat patch) {
  const auto it = tracks_.find(id);
  if (it == tracks_.end()) return;
  it->second.patch = std::move(patch);
  it->second.patch_from = keyframes_.back().T_world_camera.t();
}

std::vector<MapPointCandidate> KeyframeWindow::untrackedPoints(const std::vector<int>& tracked_ids) const {
  std::vector<MapPointCandidate> out;
  for (const auto& [id, track] : tracks_) {
    if (!track.valid || track.patch.empty() || std::binary_search(tracked_ids.begin(), tracked_ids.end(), id)) continue;
    out.push_back({id, track.p_world, &track.patch, track.patch_from, static_cast<int>(track.keyframes.size())});
  }
  return out;
}

std::vector<MapPoint> KeyframeWindow::points() const {
  std::vector<MapPoint> out;
  for (const auto& [id, track] : tracks_)
    if (track.valid) out.push_back({id, track.p_world, static_cast<int>(track.keyframes.size()), -1});
  std::sort(out.begin(), out.end(), [](const MapPoint& a, const MapPoint& b) { return a.id < b.id; });
  return out;
}

}  // namespace slamcmp
