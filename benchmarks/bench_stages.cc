// Cost of each stage of the CSLAM back-end, called as cslam_tracker.cc calls it, with its default
// options, on real-looking frames: the tv1 preset (640x480, rendered once into a temporary folder
// and shared with bench_tracking), board_leaves for frames without the board and the board's
// return, board_partial for a board partly out of the image, and the first 60 frames of the
// shared VAMR data (752x480 JPEG; those benchmarks are skipped when it is absent). The n-view
// refinement's estimators (bundle adjustment of a window, the gap's pose graph) run on synthetic
// problems of the window's size. The EKF's stages are in bench_monoslam; whole frames in
// bench_tracking.
//
//   build/benchmarks/bench_stages [--benchmark_filter=tv1]
//
// One core (cv::setNumThreads(1)), image decoding excluded except in the Decode benchmarks.
#include <benchmark/benchmark.h>

#include <functional>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include <opencv2/core/utility.hpp>
#include <opencv2/video/tracking.hpp>

#include "benchmarks/bench_frames.h"
#include "core/chessboard.h"
#include "cslam/board_image_motion.h"
#include "cslam/map_point_search.h"
#include "eval/metrics/board_visibility.h"
#include "geometry/bundle_adjustment.h"
#include "geometry/pose_graph.h"
#include "tracking/board_corner_tracker.h"
#include "tracking/board_presence.h"
#include "cslam/cslam_tracker.h"
#include "geometry/essential_eight_point.h"
#include "cslam/feature_map.h"
#include "tracking/feature_tracker.h"
#include "geometry/homography_pose.h"
#include "geometry/two_view_motion.h"

