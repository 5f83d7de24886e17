// Cost of each stage of the CSLAM back-end, called as cslam_tracker.cc calls it, with its default
// options, on real-looking frames: the tv1 preset (640x480, rendered once into a temporary folder
// and shared with bench_tracking), board_leaves for frames without the board, and the first 60
// frames of the shared VAMR data (752x480 JPEG; those benchmarks are skipped when it is absent).
// The EKF's stages are in bench_monoslam; whole frames in bench_tracking.
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
#include <vector>

#include <opencv2/core/utility.hpp>
#include <opencv2/video/tracking.hpp>

#include "benchmarks/bench_frames.h"
#include "core/chessboard.h"
#include "tracking/board_corner_tracker.h"
#include "cslam/cslam_tracker.h"
#include "geometry/essential_eight_point.h"
#include "cslam/feature_map.h"
#include "tracking/feature_tracker.h"
#include "geometry/homography_pose.h"
#include "geometry/two_view_motion.h"

namespace slamcmp {
namespace {

constexpr int kVamrFrames = 60;
constexpr int kBoardLeavesFrames = 160;  // the board is out of view from about frame 110 to 150
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
  for (int i = 0; i < static_cast<int>(d->b->frames.size()); ++i) {
    const auto it = T_world_camera.lower_bound(d->b->frames[i].timestamp - 1e-6);
    if (it == T_world_camera.end() || it->first > d->b->frames[i].timestamp + 1e-6) continue;
    const SE3 T_camera_world = it->second.inverse();
    int in_view = 0;
    for (const Vec3& p : corners) {
      const Vec3 p_camera = T_camera_world * p;
      in_view += p_camera.z() > 0 && d->camera.inImage(d->camera.project(p_camera), 10.0);
    }
    if (in_view == static_cast<int>(corners.size())) d->board_visible.push_back(i);
    if (in_view == 0) d->board_absent.push_back(i);
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

// "tv1", "board_leaves" or "vamr"; nullptr when the data is absent.
const StageData* stageData(const std::string& set) {
  static std::map<std::string, std::unique_ptr<StageData>> cache;
  auto it = cache.find(set);
  if (it != cache.end()) return it->second.get();
  const BenchSequence* b = set == "vamr"           ? sharedSequence("vamr_checkerboard", kVamrFrames)
                           : set == "board_leaves" ? &renderedSequence("board_leaves", kBoardLeavesFrames)
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

void BM_CornerRefinement(benchmark::State& state, const std::string& set) {
  const StageData* d = dataOrSkip(state, set);
  if (!d) return;
  size_t i = 0;
  for (auto _ : state) {
    std::vector<cv::Point2f> uv = d->corners[i];
    refineChessboardCorners(d->b->frames[d->detected[i]].grey, d->target, uv);
    benchmark::DoNotOptimize(uv.data());
    i = (i + 1) % d->corners.size();
  }
}

// The back-end's per-frame board step: last frame's corners tracked by LK and confirmed.
void BM_BoardCornerTracking(benchmark::State& state, const std::string& set) {
  const StageData* d = dataOrSkip(state, set);
  if (!d) return;
  const auto fresh = [&] {
    auto t = std::make_unique<BoardCornerTracker>(d->target, cslamOptions().board);
    t->find(d->b->frames[0].grey, {}, d->pyramids[0], lkWindow(), cslamOptions().lk_levels, &d->camera);
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
    const auto corners = tracker->find(d->b->frames[i].grey, d->pyramids[i - 1], d->pyramids[i], lkWindow(),
                                       cslamOptions().lk_levels, &d->camera);
    tracked += corners.has_value() && tracker->lastWasTracked();
    ++i;
  }
  state.counters["tracked"] = benchmark::Counter(static_cast<double>(tracked), benchmark::Counter::kAvgIterations);
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
  for (const std::string set : {"tv1", "vamr"}) {
    add("BM_ChessboardDetect/" + set + "/board_present", [set](auto& s) { BM_ChessboardDetect(s, set, true); },
        benchmark::kMillisecond);
    add("BM_CornerRefinement/" + set, [set](auto& s) { BM_CornerRefinement(s, set); });
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

BENCHMARK_MAIN();
