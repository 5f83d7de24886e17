// Per-frame cost of each back-end (and cslam mode) through the Tracker interface, image decoding
// excluded, and the cost of decoding the same frames: the figures of the thesis's Table 3.2. A
// back-end that takes --init also runs started without the board (BM_Track/<backend>@none).
//
//   build/benchmarks/bench_tracking [--benchmark_filter=cslam]
//
// Frames come from a rendered preset (SLAMCMP_BENCH_PRESET, default tv1; SLAMCMP_BENCH_FRAMES,
// default 120) in a temporary folder, decoded once into memory. One iteration tracks one frame; at
// the end of the sequence the tracker starts again (untimed). SLAMCMP_BENCH_CONFIG names an option
// file (as `slamcmp run --config`): the back-ends with a section in it run with those options.
//
//   SLAMCMP_BENCH_CONFIG=configs/hybrid_patches.yaml build/benchmarks/bench_tracking --benchmark_filter=hybrid
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core/utility.hpp>

#include "benchmarks/bench_frames.h"
#include "core/error.h"
#include "core/stage_timer.h"
#include "core/statistics.h"
#include "eval/app/backends.h"

namespace slamcmp {
namespace {

// Tracks b's frames, one an iteration, starting a new tracker (untimed) at the end of the sequence;
// false (the benchmark skipped with the reason) when the options cannot be read. The frames' CPU
// times (the tracking thread's) go to *frame_ms when given.
bool trackFrames(benchmark::State& state, const BenchSequence& b, const BackendRegistration& backend,
                 const std::string& mode, InitSource init, const std::string& config,
                 std::vector<double>* frame_ms = nullptr) {
  cv::setNumThreads(1);  // one core, as Table 3.2 is quoted
  TrackerContext context;
  context.camera = b.seq.camera;
  context.target = b.seq.target;
  context.mode = mode;
  context.image_size = b.seq.image_size;
  context.init = init;
  std::unique_ptr<BackendOptions> options;
  try {  // the back-end's defaults, or as `slamcmp run --config` reads the file
    options = loadBackendOptions(backend, config, {}, std::nullopt, b.seq.image_size);
  } catch (const InputError& e) {
    state.SkipWithError(e.what());
    return false;
  }
  std::unique_ptr<Tracker> tracker = backend.make(context, *options);
  size_t i = 0;
  for (auto _ : state) {
    if (i == b.frames.size()) {
      state.PauseTiming();
      tracker = backend.make(context, *options);
      i = 0;
      state.ResumeTiming();
    }
    const double start = frame_ms ? threadCpuMs() : 0;
    benchmark::DoNotOptimize(tracker->track(b.frames[i++]));
    if (frame_ms) frame_ms->push_back(threadCpuMs() - start);
  }
  return true;
}

void BM_Track(benchmark::State& state, const BackendRegistration* backend, const BackendMode* mode, InitSource init) {
  const char* config = std::getenv("SLAMCMP_BENCH_CONFIG");
  if (!trackFrames(state, defaultRenderedSequence(), *backend, mode->name, init, config ? config : "")) return;
  // bench_report's Table 3.2 column, without linking the back-ends (the thesis started from the board)
  state.SetLabel(init == InitSource::Board ? mode->thesis_method : "");
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()),
                                                      benchmark::Counter::kIsRate);
}

void BM_DecodeFrame(benchmark::State& state) {
  const BenchSequence& b = defaultRenderedSequence();
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(readGreyImage(b.files[i]));
    i = (i + 1) % b.files.size();
  }
}
BENCHMARK(BM_DecodeFrame)->Unit(benchmark::kMillisecond);

// Issue 18's measurement: monoslam started without a board (--init none) on the real hand-held
// tum_fr1_rpy, its 250 frames, with configs/monoslam_handheld.yaml, as `slamcmp run` runs it. The
// counter median_ms is the frames' median CPU time (the target, 5 ms; the benchmark's own time
// is the mean, which the frames that look for new features pull up); skipped where ../shared is
// absent.
void BM_TrackHandheldTum(benchmark::State& state) {
  const BenchSequence* b = sharedSequence("tum_fr1_rpy", 250);
  if (!b) {
    state.SkipWithError("../shared/datasets/tum_fr1_rpy is absent");
    return;
  }
  const BackendRegistration& monoslam = findBackend("monoslam");
  std::vector<double> frame_ms;
  if (trackFrames(state, *b, monoslam, monoslam.modes.front().name, InitSource::None,
                  std::string(SLAMCMP_SOURCE_DIR) + "/configs/monoslam_handheld.yaml", &frame_ms))
    state.counters["median_ms"] = median(frame_ms);
}
BENCHMARK(BM_TrackHandheldTum)->Unit(benchmark::kMillisecond)->Iterations(500);

// One benchmark per registered back-end and mode: BM_Track/<backend>[/<mode> when it has several],
// and BM_Track/<backend>@none for those that take --init.
const bool registered = [] {
  for (const BackendRegistration& b : backends())
    for (const BackendMode& m : b.modes)
      for (const InitSource init : {InitSource::Board, InitSource::None}) {
        if (init == InitSource::None && !b.takes_init) continue;
        const std::string name = "BM_Track/" + b.name + (init == InitSource::None ? "@none" : "") +
                                 (b.modes.size() > 1 ? "/" + m.name : "");
        benchmark::RegisterBenchmark(name.c_str(), BM_Track, &b, &m, init)->Unit(benchmark::kMillisecond)->MinTime(2.0);
      }
  return true;
}();

}  // namespace
}  // namespace slamcmp