namespace slamcmp {
namespace {

constexpr int kVamrFrames = 60;
constexpr int kBoardLeavesFrames = 200;  // the board is out of view from about frame 95 to 165, back by 175
constexpr int kBoardPartialFrames = 60;  // up to half the board out of the image from about frame 14
constexpr int kPyramidFrames = 20;       // consecutive frames whose pyramids are kept in memory
constexpr int kMaxBoardFrames = 20;      // board frames whose corners are detected up front
constexpr int kTwoViewGap = 5;           // frames between the two views of the eight-point benchmark

// A data set's frames with what the stages need precomputed once.
struct StageData {
  const BenchSequence* b = nullptr;
  CameraModel camera;
  ChessboardTarget target;
  std::vector<int> board_visible;  // frames whose whole board projects into the image (ground truth)
  std::vector<int> board_absent;   // frames where no corner of the board does
  std::vector<int> board_partial;  // frames where half the corners or more do, not all
  std::vector<SE3> T_world_camera;  // the ground truth of every frame (identity where none)
  std::vector<int> detected;       // frames (among board_visible) where the detector found the board
  std::vector<std::vector<cv::Point2f>> corners;  // their corners, distorted pixels
  std::vector<std::vector<Vec2>> corners_normalised;  // undistorted normalised
  std::vector<std::vector<cv::Mat>> pyramids;  // the first kPyramidFrames frames
  // Features tracked from frame k to frame k + kTwoViewGap: undistorted normalised coordinates.
  std::vector<std::pair<std::vector<Vec2>, std::vector<Vec2>>> correspondences;
};

const CslamOptions& cslamOptions() {
  static const CslamOptions options;
  return options;
}

cv::Size lkWindow() { return cv::Size(cslamOptions().lk_window_px, cslamOptions().lk_window_px); }

void classifyByGroundTruth(StageData* d) {
  const Sequence& seq = d->b->seq;
  if (!seq.groundtruth) return;
  std::map<double, SE3> T_world_camera;
  for (const auto& pose : *seq.groundtruth) T_world_camera[pose.timestamp] = pose.T_world_camera;
  const std::vector<Vec3> corners = d->target.cornersWorld();
  d->T_world_camera.assign(d->b->frames.size(), SE3());
  for (int i = 0; i < static_cast<int>(d->b->frames.size()); ++i) {
    const auto it = T_world_camera.lower_bound(d->b->frames[i].timestamp - 1e-6);
    if (it == T_world_camera.end() || it->first > d->b->frames[i].timestamp + 1e-6) continue;
    d->T_world_camera[i] = it->second;
    const int in_view = boardCornersInView(d->camera, corners, it->second, 10.0);
    if (in_view == static_cast<int>(corners.size())) d->board_visible.push_back(i);
    if (in_view == 0) d->board_absent.push_back(i);
    if (2 * in_view >= static_cast<int>(corners.size()) && in_view < static_cast<int>(corners.size()))
      d->board_partial.push_back(i);
  }
}

std::unique_ptr<StageData> prepare(const BenchSequence* b) {
  cv::setNumThreads(1);
  auto d = std::make_unique<StageData>();
  d->b = b;
  d->camera = *b->seq.camera;
  d->target = *b->seq.target;
  classifyByGroundTruth(d.get());
  for (int i : d->board_visible) {
    if (static_cast<int>(d->detected.size()) == kMaxBoardFrames) break;
    std::vector<cv::Point2f> uv;
    if (!detectChessboard(b->frames[i].grey, d->target, &uv)) continue;
    std::vector<Vec2> xy;
    for (const auto& c : uv) xy.push_back(d->camera.undistortPixel(Vec2(c.x, c.y)));
    d->detected.push_back(i);
    d->corners.push_back(uv);
    d->corners_normalised.push_back(xy);
  }
  const int n_pyramids = std::min<int>(kPyramidFrames, static_cast<int>(b->frames.size()));
  d->pyramids.resize(n_pyramids);
  for (int i = 0; i < n_pyramids; ++i)
    cv::buildOpticalFlowPyramid(b->frames[i].grey, d->pyramids[i], lkWindow(), cslamOptions().lk_levels);
  // Feature tracks over the kept frames, as the back-end tracks them (no replenishing in between,
  // so a feature's two views are the same physical point).
  for (int k = 0; k + kTwoViewGap < n_pyramids; k += kTwoViewGap) {
    FeatureTracker tracker(cslamOptions().features);
    tracker.replenish(b->frames[k].grey);
    std::map<int, Vec2> start;
    for (const auto& f : tracker.features()) start[f.id] = d->camera.undistortPixel(Vec2(f.uv.x, f.uv.y));
    for (int i = k + 1; i <= k + kTwoViewGap; ++i)
      tracker.track(d->pyramids[i - 1], d->pyramids[i], lkWindow(), cslamOptions().lk_levels);
    std::pair<std::vector<Vec2>, std::vector<Vec2>> pair;
    for (const auto& f : tracker.features()) {
      pair.first.push_back(start.at(f.id));
      pair.second.push_back(d->camera.undistortPixel(Vec2(f.uv.x, f.uv.y)));
    }
    d->correspondences.push_back(std::move(pair));
  }
  return d;
}

// "tv1", "board_leaves", "board_partial" or "vamr"; nullptr when the data is absent.
const StageData* stageData(const std::string& set) {
  static std::map<std::string, std::unique_ptr<StageData>> cache;
  auto it = cache.find(set);
  if (it != cache.end()) return it->second.get();
  const BenchSequence* b = set == "vamr"            ? sharedSequence("vamr_checkerboard", kVamrFrames)
                           : set == "board_leaves"  ? &renderedSequence("board_leaves", kBoardLeavesFrames)
                           : set == "board_partial" ? &renderedSequence("board_partial", kBoardPartialFrames)
                                                    : &renderedSequence(set, 120);
  return (cache[set] = b ? prepare(b) : nullptr).get();
}

// The data set, or nullptr after skipping the benchmark with the reason.
const StageData* dataOrSkip(benchmark::State& state, const std::string& set, bool need_board = true) {
  const StageData* d = stageData(set);
  if (!d) {
    state.SkipWithError(("../shared/datasets/vamr_checkerboard is absent: " + set + " skipped").c_str());
    return nullptr;
  }
  if (need_board && d->detected.empty()) {
    state.SkipWithError(("no frame of " + set + " with the board detected").c_str());
    return nullptr;
  }
  return d;
}

void BM_ChessboardDetect(benchmark::State& state, const std::string& set, bool board_present) {
  const StageData* d = dataOrSkip(state, set, false);
  if (!d) return;
  const std::vector<int>& frames = board_present ? d->board_visible : d->board_absent;
  if (frames.empty()) {
    state.SkipWithError("no frame of this kind in the data set");
    return;
  }
  size_t i = 0;
  int64_t found = 0;
  std::vector<cv::Point2f> uv;
  for (auto _ : state) {
    found += detectChessboard(d->b->frames[frames[i]].grey, d->target, &uv);
    i = (i + 1) % frames.size();
  }
  state.counters["found"] = benchmark::Counter(static_cast<double>(found), benchmark::Counter::kAvgIterations);
}

// One view's corners refined (core/subpixel_corner.h: method gradient or opencv).
// method "gradient_lens": gradient, its edges taken straight through the camera's lens.
void BM_CornerRefinement(benchmark::State& state, const std::string& set, const std::string& method) {
  const StageData* d = dataOrSkip(state, set);
  if (!d) return;
  ChessboardDetectorOptions options;
  const bool lens = method == "gradient_lens";
  options.subpixel.method = lens ? "gradient" : method;
  size_t i = 0;
  for (auto _ : state) {
    std::vector<cv::Point2f> uv = d->corners[i];
    refineChessboardCorners(d->b->frames[d->detected[i]].grey, d->target, uv, options, lens ? &d->camera : nullptr);
    benchmark::DoNotOptimize(uv.data());
    i = (i + 1) % d->corners.size();
  }
}

// The back-end's per-frame board step (findCorners) with the board in view: last frame's corners
// tracked by LK and confirmed.
void BM_BoardCornerTracking(benchmark::State& state, const std::string& set) {
  const StageData* d = dataOrSkip(state, set);
  if (!d) return;
  const auto fresh = [&] {
    auto t = std::make_unique<BoardCornerTracker>(d->target, cslamOptions().board);
    t->findCorners(d->b->frames[0].grey, {}, d->pyramids[0], lkWindow(), cslamOptions().lk_levels, d->camera, nullptr,
                   true);
    return t;
  };
  std::unique_ptr<BoardCornerTracker> tracker = fresh();
  size_t i = 1;
  int64_t tracked = 0;
  for (auto _ : state) {
    if (i == d->pyramids.size()) {
      state.PauseTiming();
      tracker = fresh();
      i = 1;
      state.ResumeTiming();
    }
    const auto corners = tracker->findCorners(d->b->frames[i].grey, d->pyramids[i - 1], d->pyramids[i], lkWindow(),
                                              cslamOptions().lk_levels, d->camera, nullptr, true);
    tracked += corners.has_value() && tracker->lastFound() == BoardFound::Tracked;
    ++i;
  }
  state.counters["tracked"] = benchmark::Counter(static_cast<double>(tracked), benchmark::Counter::kAvgIterations);
}

// The per-frame board step (BoardCornerTracker::findCorners, no full search) on frames showing no
// corner of the board, where the predicted pose puts the board in the image (the pose of a frame
// that shows all of it: the worst case, the test finding nothing) or out of it (the frame's own
// pose: nothing is searched). The cost of looking for the board in every frame while it is away;
// the full search it replaces as the test is BM_ChessboardDetect/board_leaves/board_absent.
void BM_BoardAbsentTest(benchmark::State& state, bool predicted_in_view) {
  const StageData* d = dataOrSkip(state, "board_leaves", false);
  if (!d) return;
  if (d->board_absent.empty() || d->board_visible.empty()) {
    state.SkipWithError("board_leaves has no frame without the board, or none with it");
    return;
  }
  BoardCornerTracker tracker(d->target, cslamOptions().board);
  size_t i = 0;
  int64_t found = 0;
  for (auto _ : state) {
    const int frame = d->board_absent[i];
    const SE3& T_predicted = predicted_in_view ? d->T_world_camera[d->board_visible.front()] : d->T_world_camera[frame];
    found += tracker.findCorners(d->b->frames[frame].grey, {}, {}, lkWindow(), cslamOptions().lk_levels, d->camera,
                                 &T_predicted, false)
                 .has_value();
    i = (i + 1) % d->board_absent.size();
  }
  state.counters["found"] = benchmark::Counter(static_cast<double>(found), benchmark::Counter::kAvgIterations);
}

// The region around a predicted board searched by the detector (what replaces the whole image's
// search while a prediction exists: findCorners with the search allowed, the whole image never)
// on board_leaves' frames showing no corner of the board, the board predicted where a frame that
// shows all of it has it: the worst case, the region holding the far wall and nothing found. With
// and without the presence test before the detector.
void BM_BoardRegionSearchAbsent(benchmark::State& state, bool presence_test) {
  const StageData* d = dataOrSkip(state, "board_leaves", false);
  if (!d) return;
  if (d->board_absent.empty() || d->board_visible.empty()) {
    state.SkipWithError("board_leaves has no frame without the board, or none with it");
    return;
  }
  BoardCornerTrackerOptions options = cslamOptions().board;
  options.search_interval_when_predicted = 1 << 20;
  options.presence.enabled = presence_test;
  BoardCornerTracker tracker(d->target, options);
  const SE3& T_predicted = d->T_world_camera[d->board_visible.front()];
  // The board seen first, as before any prediction in a run (the presence test learns from it).
  const cv::Mat& seen = d->b->frames[d->board_visible.front()].grey;
  tracker.searchWholeBoard(seen);
  // One frame untimed: the first call after a board was found searches the whole image (220 ms,
  // once), which the region search timed here then never does; timed, it made the figure depend on
  // the iterations run (222 ms at one, 9 ms at 395).
  tracker.findCorners(d->b->frames[d->board_absent.front()].grey, {}, {}, lkWindow(), cslamOptions().lk_levels,
                      d->camera, &T_predicted, true);
  size_t i = 0;
  int64_t found = 0;
  for (auto _ : state) {
    const int frame = d->board_absent[i];
    found += tracker.findCorners(d->b->frames[frame].grey, {}, {}, lkWindow(), cslamOptions().lk_levels, d->camera,
                                 &T_predicted, true)
                 .has_value();
    i = (i + 1) % d->board_absent.size();
  }
  state.counters["found"] = benchmark::Counter(static_cast<double>(found), benchmark::Counter::kAvgIterations);
}

// The presence test (X-junctions counted) on the whole of board_leaves' frames that show no corner
// of the board, learnt from the first frame showing all of it: what a whole-image search costs
// once the board has been seen (it replaces BM_ChessboardDetect/board_leaves/board_absent there).
void BM_BoardPresenceTest(benchmark::State& state) {
  const StageData* d = dataOrSkip(state, "board_leaves", false);
  if (!d) return;
  if (d->board_absent.empty() || d->detected.empty()) {
    state.SkipWithError("board_leaves has no frame without the board, or none with it detected");
    return;
  }
  BoardPresence presence(cslamOptions().board.presence);
  presence.seen(d->b->frames[d->detected.front()].grey, d->corners.front(),
                minCornerSpacing(d->target, d->corners.front()));
  size_t i = 0;
  int64_t may_hold = 0;
  for (auto _ : state) {
    const cv::Mat& grey = d->b->frames[d->board_absent[i]].grey;
    may_hold += presence.mayHoldBoard(grey, cv::Rect(0, 0, grey.cols, grey.rows), d->target.numCorners());
    i = (i + 1) % d->board_absent.size();
  }
  state.counters["may_hold"] = benchmark::Counter(static_cast<double>(may_hold), benchmark::Counter::kAvgIterations);
}

// What the presence test learns from each view of the whole board (the board tracker does it in
// every frame the whole board is found): its corners' response, on tv1's detected boards.
void BM_BoardPresenceSeen(benchmark::State& state) {
  const StageData* d = dataOrSkip(state, "tv1");
  if (!d) return;
  if (d->detected.empty()) {
    state.SkipWithError("no board detected on tv1");
    return;
  }
  BoardPresence presence(cslamOptions().board.presence);
  size_t i = 0;
  for (auto _ : state) {
    presence.seen(d->b->frames[d->detected[i]].grey, d->corners[i], minCornerSpacing(d->target, d->corners[i]));
    i = (i + 1) % d->detected.size();
  }
}

// Carrying the board's predicted view one frame on (BoardImageMotion::advance: the frame-to-frame
// homography of ~150 tracked features by RANSAC), on tv1's tracks.
void BM_BoardImageMotionAdvance(benchmark::State& state) {
  const StageData* d = dataOrSkip(state, "tv1");
  if (!d) return;
  if (d->correspondences.empty()) {
    state.SkipWithError("no feature tracks on tv1");
    return;
  }
  const auto& [from, to] = d->correspondences.front();
  std::unordered_map<int, Vec2> previous, current;
  for (size_t k = 0; k < from.size(); ++k) previous.emplace(static_cast<int>(k), from[k]), current.emplace(static_cast<int>(k), to[k]);
  BoardImageMotion motion(BoardImageMotionOptions{}, d->camera.fx);
  int64_t predicting = 0;
  for (auto _ : state) {
    motion.seen(d->target.cornersWorld(), d->corners_normalised.front());
    motion.advance(previous, current);
    predicting += motion.predicting();
  }
  state.counters["features"] = static_cast<double>(from.size());
  state.counters["predicting"] = benchmark::Counter(static_cast<double>(predicting), benchmark::Counter::kAvgIterations);
}

// The board found again where a predicted pose puts it: board_leaves' frames that show the
// whole board, predicted 3 mm and 0.2 degrees off (a gap's drift), no previous corners to track.
void BM_BoardReacquire(benchmark::State& state) {
  const StageData* d = dataOrSkip(state, "board_leaves", false);
  if (!d) return;
  if (d->board_visible.empty()) {
    state.SkipWithError("board_leaves has no frame with the whole board");
    return;
  }
  const SE3 drift = SE3::fromRotvec(Vec3(0.002, -0.0025, 0.001), Vec3(0.002, -0.0015, 0.0015));
  size_t i = 0;
  int64_t found = 0;
  for (auto _ : state) {
    const int frame = d->board_visible[i];
    BoardCornerTracker tracker(d->target, cslamOptions().board);
    const SE3 T_predicted = d->T_world_camera[frame] * drift;
    found += tracker.findCorners(d->b->frames[frame].grey, {}, {}, lkWindow(), cslamOptions().lk_levels, d->camera,
                                 &T_predicted, false)
                 .has_value();
    i = (i + 1) % d->board_visible.size();
  }
  state.counters["found"] = benchmark::Counter(static_cast<double>(found), benchmark::Counter::kAvgIterations);
}

// Tracking a board partly out of the image (board_partial's frames with half its corners or
// more in view): Lucas-Kanade from the previous frame, the re-entering corners added, confirmed.
void BM_BoardPartialTracking(benchmark::State& state) {
  const StageData* d = dataOrSkip(state, "board_partial", false);
  if (!d) return;
  std::vector<int> frames;  // partial frames whose previous frame is among the kept pyramids
  for (int f : d->board_partial)
    if (f >= 1 && f < static_cast<int>(d->pyramids.size())) frames.push_back(f);
  if (frames.empty()) {
    state.SkipWithError("no partial-board frame among the first frames of board_partial");
    return;
  }
  size_t i = 0;
  int64_t corners = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const int f = frames[i];
    BoardCornerTracker tracker(d->target, cslamOptions().board);
    // The previous frame's corners, found where its true pose puts them.
    tracker.findCorners(d->b->frames[f - 1].grey, {}, {}, lkWindow(), cslamOptions().lk_levels, d->camera,
                        &d->T_world_camera[f - 1], false);
    state.ResumeTiming();
    const auto found = tracker.findCorners(d->b->frames[f].grey, d->pyramids[f - 1], d->pyramids[f], lkWindow(),
                                           cslamOptions().lk_levels, d->camera, &d->T_world_camera[f], false);
    corners += found ? static_cast<int64_t>(found->ids.size()) : 0;
    i = (i + 1) % frames.size();
  }
  state.counters["corners"] = benchmark::Counter(static_cast<double>(corners), benchmark::Counter::kAvgIterations);
}

// One refinement of the keyframe window as the back-end runs it: window_keyframes free keyframes
// and as many fixed older ones, 150 points seen from all of them (0.3 px noise), the board's 54
// corners fixed in the oldest free keyframe, from poses and points perturbed by 2 mm / 0.1 degree
// and 1 cm.
void BM_WindowBundleAdjustment(benchmark::State& state) {
  const int n_free = cslamOptions().refinement.window_keyframes;
  const int n_fixed = cslamOptions().refinement.max_fixed_keyframes;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> noise(0, 0.3 / 525);
  std::vector<SE3> T_world_camera;
  for (int k = 0; k < n_free + n_fixed; ++k)
    T_world_camera.push_back(SE3::fromRotvec(Vec3(0.02 * u(rng), 0.01 * k, 0.02 * u(rng)),
                                             Vec3(0.16 + 0.01 * k, 0.1 + 0.005 * u(rng), -0.85)));
  std::vector<Vec3> points;
  for (int j = 0; j < 150; ++j) points.push_back(Vec3(0.16 + 0.5 * u(rng), 0.1 + 0.35 * u(rng), 0.2 * u(rng) + 0.1));
  const ChessboardTarget target{9, 6, 0.04};
  const auto xy = [&](int k, const Vec3& p) {
    const Vec3 c = T_world_camera[k].inverse() * p;
    return Vec2(c.x() / c.z() + noise(rng), c.y() / c.z() + noise(rng));
  };
  for (auto _ : state) {
    state.PauseTiming();
    BundleAdjustment ba;
    for (int k = 0; k < n_free + n_fixed; ++k) {
      const bool fixed = k < n_fixed;
      const SE3 start = fixed ? T_world_camera[k]
                              : T_world_camera[k] * SE3::fromRotvec(Vec3(0.0017 * u(rng), 0.0017 * u(rng), 0),
                                                                   Vec3(0.002 * u(rng), 0.002 * u(rng), 0));
      ba.addCamera(start.inverse(), fixed);
    }
    for (const Vec3& p : points) {
      const int j = ba.addPoint(p + Vec3(0.01 * u(rng), 0.01 * u(rng), 0.01 * u(rng)), false);
      for (int k = 0; k < n_free + n_fixed; ++k) ba.addObservation(k, j, xy(k, p), 0.3);
    }
    for (const Vec3& c : target.cornersWorld()) ba.addObservation(n_fixed, ba.addPoint(c, true), xy(n_fixed, c), 0.1);
    state.ResumeTiming();
    benchmark::DoNotOptimize(ba.solve(cslamOptions().refinement.bundle_adjustment, 525));
  }
}

// The gap's re-anchoring: a chain of 40 keyframes (a 12 s gap) held at both ends.
void BM_GapPoseGraph(benchmark::State& state) {
  constexpr int n = 42;
  std::vector<SE3> nodes;
  std::vector<char> fixed(n, 0);
  fixed.front() = fixed.back() = 1;
  std::vector<PoseGraphEdge> edges;
  for (int k = 0; k < n; ++k) nodes.push_back(SE3::fromRotvec(Vec3(0, 0.04 * k, 0), Vec3(0.01 * k, 0, 0)));
  for (int k = 0; k + 1 < n; ++k) {
    PoseGraphEdge e;
    e.from = k;
    e.to = k + 1;
    // Each motion measured 0.1 % short and 0.01 degrees off: the drift the chain spreads.
    const SE3 motion = nodes[k].inverse() * nodes[k + 1];
    e.T_from_to = SE3(rotationFromRotvec(Vec3(0, 0.0002, 0)) * motion.R(), 0.999 * motion.t());
    edges.push_back(e);
  }
  for (auto _ : state) benchmark::DoNotOptimize(optimisePoseGraph(nodes, fixed, edges));
}

// Map points looked for where the pose projects them (at keyframes while few are tracked): 60
// points of tv1's first frame, their patches taken there, searched for 5 frames later.
void BM_MapPointSearch(benchmark::State& state) {
  const StageData* d = dataOrSkip(state, "tv1", false);
  if (!d || d->b->frames.size() < 6) return;
  FeatureTracker detector(cslamOptions().features);
  detector.replenish(d->b->frames[0].grey);
  // The points on the board's wall (z = 0) under the features, from the true pose.
  std::vector<cv::Mat> patches;
  std::vector<MapPointCandidate> candidates;
  const SE3& T0 = d->T_world_camera[0];
  for (const Feature& f : detector.features()) {
    if (static_cast<int>(candidates.size()) == 60) break;
    const Vec3 ray = T0.R() * d->camera.undistortPixel(Vec2(f.uv.x, f.uv.y)).homogeneous();
    if (std::abs(ray.z()) < 1e-9) continue;
    const double s = -T0.t().z() / ray.z();
    if (s <= 0) continue;
    patches.push_back(mapPointPatch(d->b->frames[0].grey, f.uv));
    candidates.push_back({f.id, T0.t() + s * ray, nullptr, T0.t(), 5});
  }
  for (size_t k = 0; k < candidates.size(); ++k) candidates[k].patch = &patches[k];
  int64_t found = 0;
  for (auto _ : state)
    found += static_cast<int64_t>(searchMapPoints(d->b->frames[5].grey, d->camera, d->T_world_camera[5], candidates,
                                                   {}, cslamOptions().features.min_distance_px,
                                                   cslamOptions().map_search)
                                      .size());
  state.counters["found"] = benchmark::Counter(static_cast<double>(found), benchmark::Counter::kAvgIterations);
  state.counters["searched"] = static_cast<double>(candidates.size());
}

void BM_HomographyPose(benchmark::State& state, const std::string& set, bool refine) {
  const StageData* d = dataOrSkip(state, set);
  if (!d) return;
  BoardPoseOptions options = cslamOptions().board_pose;
  options.refine = refine;
  const std::vector<Vec3> p_board = d->target.cornersWorld();
  const double focal_px = 0.5 * (d->camera.fx + d->camera.fy);
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(boardPose(p_board, d->corners_normalised[i], focal_px, options));
    i = (i + 1) % d->corners_normalised.size();
  }
}

