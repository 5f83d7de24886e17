// libFuzzer target: `run` end to end (eval/app/run_sequence.h) on a tiny rendered sequence (four
// 320x240 frames of preset tv1, rendered once) with a mutated camera.yaml, target.yaml and --config.
// The input: a first byte choosing the back-end, then the three files separated by lines "==="
// (fuzz/seeds/run holds valid ones); an input without exactly three is skipped.
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "core/error.h"
#include "datasets/camera_motion.h"
#include "datasets/room_scene.h"
#include "datasets/scene_renderer.h"
#include "eval/app/backends.h"
#include "eval/app/run_sequence.h"
#include "fuzz/fuzz_input.h"

namespace {

constexpr int kFrames = 4;

// The rendered frames and rgb.txt in workDir()/seq; returns the folder.
std::string renderSequence() {
  using namespace slamcmp;
  const auto dir = fuzz::workDir() / "seq";
  std::filesystem::create_directories(dir / "rgb");
  CameraModel camera = syntheticCamera("tv1");  // 640x480 halved
  camera.width /= 2;
  camera.height /= 2;
  camera.fx /= 2;
  camera.fy /= 2;
  camera.cx = (camera.cx + 0.5) / 2 - 0.5;
  camera.cy = (camera.cy + 0.5) / 2 - 0.5;
  const Scene scene = buildRoomScene(1);
  const CameraMotion motion("tv1", 1);
  const SceneRenderer renderer(camera, scene, 1);
  std::string list;
  for (int i = 0; i < kFrames; ++i) {
    const double t = i / kSyntheticFps;
    const cv::Mat image = renderer.renderFrame([&motion](double s) { return motion.T_world_camera(s); }, t,
                                               1.0 / kSyntheticFps, FrameEffects{}, 1, i);
    const std::string name = "rgb/" + std::to_string(i) + ".png";
    cv::imwrite((dir / name).string(), image);
    list += std::to_string(t) + " " + name + "\n";
  }
  fuzz::writeInput("seq/rgb.txt", reinterpret_cast<const uint8_t*>(list.data()), list.size());
  return dir.string();
}

// Rendered before fuzzing starts, not within the first input's time limit (tens of seconds with
// the sanitizers on a busy machine: reported as a timeout).
const std::string& sequenceFolder() {
  static const std::string seq = renderSequence();
  return seq;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  sequenceFolder();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace slamcmp;
  const std::string& seq = sequenceFolder();
  if (size < 1) return 0;
  const BackendRegistration& backend = backends()[data[0] % backends().size()];
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  std::vector<std::string> parts;
  for (size_t start = 0;;) {
    const size_t end = text.find("\n===\n", start);
    parts.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) break;
    start = end + 5;
  }
  if (parts.size() != 3) return 0;
  const auto write = [](const std::string& name, const std::string& s) {
    return fuzz::writeInput(name, reinterpret_cast<const uint8_t*>(s.data()), s.size());
  };
  RunRequest request;
  request.backend = backend.name;
  request.sequence_path = seq;
  request.camera_path = write("camera.yaml", parts[0]);
  request.target_path = write("target.yaml", parts[1]);
  request.config_path = write("config.yaml", parts[2]);
  request.out_dir = (fuzz::workDir() / "out").string();
  request.progress = false;
  try {
    runSequence(request);
  } catch (const InputError&) {  // the expected answer to bad input; anything else is a finding
  }
  return 0;
}
