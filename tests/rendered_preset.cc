#include "tests/rendered_preset.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/sequence.h"
#include "datasets/synth_sequence.h"
#include "tests/test_util.h"

namespace slamcmp::test {

RenderedPreset renderPreset(const std::string& preset, int frames) {
  TempDir dir;
  SynthOptions options;
  options.preset = preset;
  options.frames = frames;
  writeSyntheticSequence(options, dir.file(preset));
  Sequence seq = openSequence(dir.file(preset));
  RenderedPreset out;
  if (!seq.camera || !seq.target || !seq.groundtruth) {
    ADD_FAILURE() << preset << " rendered without camera, target or ground truth";
    return out;
  }
  out.camera = *seq.camera;
  out.target = *seq.target;
  for (Frame f; seq.frames->next(&f);)
    for (const StampedPose& p : *seq.groundtruth)
      if (std::abs(p.timestamp - f.timestamp) < 1e-6) out.frames.push_back({f.grey, p.T_world_camera});
  EXPECT_EQ(static_cast<int>(out.frames.size()), frames) << preset << ": frames with their true pose";
  return out;
}

}  // namespace slamcmp::test