void BM_BuildPyramid(benchmark::State& state, const std::string& set) {
  const StageData* d = dataOrSkip(state, set, false);
  if (!d) return;
  std::vector<cv::Mat> pyramid;
  size_t i = 0;
  for (auto _ : state) {
    cv::buildOpticalFlowPyramid(d->b->frames[i].grey, pyramid, lkWindow(), cslamOptions().lk_levels);
    i = (i + 1) % d->b->frames.size();
  }
}

// Shi-Tomasi over the whole image, up to max_features (150), as when the back-end starts.
void BM_FeatureDetection(benchmark::State& state, const std::string& set) {
  const StageData* d = dataOrSkip(state, set, false);
  if (!d) return;
  size_t i = 0;
  int64_t detected = 0;
  for (auto _ : state) {
    FeatureTracker tracker(cslamOptions().features);
    detected += tracker.replenish(d->b->frames[i].grey);
    i = (i + 1) % d->b->frames.size();
  }
  state.counters["features"] = benchmark::Counter(static_cast<double>(detected), benchmark::Counter::kAvgIterations);
}

// 100 features from one frame to the next: forward LK, the backward check, the border test.
void BM_LkTracking100(benchmark::State& state, const std::string& set) {
  const StageData* d = dataOrSkip(state, set, false);
  if (!d) return;
  FeatureTrackerOptions options = cslamOptions().features;
  options.max_features = options.min_features = 100;
  std::vector<FeatureTracker> detected;
  for (size_t k = 0; k + 1 < d->pyramids.size(); ++k) {
    detected.emplace_back(options);
    detected.back().replenish(d->b->frames[k].grey);
  }
  size_t k = 0;
  int64_t points = 0, kept = 0;
  for (auto _ : state) {
    FeatureTracker tracker = detected[k];
    points += static_cast<int64_t>(tracker.features().size());
    tracker.track(d->pyramids[k], d->pyramids[k + 1], lkWindow(), cslamOptions().lk_levels);
    kept += static_cast<int64_t>(tracker.features().size());
    k = (k + 1) % detected.size();
  }
  state.counters["points"] = benchmark::Counter(static_cast<double>(points), benchmark::Counter::kAvgIterations);
  state.counters["kept"] = benchmark::Counter(static_cast<double>(kept), benchmark::Counter::kAvgIterations);
}

