// Cost of the MonoSLAM EKF's steps against the map size N (thesis section 2.4: the update is
// O(N^2) in the number of map features, which caps a real-time map at about 100 features).
//
//   build/benchmarks/bench_monoslam [--benchmark_filter=Update]
//
// The state is synthetic: a camera at the origin looking along +z and N points spread over its
// field of view at 1-3 m, with a dense, positive definite covariance (every point correlated with
// the camera and with each other, as after a few frames of tracking; see syntheticState). The
// update measures 12 features, as the tracker does a frame. Active search is timed per feature
// against the size of its 3-sigma search ellipse (half-axis in pixels), on a smooth random texture.
// The whole EKF frame (BM_EkfFrame) is the tracker's per-frame filter work on a map of N points:
// prediction, every point's prediction and S, active search of 12 with warped templates, joint
// compatibility and the batch update (measureFeatures), one core; the points lie on a textured
// plane the camera sees. Not included: the rays' particle search and new-feature selection,
// which do not depend on N. A new feature's ORB descriptor (BM_NewFeatureDescriptor) is timed over
// its neighbourhood, as the filter computes it, and over the whole image.
// The board-free hand-held frame's two-view stage (issue 18; configs/monoslam_handheld.yaml), its
// two costly parts, on tum_fr1_rpy (skipped where ../shared is absent): BM_TwoViewTracks, one
// frame's pyramid, its tracks moved on from the last frame (Lucas-Kanade forward, checked backward)
// and replenished, undistorted (TwoViewOrientation::track); BM_MultiBaselineRotation, one frame's
// orientation from the views of the frames before it (a rotation-only fit and three refinements
// of the two-view motion a view). Left out: the filter's orientation update. Their time
// is the mean a frame; the counter median_ms the median frame's CPU time, as issue 18 counts it.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "benchmarks/bench_frames.h"

#include "core/camera.h"
#include "core/stage_timer.h"
#include "core/statistics.h"
#include "ekf/ekf_state.h"
#include "ekf/ekf_update.h"
#include "ekf/frame_measurement.h"
#include "ekf/measurement_model.h"
#include "ekf/msckf_update.h"
#include "monoslam_ekf/monoslam_options.h"
#include "ekf/motion_model.h"
#include "ekf/patch_search.h"
#include "ekf/patch_warp.h"
#include "ekf/relocaliser.h"
#include "geometry/multi_baseline_rotation.h"
#include "monoslam_ekf/two_view_orientation.h"

