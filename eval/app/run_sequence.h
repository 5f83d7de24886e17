#pragma once
// One back-end on one sequence: open, track every frame, record (SPEC section 4 outputs).
// Shared by `slamcmp run`, `compare` and `reproduce`.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace slamcmp {

struct RunRequest {
  std::string backend;        // a registered back-end (eval/app/backends.h)
  std::string sequence_path;  // folder, video or EuRoC folder
  std::string out_dir;        // "" = runs/<sequence>-<backend>[-<mode>]
  std::string config_path;    // YAML with one section per back-end; "" = defaults
  std::vector<std::string> sets;  // --set section.key=value overrides of the config
  std::optional<int> seed;        // --seed: every random seed of the back-end (none = its defaults)
  std::string camera_path;    // overrides camera.yaml
  std::string target_path;    // overrides target.yaml
  int max_frames = -1;        // < 0: all
  std::string mode;           // back-end mode ("" = its default)
  std::string init;           // board | groundtruth | manual:FILE | none; "" = board for back-ends that take it
  bool progress = true;       // a progress line on a terminal
  std::string overlay_path;   // run --overlay: video file or PNG folder of drawn frames; "" = none
  bool show = false;          // run --show: the drawn frames in a live window
  // OpenCV's threads for the back-end (run --threads). With 1 OpenCV's work stays on the tracking
  // thread, whose CPU time is a frame's cpu_ms; with more, its workers' part is not in cpu_ms.
  int opencv_threads = 1;
  std::function<void()> on_frame;  // called after each frame (compare's overall progress)
};

// Runs to the end of the sequence (or max_frames, or Ctrl-C: the frames done stay valid) and
// returns summary.json's content. Throws InputError for bad input.
nlohmann::json runSequence(const RunRequest& request);
// What `run` prints after its summary ("cslam: 20/20 frames tracked, ..."): a log holding it
// belongs to a run that finished (compare's collect tells it from one still running).
inline constexpr const char* kRunResultMark = " frames tracked";

// Ctrl-C stops runs at the next frame instead of killing the process.
void installInterruptHandler();
bool interrupted();

// runs/<sequence>-<backend>[-<mode>]
std::string defaultRunDir(const std::string& sequence_name, const std::string& backend,
                          const std::string& mode);

}  // namespace slamcmp