// The minimal solver alone: one RANSAC hypothesis.
void BM_EssentialEightPoint(benchmark::State& state, const std::string& set) {
  const StageData* d = dataOrSkip(state, set, false);
  if (!d) return;
  const auto& [a, b] = d->correspondences.front();
  if (a.size() < 8) {
    state.SkipWithError("fewer than 8 tracked features");
    return;
  }
  std::mt19937 rng(1);
  std::vector<std::vector<Vec2>> samples_a, samples_b;
  for (int s = 0; s < 64; ++s) {
    std::vector<int> idx(a.size());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<int>(i);
    std::shuffle(idx.begin(), idx.end(), rng);
    samples_a.emplace_back(), samples_b.emplace_back();
    for (int k = 0; k < 8; ++k) samples_a.back().push_back(a[idx[k]]), samples_b.back().push_back(b[idx[k]]);
  }
  size_t s = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(essentialEightPoint(samples_a[s], samples_b[s]));
    s = (s + 1) % samples_a.size();
  }
}

// Two-view motion as the back-end runs it: 8-point RANSAC (MSAC, adaptive stop), refinement on
// the inliers, cheirality, the parallax test; on features tracked over kTwoViewGap frames.
void BM_TwoViewRansac(benchmark::State& state, const std::string& set) {
  const StageData* d = dataOrSkip(state, set, false);
  if (!d) return;
  const double focal_px = 0.5 * (d->camera.fx + d->camera.fy);
  size_t k = 0;
  int64_t points = 0, inliers = 0;
  for (auto _ : state) {
    const auto& [a, b] = d->correspondences[k];
    const TwoViewResult r = estimateTwoViewMotion(a, b, focal_px, cslamOptions().two_view);
    points += static_cast<int64_t>(a.size());
    inliers += r.num_inliers;
    k = (k + 1) % d->correspondences.size();
  }
  state.counters["points"] = benchmark::Counter(static_cast<double>(points), benchmark::Counter::kAvgIterations);
  state.counters["inliers"] = benchmark::Counter(static_cast<double>(inliers), benchmark::Counter::kAvgIterations);
}

