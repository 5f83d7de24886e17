#pragma once
// The frames the benchmarks run on, decoded once into memory: a synthetic preset rendered once
// into a cached temporary folder, or a folder of the shared real data beside the project.
#include <string>
#include <vector>

#include "core/sequence.h"

namespace slamcmp {

struct BenchSequence {
  std::string dir;
  Sequence seq;
  std::vector<Frame> frames;
  std::vector<std::string> files;  // frames[i]'s image file
};

// `preset` rendered with `frames` frames into $TMPDIR/slamcmp-bench-<preset>-<frames> (rendered
// only if that folder has no rgb.txt yet), decoded. The same object on every call.
const BenchSequence& renderedSequence(const std::string& preset, int frames);

// The environment's SLAMCMP_BENCH_PRESET (default tv1) and SLAMCMP_BENCH_FRAMES (default 120).
const BenchSequence& defaultRenderedSequence();

// ../shared/datasets/<name> beside the source tree, its first max_frames frames decoded; nullptr
// when the shared data is absent (a user's clone).
const BenchSequence* sharedSequence(const std::string& name, int max_frames);

}  // namespace slamcmp
