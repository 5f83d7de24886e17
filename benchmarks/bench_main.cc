// The benchmarks' main: frame buffers reused as in slamcmp (core/frame_memory.h), so that a stage
// costs here what it costs in a run.
#include <benchmark/benchmark.h>

#include "core/frame_memory.h"

int main(int argc, char** argv) {
  slamcmp::keepFreedMemoryForReuse();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