// The map's triangulation of one feature from n rays, added one frame at a time as the back-end
// adds them (FeatureMap::addObservation): rays from tv1's true poses to a corner of the board,
// 0.3 px noise. Least squares costs the same per ray (O(n) here); Algorithm 3.1
// (midpoint_average) pairs each new ray with every earlier one (O(n^2) here).
void BM_TriangulateFeature(benchmark::State& state, const std::string& method) {
  const StageData* d = dataOrSkip(state, "tv1", false);
  if (!d) return;
  const int n = static_cast<int>(state.range(0));
  const Trajectory& gt = *d->b->seq.groundtruth;
  if (static_cast<int>(gt.size()) < n) {
    state.SkipWithError("fewer ground-truth poses than rays");
    return;
  }
  FeatureMapOptions options;
  options.method = method;
  const double focal_px = 0.5 * (d->camera.fx + d->camera.fy);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.3 / focal_px);
  const Vec3 p_world = d->target.cornersWorld().front();
  std::vector<Vec2> xy(n);
  for (int k = 0; k < n; ++k) {
    const Vec3 p_camera = gt[k].T_world_camera.inverse() * p_world;
    xy[k] = Vec2(p_camera.x() / p_camera.z() + noise(rng), p_camera.y() / p_camera.z() + noise(rng));
  }
  for (auto _ : state) {
    FeatureMap map(options, focal_px);
    for (int k = 0; k < n; ++k) map.addObservation(0, gt[k].T_world_camera, xy[k]);
    benchmark::DoNotOptimize(map.position(0));
  }
}

