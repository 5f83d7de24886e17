// Per-frame cost of each back-end (and cslam mode) through the Tracker interface, image decoding
// excluded, and the cost of decoding the same frames: the figures of the thesis's Table 3.2.
//
//   build/benchmarks/bench_tracking [--benchmark_filter=cslam]
//
// Frames come from a rendered preset (SLAMCMP_BENCH_PRESET, default tv1; SLAMCMP_BENCH_FRAMES,
// default 120) in a temporary folder, decoded once into memory. One iteration tracks one frame; at
// the end of the sequence the tracker starts again (untimed).
#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <vector>

#include <opencv2/core/utility.hpp>

#include "benchmarks/bench_frames.h"
#include "eval/tracker_factory.h"

namespace slamcmp {
namespace {

void BM_Track(benchmark::State& state, const std::string& backend, const std::string& mode) {
  cv::setNumThreads(1);  // one core, as Table 3.2 is quoted
  const BenchSequence& b = defaultRenderedSequence();
  TrackerContext context;
  context.camera = b.seq.camera;
  context.target = b.seq.target;
  context.mode = mode;
  context.image_size = b.seq.image_size;
  std::unique_ptr<Tracker> tracker = makeTracker(backend, context);
  size_t i = 0;
  for (auto _ : state) {
    if (i == b.frames.size()) {
      state.PauseTiming();
      tracker = makeTracker(backend, context);
      i = 0;
      state.ResumeTiming();
    }
    benchmark::DoNotOptimize(tracker->track(b.frames[i++]));
  }
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

// One benchmark per back-end and mode that is built in.
const bool registered = [] {
  for (const auto& name : trackerNames()) {
    const std::vector<std::string> modes =
        name == "cslam" ? std::vector<std::string>{"combined", "calibration", "two_view"} : std::vector<std::string>{""};
    for (const auto& mode : modes)
      benchmark::RegisterBenchmark(("BM_Track/" + name + (mode.empty() ? "" : "/" + mode)).c_str(), BM_Track,
                                   name, mode)
          ->Unit(benchmark::kMillisecond)
          ->MinTime(2.0);
  }
  return true;
}();

}  // namespace
}  // namespace slamcmp

BENCHMARK_MAIN();
