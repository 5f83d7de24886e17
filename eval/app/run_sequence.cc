#include "eval/app/run_sequence.h"

#include <algorithm>
#include <chrono>
#include <csignal>  // sigaction (POSIX)
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <thread>

#include <opencv2/core/utility.hpp>

#include "core/error.h"
#include "core/frame_prefetcher.h"
#include "core/interrupt.h"
#include "core/map_ply.h"
#include "core/progress.h"
#include "core/run_files.h"
#include "core/run_recorder.h"
#include "core/sequence.h"
#include "core/trajectory.h"
#include "eval/metrics/board_visibility.h"
#include "eval/metrics/map_metrics.h"
#include "eval/metrics/nees.h"
#include "eval/metrics/trajectory_metrics.h"
#include "eval/overlay/overlay_output.h"
#include "eval/metrics/run_errors.h"
#include "eval/app/backends.h"

namespace slamcmp {

namespace {

extern "C" void onInterrupt(int) { requestInterrupt(); }

// OpenCV's thread count for one run, restored after it (the fuzzer runs many in one process) as
// getNumThreads() reports it: a setting of 0 (sequential) reads back as the core count.
class OpenCvThreads {
 public:
  explicit OpenCvThreads(int threads) : previous_(cv::getNumThreads()) { cv::setNumThreads(threads); }
  ~OpenCvThreads() { cv::setNumThreads(previous_); }
  OpenCvThreads(const OpenCvThreads&) = delete;
  OpenCvThreads& operator=(const OpenCvThreads&) = delete;

 private:
  int previous_;
};

// TrackerContext.init from "board", "groundtruth", "manual:FILE" or "none".
void setInitialisation(const std::string& init, const Sequence& seq, TrackerContext* context) {
  if (init == "board") {
    context->init = InitSource::Board;
  } else if (init == "none") {
    context->init = InitSource::None;
  } else if (init == "groundtruth") {
    if (!seq.groundtruth)
      throw InputError("--init groundtruth", "sequence " + seq.path + " has no groundtruth.txt");
    context->init = InitSource::GroundTruth;
    context->T_world_camera_init = seq.groundtruth->front().T_world_camera;
  } else if (init.rfind("manual:", 0) == 0) {
    const std::string file = init.substr(7);
    if (file.empty()) throw InputError("--init", "manual:FILE needs a file (a TUM pose line)");
    context->init = InitSource::Manual;
    context->T_world_camera_init = readSingleTumPose(file).T_world_camera;
  } else {
    throw InputError("--init", "must be board, groundtruth, manual:FILE or none, got '" + init + "'");
  }
}

}  // namespace

// Ctrl-C (SIGINT), `kill` (SIGTERM) and a closed terminal or ssh session (SIGHUP) all stop the run
// at the next frame, leaving whole outputs for the frames done and "interrupted": true.
// A hang-up the parent ignores stays ignored (`nohup slamcmp run ...` must survive it).
void installInterruptHandler() {
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction current {};
    if (signal_number == SIGHUP && sigaction(signal_number, nullptr, &current) == 0 &&
        current.sa_handler == SIG_IGN)
      continue;
    struct sigaction action {};
    action.sa_handler = onInterrupt;
    sigemptyset(&action.sa_mask);
    sigaction(signal_number, &action, nullptr);
  }
}
bool interrupted() { return interruptRequested(); }

std::string defaultRunDir(const std::string& sequence_name, const std::string& backend,
                          const std::string& mode) {
  return "runs/" + sequence_name + "-" + backend + (mode.empty() ? "" : "-" + mode);
}