// Decoding one frame of a data set with core's readGreyImage.
void BM_DecodeFrame(benchmark::State& state, const std::string& set) {
  const StageData* d = dataOrSkip(state, set, false);
  if (!d) return;
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(readGreyImage(d->b->files[i]));
    i = (i + 1) % d->b->files.size();
  }
}

// Decoding the whole rendered tv1 (all its 337 frames) through openSequence, as `slamcmp run`
// reads it, with nothing tracked: the baseline of scripts/bench.sh's whole-run ratio.
void BM_DecodeSequence(benchmark::State& state) {
  const BenchSequence& b = renderedSequence("tv1", 0);
  for (auto _ : state) {
    Sequence seq = openSequence(b.dir);
    Frame f;
    int n = 0;
    while (seq.frames->next(&f)) ++n;
    benchmark::DoNotOptimize(n);
  }
  state.counters["frames"] = static_cast<double>(b.frames.size());
}

const bool registered = [] {
  using Fn = std::function<void(benchmark::State&)>;
  const auto add = [](const std::string& name, Fn fn, benchmark::TimeUnit unit = benchmark::kMicrosecond) {
    benchmark::RegisterBenchmark(name.c_str(), [fn](benchmark::State& s) { fn(s); })->Unit(unit);
  };
  add("BM_ChessboardDetect/board_leaves/board_absent",
      [](auto& s) { BM_ChessboardDetect(s, "board_leaves", false); }, benchmark::kMillisecond);
  add("BM_BoardAbsentTest/board_leaves/predicted_in_view", [](auto& s) { BM_BoardAbsentTest(s, true); });
  add("BM_BoardAbsentTest/board_leaves/predicted_out_of_view", [](auto& s) { BM_BoardAbsentTest(s, false); });
  add("BM_BoardRegionSearch/board_leaves/board_absent", [](auto& s) { BM_BoardRegionSearchAbsent(s, true); });
  add("BM_BoardRegionSearch/board_leaves/board_absent/no_presence_test",
      [](auto& s) { BM_BoardRegionSearchAbsent(s, false); });
  add("BM_BoardPresenceTest/board_leaves/board_absent", [](auto& s) { BM_BoardPresenceTest(s); });
  add("BM_BoardPresenceSeen/tv1", [](auto& s) { BM_BoardPresenceSeen(s); });
  add("BM_BoardImageMotionAdvance/tv1", [](auto& s) { BM_BoardImageMotionAdvance(s); });
  add("BM_BoardReacquire/board_leaves", [](auto& s) { BM_BoardReacquire(s); });
  add("BM_BoardPartialTracking/board_partial", [](auto& s) { BM_BoardPartialTracking(s); });
  add("BM_WindowBundleAdjustment", [](auto& s) { BM_WindowBundleAdjustment(s); });
  add("BM_GapPoseGraph", [](auto& s) { BM_GapPoseGraph(s); });
  add("BM_MapPointSearch/tv1", [](auto& s) { BM_MapPointSearch(s); });
  for (const std::string set : {"tv1", "vamr"}) {
    add("BM_ChessboardDetect/" + set + "/board_present", [set](auto& s) { BM_ChessboardDetect(s, set, true); },
        benchmark::kMillisecond);
    for (const std::string method : {"opencv", "gradient", "gradient_lens"})
      add("BM_CornerRefinement/" + set + "/" + method, [set, method](auto& s) { BM_CornerRefinement(s, set, method); });
    add("BM_BoardCornerTracking/" + set, [set](auto& s) { BM_BoardCornerTracking(s, set); });
    add("BM_HomographyPose/" + set + "/dlt", [set](auto& s) { BM_HomographyPose(s, set, false); });
    add("BM_HomographyPose/" + set + "/refined", [set](auto& s) { BM_HomographyPose(s, set, true); });
    add("BM_BuildPyramid/" + set, [set](auto& s) { BM_BuildPyramid(s, set); });
    add("BM_FeatureDetection/" + set, [set](auto& s) { BM_FeatureDetection(s, set); });
    add("BM_LkTracking100/" + set, [set](auto& s) { BM_LkTracking100(s, set); });
    add("BM_EssentialEightPoint/" + set, [set](auto& s) { BM_EssentialEightPoint(s, set); });
    add("BM_TwoViewRansac/" + set, [set](auto& s) { BM_TwoViewRansac(s, set); });
  }
  // tv1's PNG frames are decoded in bench_tracking's BM_DecodeFrame.
  add("BM_DecodeFrame/vamr", [](auto& s) { BM_DecodeFrame(s, "vamr"); }, benchmark::kMillisecond);
  for (const std::string method : {"least_squares", "midpoint_average"})
    benchmark::RegisterBenchmark(("BM_TriangulateFeature/" + method).c_str(),
                                 [method](benchmark::State& s) { BM_TriangulateFeature(s, method); })
        ->Arg(2)
        ->Arg(10)
        ->Arg(50)
        ->Arg(100)
        ->ArgName("n")
        ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("BM_DecodeSequence/tv1", BM_DecodeSequence)->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace
}  // namespace slamcmp