namespace slamcmp {
namespace {

constexpr int kMeasuredPerFrame = 12;

CameraModel benchCamera() {
  return CameraModel::fromOpenCV((cv::Mat_<double>(3, 3) << 500, 0, 319.5, 0, 500, 239.5, 0, 0, 1),
                                 cv::Mat::zeros(1, 5, CV_64F), {640, 480});
}

// Camera at the origin; points at `points` (default: N spread over the field of view at 1-3 m).
EkfState syntheticState(int n_points, const std::vector<Vec3>& points = {}) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  EkfState state;
  state.reset(SE3(), Eigen::Matrix<double, 13, 13>::Identity() * 1e-4);
  for (int i = 0; i < n_points; ++i) {
    const double depth = 2.0 + unit(rng);
    const Vec3 y = points.empty() ? Vec3(0.5 * depth * unit(rng), 0.4 * depth * unit(rng), depth) : points[i];
    state.append(y, Mat3::Identity() * 1e-4, Eigen::MatrixXd::Zero(3, state.size()));
  }
  // A dense covariance D C D: C a random correlation matrix (A A^T normalised, every entry
  // correlated), D the standard deviations of a camera tracked for a while: 2 mm, quaternion 1e-3,
  // 2 cm/s, 0.03 rad/s, points 5 mm (search ellipses of about 10 px half-axis after prediction).
  const int n = state.size();
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = unit(rng);
  Eigen::MatrixXd C = A * A.transpose() / n + Eigen::MatrixXd::Identity(n, n);
  const Eigen::VectorXd c_inv_sqrt = C.diagonal().cwiseSqrt().cwiseInverse();
  Eigen::VectorXd sigma = Eigen::VectorXd::Constant(n, 0.005);
  sigma.head<13>() << Vec3::Constant(0.002), Vec4::Constant(1e-3), Vec3::Constant(0.02), Vec3::Constant(0.03);
  const Eigen::VectorXd d = sigma.cwiseProduct(c_inv_sqrt);
  state.P() = d.asDiagonal() * C * d.asDiagonal();
  return state;
}

std::vector<PointObservation> observe(const EkfState& state, const CameraModel& camera, int max_count) {
  std::vector<PointObservation> observations;
  for (int offset = EkfState::kCameraDim; offset + 3 <= state.size(); offset += 3) {
    PointObservation o;
    o.offset = offset;
    if (!predictMeasurement(camera, state.r(), state.q(), state.x().segment<3>(offset), &o.h)) continue;
    o.z = o.h.uv_distorted + Vec2(0.5, -0.5);
    observations.push_back(o);
    if (static_cast<int>(observations.size()) == max_count) break;
  }
  return observations;
}

const std::vector<int64_t> kMapSizes = {25, 50, 100, 200};

// A smooth random texture (grey-level std well above min_patch_stddev at 11x11).
cv::Mat textureImage() {
  cv::Mat noise(480, 640, CV_8U), grey;
  cv::randu(noise, 0, 255);
  cv::GaussianBlur(noise, grey, cv::Size(0, 0), 2.0);
  cv::normalize(grey, grey, 0, 255, cv::NORM_MINMAX);
  return grey;
}

void BM_Predict(benchmark::State& bench) {
  EkfState state = syntheticState(static_cast<int>(bench.range(0)));
  const MotionModelOptions options;
  for (auto _ : bench) {
    predict(state, 0.1, options);
    benchmark::DoNotOptimize(state.P().data());
  }
}
BENCHMARK(BM_Predict)->ArgsProduct({kMapSizes})->ArgName("N");

// h, its Jacobians and the 2x2 innovation covariance of every feature, as active search needs them.
void BM_MeasurementPrediction(benchmark::State& bench) {
  const EkfState state = syntheticState(static_cast<int>(bench.range(0)));
  const CameraModel camera = benchCamera();
  for (auto _ : bench) {
    int visible = 0;
    for (int offset = EkfState::kCameraDim; offset + 3 <= state.size(); offset += 3) {
      PointMeasurement h;
      if (!predictMeasurement(camera, state.r(), state.q(), state.x().segment<3>(offset), &h)) continue;
      const Mat2 S = pointInnovationCovariance(state, h, offset, 1.0);
      benchmark::DoNotOptimize(S.data());
      ++visible;
    }
    benchmark::DoNotOptimize(visible);
  }
}
BENCHMARK(BM_MeasurementPrediction)->ArgsProduct({kMapSizes})->ArgName("N");

// 12 matched features in one batch: K = P H^T S^-1 and P -= K S K^T over the whole state.
void BM_BatchUpdate(benchmark::State& bench) {
  const EkfState prior = syntheticState(static_cast<int>(bench.range(0)));
  const std::vector<PointObservation> observations = observe(prior, benchCamera(), kMeasuredPerFrame);
  EkfState state = prior;
  for (auto _ : bench) {
    bench.PauseTiming();
    state = prior;
    bench.ResumeTiming();
    batchUpdate(state, observations, 1.0);
    benchmark::DoNotOptimize(state.P().data());
  }
}
BENCHMARK(BM_BatchUpdate)->ArgsProduct({kMapSizes})->ArgName("N");

// hybrid's board: 54 corners, known points, in one update on a map of 25 or 60 points (60: about
// the state of hybrid's defaults, their clones and tracked points); the camera 1 mm and
// 0.05 degrees from where the corners put it (a frame of tracking). once 1: one linearisation
// (batchUpdate, P's update of rank 108); 0: iterated to convergence (iteratedUpdate, what hybrid
// runs; here 2 steps; P's update compressed to rank 7).
void BM_BoardCornerUpdate(benchmark::State& bench) {
  const CameraModel camera = benchCamera();
  EkfState prior = syntheticState(static_cast<int>(bench.range(1)));
  std::vector<Vec3> corners;
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 9; ++i) corners.emplace_back(-0.16 + 0.04 * i, -0.1 + 0.04 * j, 0.8);
  const SE3 truth = prior.T_world_camera() * SE3::fromRotvec(Vec3(0.0005, -0.0008, 0.0003), Vec3(0.001, 0, 0));
  std::vector<PointObservation> observations(corners.size());
  for (size_t k = 0; k < corners.size(); ++k) {
    observations[k].offset = kKnownPoint;
    observations[k].z = camera.project(truth.inverse() * corners[k]);
  }
  const Relinearise predict_at = [&](const Eigen::VectorXd& x, std::vector<PointObservation>* o) {
    for (size_t k = 0; k < corners.size(); ++k)
      if (!predictMeasurement(camera, x.segment<3>(EkfState::kR), x.segment<4>(EkfState::kQ), corners[k], &(*o)[k].h))
        return false;
    return true;
  };
  predict_at(prior.x(), &observations);
  const bool once = bench.range(0) == 1;
  for (auto _ : bench) {
    bench.PauseTiming();
    EkfState state = prior;
    std::vector<PointObservation> o = observations;
    bench.ResumeTiming();
    if (once)
      batchUpdate(state, o, 0.2);
    else
      iteratedUpdate(state, &o, 0.2, predict_at);
    benchmark::DoNotOptimize(state.P().data());
  }
}
BENCHMARK(BM_BoardCornerUpdate)
    ->ArgsProduct({{1, 0}, {25, 60}})
    ->ArgNames({"once", "points"})
    ->Unit(benchmark::kMicrosecond);