nlohmann::json runSequence(const RunRequest& request) {
  // Not "the sequence has no frames", which is what an empty run would say at its end.
  if (request.max_frames == 0) throw InputError("--max-frames 0", "nothing to run");
  // Beyond the machine's hardware threads OpenCV's TBB pool only warns (and crashed past 65536).
  const int hardware_threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  if (request.opencv_threads < 1 || request.opencv_threads > hardware_threads)
    throw InputError("--threads", "must be in [1, " + std::to_string(hardware_threads) + "] (this machine's hardware threads), got " +
                                      std::to_string(request.opencv_threads));
  const OpenCvThreads opencv_threads(request.opencv_threads);
  if (request.show) requireDisplay();
  SequenceOpenOptions open_options;
  open_options.camera_path = request.camera_path;
  open_options.target_path = request.target_path;
  open_options.allow_symmetric_target = true;  // warned about below; the back-ends keep its origin
  Sequence seq = openSequence(request.sequence_path, open_options);
  const bool board_symmetric = seq.target && seq.target->symmetric();
  if (board_symmetric)
    std::cerr << seq.target_path + ": the " + std::to_string(seq.target->cols) + "x" +
                     std::to_string(seq.target->rows) +
                     " board is symmetric (a 180 degree turn looks the same); its origin is chosen in the "
                     "first frame that shows it and kept by continuity\n";
  // A synthetic sequence's true surfaces, read before tracking so a bad file stops the run early.
  std::optional<SceneGeometry> scene;
  if (const std::string scene_path = sceneFileOf(seq.path); !scene_path.empty()) scene = readSceneYaml(scene_path);

  const BackendRegistration& backend = findBackend(request.backend);
  TrackerContext context;
  context.camera = seq.camera;
  context.target = seq.target;
  context.mode = findMode(backend, request.mode).name;
  context.image_size = seq.image_size;
  if (!request.init.empty()) requireTakesInit(backend);
  if (backend.takes_init) setInitialisation(request.init.empty() ? "board" : request.init, seq, &context);
  context.want_overlay = !request.overlay_path.empty() || request.show;
  const std::unique_ptr<BackendOptions> options =
      loadBackendOptions(backend, request.config_path, request.sets, request.seed, seq.image_size);
  std::unique_ptr<Tracker> tracker = backend.make(context, *options);
  // Created once the options and the back-end are known good: a bad --config leaves no video behind.
  std::optional<OverlayOutput> overlay;
  if (context.want_overlay) overlay.emplace(request.overlay_path, request.show, seq.image_size, seq.fps);

  const std::string out_dir =
      request.out_dir.empty() ? defaultRunDir(seq.name, request.backend, request.mode) : request.out_dir;
  // A run before into this folder: its outputs are not this run's, and one left beside this run's
  // (a summary.json beside a trajectory.txt cut short by a failure) would pass for a whole run.
  // Only these files, by name: the folder may hold anything else.
  for (const char* stale : {run_files::kSummary, run_files::kMap, run_files::kNees, run_files::kKeyframes}) {
    std::error_code ignored;
    std::filesystem::remove(std::filesystem::path(out_dir) / stale, ignored);
  }
  RunRecorder recorder(out_dir, tracker->name());  // replaces trajectory.txt and frames.csv
  const int total = request.max_frames >= 0 && seq.frames->size() >= 0
                        ? std::min(request.max_frames, seq.frames->size())
                        : seq.frames->size();
  Progress progress(request.progress ? seq.name + " " + tracker->name() : "", request.progress ? total : 0);

  FramePrefetcher frames(*seq.frames, request.max_frames);
  DecodedFrame d;
  int decoded_ok = 0;
  std::vector<CovariantPose> covariant_poses;  // filters' poses with their covariance, for NEES
  std::vector<double> frame_timestamps;        // every frame read, posed or not
  bool quit = false;  // q or Esc in the --show window: this run only, unlike Ctrl-C
  std::set<std::string> undecodable;  // image files warned about
  while (!interrupted() && !quit && frames.next(&d)) {
    frame_timestamps.push_back(d.frame.timestamp);
    if (d.frame.grey.empty()) {
      // One bad image in a long sequence must not end the run, nor pass unseen: said once a file
      // (a looped list plays a file again).
      if (undecodable.insert(d.frame.source).second)
        std::cerr << d.frame.source << ": warning: cannot be decoded as an image"
                  << (d.frame.decode_error.empty() ? "" : " (" + d.frame.decode_error + ")")
                  << "; its frame is recorded as lost\n";
      recorder.recordUndecodable(d.frame, d.decode_ms);
      continue;
    }
    ++decoded_ok;
    const double cpu_start = threadCpuMs();
    const auto start = std::chrono::steady_clock::now();
    const FrameResult result = tracker->track(d.frame);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    recorder.record(d.frame, result, ms, threadCpuMs() - cpu_start, d.decode_ms);
    if (result.T_world_camera && result.pose_covariance && result.T_world_camera->isFinite() &&
        result.pose_covariance->allFinite())
      covariant_poses.push_back({d.frame.timestamp, *result.T_world_camera, *result.pose_covariance});
    if (overlay && !overlay->add(d.frame, result)) quit = true;
    if (request.progress) progress.update(recorder.frames(), toString(result.status));
    if (request.on_frame) request.on_frame();
  }
  progress.finish();
  recorder.flush();  // before finish() may throw: the files hold every frame recorded
  // Interrupted before a frame could be tracked: still written whole below, a run of the frames
  // read (none, or none decodable) with "interrupted": true and no timings, so that --collect
  // counts it interrupted, not failed.
  if (!interrupted()) {
    if (recorder.frames() == 0) throw InputError(seq.path, "the sequence has no frames");
    if (decoded_ok == 0) throw InputError(seq.path, "not one frame could be decoded");
  }
  if (!interrupted() && !quit) {
    try {
      tracker->finish();
    } catch (const InputError& e) {  // the back-end cannot know the path: name it here
      throw InputError(seq.path, e.what());
    }
  }

  nlohmann::json extra;
  // A video cut short (an interrupted copy or download): its container counts more frames than
  // could be read. The run covers those read; the gap is said, not left to be noticed.
  if (!interrupted() && !quit && total > 0 && recorder.frames() < total) {
    extra["frames_expected"] = total;
    extra["frames_missing"] = total - recorder.frames();
    std::cerr << seq.path << ": warning: the file says " << total << " frames but only " << recorder.frames()
              << " could be read (cut short?); the results cover those\n";
  }
  extra["sequence"] = seq.path;
  extra["mode"] = context.mode;
  if (backend.takes_init) extra["init"] = request.init.empty() ? "board" : request.init;
  extra["interrupted"] = interrupted() || quit;
  extra["opencv_threads"] = request.opencv_threads;
  if (board_symmetric) extra["board_symmetric"] = true;
  extra["options"] = tracker->options();
  // A board-free start has no metric world frame: its world is its first camera's and its unit
  // the inverse-depth prior's, so it is scored after a Sim(3) alignment (and says so).
  const bool scale_free = backend.takes_init && context.init == InitSource::None;
  if (scale_free) {
    extra["alignment"] = "sim3";
    extra["scale_convention"] = "arbitrary: world = the first camera, unit = the inverse-depth prior's "
                                "(inverse_depth.rho0; with inverse_depth.scale_gauge_sigma > 0 the first frame's "
                                "features' mean inverse depth is rho0 within it); scale = ground-truth metres per unit";
    // One Sim(3) fits the run only if the run has one scale: a lost filter is never restarted.
    extra["after_loss"] = "one map at one scale: lost frames are posed again only once the map made while "
                          "the run was posed is found again (relocalised), never from a new map";
  }
  std::optional<Similarity3> T_gt_scale_free;  // a scale-free run's Sim(3) alignment, for its map too
  if (seq.groundtruth && recorder.tracked() < 2 && !interrupted() && !quit) {
    // Not scored, and said: a summary.json without ate would otherwise pass for a run without truth.
    extra["metrics_error"] = std::to_string(recorder.tracked()) + " posed frame(s): the ATE and RPE need 2 or more";
    std::cerr << seq.groundtruth_path << ": warning: the run cannot be scored against it: "
              << extra["metrics_error"].get<std::string>() << "\n";
  }
  if (seq.groundtruth && recorder.tracked() > 0) {
    try {
      const Trajectory estimate = readTrajectory(recorder.trajectoryPath(), TrajectoryFormat::Tum);
      // A run started from the board is in the board's world, as its ground truth must then be.
      const bool board_world = !backend.takes_init || context.init == InitSource::Board;
      Similarity3 T_gt_estimate;
      if (const auto errors = evaluateRun(*seq.groundtruth, estimate, scale_free ? "sim3" : "none")) {
        extra["ate"] = errors->json["ate"];
        extra["rpe"] = errors->json["rpe"];
        // As `eval --json` says them: the poses scored and how they were aligned ("none": in the
        // board's world as given).
        extra["matched"] = errors->json["matched"];
        extra["alignment"] = errors->json["align"];
        T_gt_estimate = errors->T_gt_estimate;
        if (scale_free) {
          extra["scale"] = T_gt_estimate.scale;
          T_gt_scale_free = T_gt_estimate;
        } else if (const std::string hint = board_world ? boardWorldMismatch(*seq.groundtruth, estimate, errors->ate_trans_rmse) : "";
                   !hint.empty()) {
          std::cerr << seq.groundtruth_path << ": warning: " << hint << "\n";
          extra["metrics_warning"] = hint;
        }
      }
      // Scored by what the true camera sees of the board: for a run in the board's world; not once
      // no frame sees a corner.
      if (board_world && seq.camera && seq.target) {
        const auto board_frames = boardViewFrames(frame_timestamps, *seq.groundtruth, estimate, *seq.camera,
                                                  *seq.target, EvalOptions{}.max_diff);
        if (std::any_of(board_frames.begin(), board_frames.end(), [](const BoardViewFrame& f) { return f.corners_in_view > 0; }))
          extra["board_view"] = boardVisibilityToJson(scoreBoardVisibility(board_frames, seq.target->numCorners()));
      }
      if (const auto nees = poseNees(*seq.groundtruth, covariant_poses, EvalOptions{}.max_diff, T_gt_estimate, scale_free)) {
        extra["nees"] = neesToJson(*nees);
        writeNeesCsv(out_dir + "/" + run_files::kNees, *nees);  // for compare's test over trials
      }
    } catch (const InputError& e) {  // the run is fine; only its score is impossible, which is said
      extra["metrics_error"] = e.what();
      std::cerr << seq.groundtruth_path << ": warning: the run cannot be scored against it: " << e.what() << "\n";
    }
  }
  writeMapPly(out_dir + "/" + run_files::kMap, tracker->mapPoints());
  if (const auto keyframes = tracker->keyframePoses(); !keyframes.empty()) {
    Trajectory keyframe_trajectory;
    for (const auto& [index, T_world_camera] : keyframes)  // a keyframe is a frame this run read
      if (index >= 0 && index < static_cast<int>(frame_timestamps.size()))
        keyframe_trajectory.push_back({frame_timestamps[index], T_world_camera});
    writeTumTrajectory(out_dir + "/" + run_files::kKeyframes, keyframe_trajectory);
  }
  // The map as written scored, as the trajectory is (compare --collect scores the same file and
  // gets the same figures); a scale-free map through its trajectory's Sim(3), or not at all.
  if (scene && (!scale_free || T_gt_scale_free)) {
    const std::vector<MapPoint> map = readRunMap(out_dir + "/" + run_files::kMap, T_gt_scale_free ? &*T_gt_scale_free : nullptr);
    extra["map"] = mapStatsToJson(evaluateMap(map, *scene).stats);
  }
  return recorder.writeSummary(extra);
}

}  // namespace slamcmp
