#include "benchmarks/bench_frames.h"

#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>

#include "datasets/synth_sequence.h"

namespace slamcmp {

namespace {

std::unique_ptr<BenchSequence> decodeSequence(const std::string& dir, int max_frames) {
  auto b = std::make_unique<BenchSequence>();
  b->dir = dir;
  b->seq = openSequence(dir);
  Frame f;
  while ((max_frames < 0 || static_cast<int>(b->frames.size()) < max_frames) && b->seq.frames->next(&f)) {
    b->files.push_back(f.source);
    b->frames.push_back(f);
    f = Frame();
  }
  return b;
}

}  // namespace

const BenchSequence& renderedSequence(const std::string& preset, int frames) {
  static std::map<std::string, std::unique_ptr<BenchSequence>> cache;
  const std::string key = preset + "-" + std::to_string(frames);
  auto& entry = cache[key];
  if (!entry) {
    const std::string dir = (std::filesystem::temp_directory_path() / ("slamcmp-bench-" + key)).string();
    if (!std::filesystem::exists(dir + "/rgb.txt")) {
      SynthOptions synth;
      synth.preset = preset;
      synth.frames = frames;
      writeSyntheticSequence(synth, dir);
    }
    entry = decodeSequence(dir, -1);
  }
  return *entry;
}

const BenchSequence& defaultRenderedSequence() {
  const char* preset = std::getenv("SLAMCMP_BENCH_PRESET");
  const char* frames = std::getenv("SLAMCMP_BENCH_FRAMES");
  return renderedSequence(preset ? preset : "tv1", frames ? std::atoi(frames) : 120);
}

const BenchSequence* sharedSequence(const std::string& name, int max_frames) {
  static std::map<std::string, std::unique_ptr<BenchSequence>> cache;
  auto& entry = cache[name];
  if (!entry) {
    const std::filesystem::path dir =
        std::filesystem::path(SLAMCMP_SOURCE_DIR) / ".." / "shared" / "datasets" / name;
    if (!std::filesystem::exists(dir / "rgb.txt")) return nullptr;
    entry = decodeSequence(dir.lexically_normal().string(), max_frames);
  }
  return entry.get();
}

}  // namespace slamcmp