// hybrid's tracked features (hybrid/tracked_motion.h): one MSCKF update of T tracks seen in the
// last two frames (a window of 2, not the defaults' 4: the clone of the previous pose and the
// camera, 4 mm apart), on a map of 25 points; each track triangulated, its residual projected on
// the left null space of its point, the rows compressed by QR to the clones' 14 columns.
void BM_MsckfUpdate(benchmark::State& bench) {
  const CameraModel camera = benchCamera();
  EkfState prior = syntheticState(25);
  const SE3 T_world_previous = prior.T_world_camera() * SE3::fromRotvec(Vec3(0.001, -0.004, 0.0005), Vec3(-0.004, 0, 0));
  prior.x().head<3>() = T_world_previous.t();
  prior.x().segment<4>(EkfState::kQ) = quatVector(T_world_previous.quat());
  const int clone = cloneCameraPose(prior);
  prior.x().head<3>() = Vec3::Zero();
  prior.x().segment<4>(EkfState::kQ) = Vec4(1, 0, 0, 0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<std::vector<CloneObservation>> tracks;
  for (int i = 0; i < bench.range(0); ++i) {
    const double depth = 2.0 + unit(rng);
    const Vec3 p(0.5 * depth * unit(rng), 0.4 * depth * unit(rng), depth);
    tracks.push_back({{clone, camera.project(T_world_previous.inverse() * p)}, {0, camera.project(p)}});
  }
  MsckfOptions options;
  options.pixel_sigma = 0.3;
  options.min_parallax_deg = 0;
  options.snooping_probability = bench.range(1) ? 0.99 : 0;  // each track tested against the others
  for (auto _ : bench) {
    bench.PauseTiming();
    EkfState state = prior;
    bench.ResumeTiming();
    const MsckfResult result = msckfUpdate(state, camera, tracks, options);
    benchmark::DoNotOptimize(result.used);
    benchmark::DoNotOptimize(state.P().data());
  }
}
BENCHMARK(BM_MsckfUpdate)
    ->ArgsProduct({{40, 80, 160}, {0, 1}})
    ->ArgNames({"tracks", "snooping"})
    ->Unit(benchmark::kMicrosecond);

// One feature: its template warped to the predicted view, then searched over its 3-sigma ellipse.
void BM_ActiveSearchPerFeature(benchmark::State& bench) {
  const double half_axis = static_cast<double>(bench.range(0));
  const CameraModel camera = benchCamera();
  const cv::Mat grey = textureImage();
  const Vec2 uv(320, 240);
  const Vec3 y = Vec3(0, 0, 2.0) + 2.0 * Vec3((uv.x() - 319.5) / 500, (uv.y() - 239.5) / 500, 0);
  PatchSource source;
  makePatchSource(grey, uv, ActiveSearchOptions().source_size, SE3(), &source);
  const SE3 T_world_camera = SE3::fromRotvec(Vec3(0, 0.01, 0), Vec3(0.01, 0, 0));
  const double sigma = half_axis / 3.0;
  const SearchEllipse ellipse{uv, Mat2::Identity() * sigma * sigma};
  for (auto _ : bench) {
    cv::Mat templ;
    warpTemplate(source, camera, T_world_camera, y, uv, ActiveSearchOptions().patch_size, &templ);
    const std::vector<PatchMatch> matches = searchEllipses(grey, templ, {ellipse}, 3.0, 0.8);
    benchmark::DoNotOptimize(matches.data());
  }
}
BENCHMARK(BM_ActiveSearchPerFeature)->Arg(5)->Arg(10)->Arg(20)->Arg(40)->Arg(70)->ArgName("half_axis_px");

// A new feature's ORB descriptor, kept for relocalisation: over the corner's neighbourhood
// (Relocaliser::describe, whole_image 0) and over the whole 640x480 image (describeAll, 1), the
// same bits.
void BM_NewFeatureDescriptor(benchmark::State& bench) {
  const bool whole_image = bench.range(0) != 0;
  const cv::Mat grey = textureImage();
  const Relocaliser relocaliser{RelocalisationOptions{}};
  for (auto _ : bench) {
    cv::Mat descriptor;
    if (whole_image) {
      std::vector<cv::Point2f> one = {cv::Point2f(320.3f, 240.6f)};
      descriptor = relocaliser.describeAll(grey, &one);
    } else {
      descriptor = relocaliser.describe(grey, Vec2(320.3, 240.6));
    }
    benchmark::DoNotOptimize(descriptor.data);
  }
}
BENCHMARK(BM_NewFeatureDescriptor)->Arg(0)->Arg(1)->ArgName("whole_image")->Unit(benchmark::kMicrosecond);

// The filter's whole frame on a map of N points: the image is the texture on the plane z = 2 m
// seen by the camera at the origin, each point a pixel of a grid over it with its patch from that
// image, the covariance dense (syntheticState). One iteration: predict, measureFeatures.
void BM_EkfFrame(benchmark::State& bench) {
  cv::setNumThreads(1);
  const int n = static_cast<int>(bench.range(0));
  const CameraModel camera = benchCamera();
  const cv::Mat grey = textureImage();
  const int cols = static_cast<int>(std::ceil(std::sqrt(n * 4.0 / 3.0))), rows = (n + cols - 1) / cols;
  const double margin = 40;
  std::vector<Vec3> points;
  std::vector<MapFeature> prior_features;
  const ActiveSearchOptions options;
  for (int i = 0; i < n; ++i) {
    const Vec2 uv(margin + (640 - 2 * margin) * (i % cols + 0.5) / cols,
                  margin + (480 - 2 * margin) * (i / cols + 0.5) / rows);
    points.push_back(2.0 * Vec3((uv.x() - 319.5) / 500, (uv.y() - 239.5) / 500, 1.0));
    MapFeature f;
    f.id = i;
    f.offset = EkfState::kCameraDim + 3 * i;
    makePatchSource(grey, uv, options.source_size, SE3(), &f.source);
    prior_features.push_back(f);
  }
  const EkfState prior = syntheticState(n, points);
  const MotionModelOptions motion;
  EkfState state = prior;
  std::vector<MapFeature> features = prior_features;
  int matched = 0;
  for (auto _ : bench) {
    bench.PauseTiming();
    state = prior;
    features = prior_features;
    bench.ResumeTiming();
    predict(state, 1.0 / 30, motion);
    matched = measureFeatures(state, features, camera, grey, options).matched;
    benchmark::DoNotOptimize(state.P().data());
  }
  bench.counters["matched"] = matched;
}
BENCHMARK(BM_EkfFrame)->ArgsProduct({kMapSizes})->ArgName("N")->Unit(benchmark::kMicrosecond)->MinTime(1.0);

constexpr int kTumFrames = 250;  // tum_fr1_rpy's
const int kTumMaxGap = TwoViewOrientationOptions().rotation.max_gap;

// tum_fr1_rpy's frames and each one's tracks as the two-view stage makes them.
struct TumTwoView {
  const BenchSequence* b = nullptr;
  TwoViewOrientationOptions options;
  std::vector<FrameTracks> tracks;  // frame k's, undistorted
};

const TumTwoView* tumTwoView() {
  static const std::unique_ptr<TumTwoView> data = []() -> std::unique_ptr<TumTwoView> {
    const BenchSequence* b = sharedSequence("tum_fr1_rpy", kTumFrames);
    if (!b || !b->seq.camera) return nullptr;
    auto d = std::make_unique<TumTwoView>();
    d->b = b;
    TwoViewOrientation stage(*b->seq.camera, d->options);
    for (const Frame& frame : b->frames) {
      stage.track(frame.grey);
      d->tracks.push_back(stage.tracks());
    }
    return d;
  }();
  return data.get();
}

const TumTwoView* tumOrSkip(benchmark::State& bench) {
  cv::setNumThreads(1);  // one core, as `slamcmp run` tracks
  const TumTwoView* d = tumTwoView();
  if (!d) {
    bench.SkipWithError("../shared/datasets/tum_fr1_rpy is absent");
    return nullptr;
  }
  if (static_cast<int>(d->b->frames.size()) < kTumFrames) {
    bench.SkipWithError(("../shared/datasets/tum_fr1_rpy: fewer than " + std::to_string(kTumFrames) + " frames").c_str());
    return nullptr;
  }
  return d;
}

// The frames in order through one stage, as a run meets them (each frame after the first timed;
// after the last the stage starts again from the first, untimed).
void BM_TwoViewTracks(benchmark::State& bench) {
  const TumTwoView* d = tumOrSkip(bench);
  if (!d) return;
  const std::vector<Frame>& frames = d->b->frames;
  const auto start = [&] {
    auto stage = std::make_unique<TwoViewOrientation>(*d->b->seq.camera, d->options);
    stage->track(frames.front().grey);
    return stage;
  };
  std::unique_ptr<TwoViewOrientation> stage = start();
  size_t k = 1;
  int64_t tracked = 0;
  std::vector<double> frame_ms;
  for (auto _ : bench) {
    const double start_ms = threadCpuMs();
    stage->track(frames[k].grey);
    frame_ms.push_back(threadCpuMs() - start_ms);
    tracked += static_cast<int64_t>(stage->tracks().size());
    if (++k == frames.size()) {
      bench.PauseTiming();
      stage = start();
      k = 1;
      bench.ResumeTiming();
    }
  }
  bench.counters["tracked"] = benchmark::Counter(static_cast<double>(tracked), benchmark::Counter::kAvgIterations);
  bench.counters["median_ms"] = median(frame_ms);
}
BENCHMARK(BM_TwoViewTracks)->Unit(benchmark::kMillisecond)->Iterations(2 * (kTumFrames - 1));  // each frame twice

void BM_MultiBaselineRotation(benchmark::State& bench) {
  const TumTwoView* d = tumOrSkip(bench);
  if (!d) return;
  const MultiBaselineRotationOptions& o = d->options.rotation;
  // Frame k with the max_gap frames before it remembered, as orientations the identity: each view's
  // refinements (the cost) are as in a run; only which views the mean keeps may differ.
  std::vector<MultiBaselineRotation> views;
  for (int k = o.max_gap; k < static_cast<int>(d->tracks.size()); ++k) {
    views.emplace_back(o, d->b->seq.camera->fx);
    for (int j = k - o.max_gap; j < k; ++j) views.back().remember(d->tracks[j], Mat3::Identity());
  }
  size_t i = 0;
  std::vector<double> frame_ms;
  for (auto _ : bench) {
    const double start_ms = threadCpuMs();
    benchmark::DoNotOptimize(views[i].measure(d->tracks[o.max_gap + i]));
    frame_ms.push_back(threadCpuMs() - start_ms);
    i = (i + 1) % views.size();
  }
  bench.counters["median_ms"] = median(frame_ms);
}
BENCHMARK(BM_MultiBaselineRotation)->Unit(benchmark::kMillisecond)->Iterations(2 * (kTumFrames - kTumMaxGap));

}  // namespace
}  // namespace slamcmp

