// The contract every registered back-end and mode keeps (STYLE: one contract test over the
// registry; a new back-end gets it for free): a frame it cannot pose has a reason and no pose; a
// run that never saw what it needs is refused by finish(); its options round-trip through the
// YAML a config file holds; and a short run through the command line writes valid files.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "core/backend_registry.h"
#include "core/error.h"
#include "core/frames_csv.h"
#include "core/map_ply.h"
#include "core/sequence.h"
#include "core/trajectory.h"
#include "core/yaml.h"
#include "datasets/camera_motion.h"
#include "datasets/room_scene.h"
#include "datasets/synth_sequence.h"
#include "eval/app/backends.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

using test::TempDir;

struct BackendCase {
  std::string backend;
  std::string mode;
};

std::vector<BackendCase> everyBackendAndMode() {
  std::vector<BackendCase> cases;
  for (const BackendRegistration& b : backends())
    for (const BackendMode& m : b.modes) cases.push_back({b.name, m.name});
  return cases;
}

std::string caseName(const ::testing::TestParamInfo<BackendCase>& info) {
  return info.param.backend + "_" + info.param.mode;
}

void PrintTo(const BackendCase& c, std::ostream* out) { *out << c.backend << ":" << c.mode; }

constexpr int kFrames = 20;

// Every frame's status in frames.csv (SPEC section 4): a pose's source, or initialising or lost.
const std::set<std::string> kPoseSources{"board", "two_view", "ekf"};

// What needs no images: the back-end for the synthetic camera and board, blank frames, options.
class BackendContract : public ::testing::TestWithParam<BackendCase> {
 protected:
  const BackendRegistration& backend() const { return findBackend(GetParam().backend); }

  // The back-end with its default options, for the synthetic camera and board (what a rendered
  // sequence's camera.yaml and target.yaml hold).
  std::unique_ptr<Tracker> makeTracker() const {
    TrackerContext context;
    context.camera = syntheticCamera();
    context.target = syntheticTarget();
    context.mode = GetParam().mode;
    context.image_size = imageSize();
    return backend().make(context, *backend().default_options());
  }

  static cv::Size imageSize() { return cv::Size(syntheticCamera().width, syntheticCamera().height); }

  // A flat grey frame: no board, no texture.
  static Frame blankFrame(int index) {
    Frame frame;
    frame.index = index;
    frame.timestamp = index / kSyntheticFps;
    frame.grey = cv::Mat(imageSize(), CV_8UC1, cv::Scalar(128));
    frame.source = "blank " + std::to_string(index);
    return frame;
  }
};

// Runs on tv1, 20 frames, rendered once for the suite (one anti-aliasing sample a pixel: these
// tests check consistency and the files' validity, not accuracy).
class BackendRunContract : public BackendContract {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    SynthOptions options;
    options.preset = "tv1";
    options.frames = kFrames;
    options.supersample = 1;
    writeSyntheticSequence(options, sequencePath());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::string sequencePath() { return dir_->file("tv1"); }

  static TempDir* dir_;
};
TempDir* BackendRunContract::dir_ = nullptr;

// Frames without a board before the back-end ever started: not posed (lost, or initialising while
// it waits for the board), each with a reason and without a pose or a pose source.
TEST_P(BackendContract, FrameWithoutBoardHasAReasonAndNoPose) {
  const auto tracker = makeTracker();
  for (int i = 0; i < 5; ++i) {
    const FrameResult r = tracker->track(blankFrame(i));
    EXPECT_NE(r.status, TrackStatus::Tracked) << "frame " << i;
    EXPECT_FALSE(r.T_world_camera.has_value()) << "frame " << i;
    EXPECT_FALSE(r.reason.empty()) << "frame " << i << " (" << toString(r.status) << ")";
    EXPECT_TRUE(r.source.empty()) << "frame " << i << ": " << r.source;
    EXPECT_TRUE(r.late_poses.empty()) << "frame " << i;
  }
}

// Over a run that sees the board, loses it (blank frames) and sees it again, every result keeps
// the invariants: no pose for a blank frame, a pose exactly when tracked, a known source then, and
// a reason otherwise; it
// times every stage its registration names, and none it does not (its optional stages may be
// timed).
TEST_P(BackendRunContract, StatusPoseAndReasonAgreeOnEveryFrame) {
  const auto tracker = makeTracker();
  Sequence seq = openSequence(sequencePath());
  ASSERT_TRUE(seq.camera && seq.target);
  ASSERT_DOUBLE_EQ(seq.camera->fx, syntheticCamera().fx);  // the camera makeTracker() gives the back-end
  ASSERT_EQ(seq.target->cols, syntheticTarget().cols);
  std::vector<Frame> frames;
  for (Frame f; seq.frames->next(&f);) frames.push_back(f);
  ASSERT_EQ(static_cast<int>(frames.size()), kFrames);
  const std::set<std::string> vocabulary(backend().stages.begin(), backend().stages.end());
  ASSERT_FALSE(vocabulary.empty()) << "the registration names no stages";
  std::set<std::string> known = vocabulary;  // what a run may time
  known.insert(backend().optional_stages.begin(), backend().optional_stages.end());
  std::set<std::string> stages_seen;
  int tracked = 0;
  for (int i = 0; i < kFrames; ++i) {
    const bool blank = i >= 8 && i < 12;
    Frame frame = blank ? blankFrame(i) : frames[i];
    frame.timestamp = frames[i].timestamp;
    const FrameResult r = tracker->track(frame);
    const std::string at = "frame " + std::to_string(i) + " (" + toString(r.status) + ")";
    EXPECT_EQ(r.status == TrackStatus::Tracked, r.T_world_camera.has_value()) << at;
    // A blank frame shows nothing to pose it by: a pose would be made up (hybrid measured its
    // corners at their predictions, monoslam extrapolated two such frames).
    if (blank) {
      EXPECT_NE(r.status, TrackStatus::Tracked) << at << ": " << r.source;
    }
    if (r.status == TrackStatus::Tracked) {
      ++tracked;
      EXPECT_TRUE(kPoseSources.count(r.source)) << at << ": source '" << r.source << "'";
      EXPECT_TRUE(r.T_world_camera->isFinite()) << at;
    } else {
      EXPECT_FALSE(r.reason.empty()) << at;
    }
    for (const auto& [stage, cpu_ms] : r.stages) {
      EXPECT_TRUE(known.count(stage)) << at << ": stage '" << stage << "' is not in the registration's";
      EXPECT_TRUE(std::isfinite(cpu_ms) && cpu_ms >= 0) << at << ": " << stage << " " << cpu_ms;
      if (vocabulary.count(stage)) stages_seen.insert(stage);
    }
    for (const LatePose& late : r.late_poses) {
      EXPECT_LT(late.frame_index, i) << at;
      EXPECT_TRUE(late.T_world_camera.isFinite()) << at;
    }
  }
  EXPECT_GT(tracked, 0);
  EXPECT_EQ(stages_seen, vocabulary) << "every stage the registration names is timed in a run";
}

// A run of blank frames only never saw the board: finish() refuses it (the command line then
// exits 2), rather than a run with nothing posed passing for a result.
TEST_P(BackendContract, FinishRefusesARunThatNeverSawTheBoard) {
  const auto tracker = makeTracker();
  for (int i = 0; i < 5; ++i) tracker->track(blankFrame(i));
  EXPECT_THROW(tracker->finish(), InputError);
}

// The options as a config file holds them (SPEC section 4: one section per back-end).
void appendYaml(const nlohmann::json& object, const std::string& indent, std::string* out) {
  for (const auto& [key, value] : object.items()) {
    if (value.is_object()) {
      *out += indent + key + ":\n";
      appendYaml(value, indent + "  ", out);
    } else if (value.is_string()) {
      *out += indent + key + ": \"" + value.get<std::string>() + "\"\n";
    } else {
      *out += indent + key + ": " + value.dump() + "\n";
    }
  }
}

nlohmann::json readBack(const BackendRegistration& backend, const nlohmann::json& options, const std::string& path) {
  std::string yaml = "%YAML:1.0\n---\n" + backend.name + ":\n";
  appendYaml(options, "  ", &yaml);
  test::writeText(path, yaml);
  const YamlFile file(path);
  const auto read = backend.default_options();
  read->read(file.node(backend.name), path + ": " + backend.name);
  return read->toJson();
}

// Every leaf of the options tree with its path ("features.max_features").
void leaves(const nlohmann::json& object, const std::string& prefix, std::vector<std::string>* paths) {
  for (const auto& [key, value] : object.items()) {
    if (value.is_object()) {
      leaves(value, prefix + key + ".", paths);
    } else {
      paths->push_back(prefix + key);
    }
  }
}

// A value other than `value`, of its type: doubles to one that needs all 17 digits.
nlohmann::json changed(const nlohmann::json& value) {
  if (value.is_boolean()) return !value.get<bool>();
  if (value.is_number_integer()) return value.get<long long>() + 1;
  if (value.is_number_float()) return value.get<double>() * 1.5 + 0.1;
  if (value.is_string()) return value.get<std::string>() + "x";
  ADD_FAILURE() << "unexpected option type: " << value.dump();
  return value;
}

// "a.b.c" as the JSON pointer "/a/b/c".
nlohmann::json::json_pointer pointerOf(std::string path) {
  for (char& c : path)
    if (c == '.') c = '/';
  return nlohmann::json::json_pointer("/" + path);
}

// --set's text for a value.
std::string setText(const nlohmann::json& value) {
  return value.is_string() ? value.get<std::string>() : value.dump();
}

TEST_P(BackendContract, DefaultOptionsRoundTripThroughYaml) {
  TempDir dir;
  const nlohmann::json defaults = backend().default_options()->toJson();
  ASSERT_TRUE(defaults.is_object());
  ASSERT_FALSE(defaults.empty());
  EXPECT_EQ(readBack(backend(), defaults, dir.file("defaults.yaml")), defaults);
}

// Every option changed by --set (each to another value of its type), written as YAML and read
// back into fresh defaults: the same JSON, so no option is lost, misnamed or rounded.
TEST_P(BackendContract, ChangedOptionsRoundTripThroughYaml) {
  TempDir dir;
  const nlohmann::json defaults = backend().default_options()->toJson();
  std::vector<std::string> paths;
  leaves(defaults, "", &paths);
  ASSERT_FALSE(paths.empty());

  const auto options = backend().default_options();
  nlohmann::json expected = defaults;
  for (const std::string& path : paths) {
    const nlohmann::json::json_pointer pointer = pointerOf(path);
    expected[pointer] = changed(defaults[pointer]);
    options->set(path, setText(expected[pointer]), "test");
    // set() changed that one option to exactly the value given.
    EXPECT_EQ(options->toJson()[pointer], expected[pointer]) << path;
  }
  EXPECT_EQ(options->toJson(), expected);
  EXPECT_NE(expected, defaults);
  EXPECT_EQ(readBack(backend(), expected, dir.file("changed.yaml")), expected);
}

// A 20-frame run of tv1 through the command line (SPEC section 4): trajectory.txt, frames.csv,
// summary.json and map.ply are readable and agree with each other.
TEST_P(BackendRunContract, ShortRunWritesValidFiles) {
  TempDir out;
  const std::string out_dir = out.file("run");
  const auto run = test::runSlamcmp("run --backend " + GetParam().backend + " --mode " + GetParam().mode +
                                    " --sequence " + sequencePath() + " --out " + out_dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;

  const std::vector<FrameRow> rows = readFramesCsv(out_dir + "/frames.csv");
  ASSERT_EQ(static_cast<int>(rows.size()), kFrames);
  std::vector<const FrameRow*> tracked_rows;
  int lost = 0, initialising = 0, first_lost = -1;
  for (int i = 0; i < kFrames; ++i) {
    const FrameRow& row = rows[i];
    EXPECT_EQ(row.frame, i);
    if (row.status == TrackStatus::Tracked) {
      EXPECT_TRUE(kPoseSources.count(row.source)) << "frame " << i << ": status '" << row.source << "'";
      tracked_rows.push_back(&row);
    } else {
      EXPECT_TRUE(row.source.empty()) << "frame " << i;
      EXPECT_FALSE(row.reason.empty()) << "frame " << i << ": not posed, and no reason";
      lost += row.status == TrackStatus::Lost;
      initialising += row.status == TrackStatus::Initialising;
      if (row.status == TrackStatus::Lost && first_lost < 0) first_lost = i;
    }
  }
  ASSERT_FALSE(tracked_rows.empty()) << "nothing posed on tv1";

  // One trajectory line for each posed frame, at its timestamp (both written to 1e-6 s), and no
  // other: never a pose for a frame not posed.
  const Trajectory trajectory = readTrajectory(out_dir + "/trajectory.txt", TrajectoryFormat::Tum);
  ASSERT_EQ(trajectory.size(), tracked_rows.size());
  for (size_t k = 0; k < trajectory.size(); ++k) {
    EXPECT_NEAR(trajectory[k].timestamp, tracked_rows[k]->timestamp, 2e-6) << "frame " << tracked_rows[k]->frame;
    EXPECT_TRUE(trajectory[k].T_world_camera.isFinite());
  }

  std::ifstream summary_file(out_dir + "/summary.json");
  ASSERT_TRUE(summary_file.good());
  const nlohmann::json summary = nlohmann::json::parse(summary_file);
  EXPECT_EQ(summary.at("backend"), GetParam().backend);
  EXPECT_EQ(summary.at("mode"), GetParam().mode);
  EXPECT_EQ(summary.at("frames"), kFrames);
  EXPECT_EQ(summary.at("tracked"), static_cast<int>(tracked_rows.size()));
  EXPECT_EQ(summary.at("lost"), lost);
  EXPECT_EQ(summary.at("initialising"), initialising);
  EXPECT_EQ(summary.at("first_lost_frame"), first_lost < 0 ? nlohmann::json() : nlohmann::json(first_lost));
  // Scored against tv1's ground truth as `eval --json` says it: every posed frame, aligned or not.
  EXPECT_EQ(summary.at("matched"), static_cast<int>(tracked_rows.size()));
  EXPECT_TRUE(summary.at("alignment") == "none" || summary.at("alignment") == "sim3") << summary.at("alignment");

  const std::vector<MapPoint> map = readMapPly(out_dir + "/map.ply");
  for (const MapPoint& p : map) EXPECT_TRUE(p.p_world.allFinite()) << "point " << p.id;

  // keyframes.txt, from a back-end that keeps keyframes (cslam's combined mode): posed frames
  // only, in order, each a few millimetres at most from its frame's pose on tv1 (no gap there to
  // re-anchor; the window's refinement moves them within the board's accuracy).
  if (std::filesystem::exists(out_dir + "/keyframes.txt")) {
    const Trajectory keyframes = readTrajectory(out_dir + "/keyframes.txt", TrajectoryFormat::Tum);
    ASSERT_FALSE(keyframes.empty());
    size_t k = 0;
    for (const StampedPose& keyframe : keyframes) {
      while (k < trajectory.size() && trajectory[k].timestamp < keyframe.timestamp - 1e-6) ++k;
      ASSERT_LT(k, trajectory.size()) << "keyframe at " << keyframe.timestamp << " s: not a posed frame, or out of order";
      EXPECT_NEAR(trajectory[k].timestamp, keyframe.timestamp, 2e-6);
      EXPECT_LT((keyframe.T_world_camera.t() - trajectory[k].T_world_camera.t()).norm(), 0.005) << keyframe.timestamp;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Registry, BackendContract, ::testing::ValuesIn(everyBackendAndMode()), caseName);
INSTANTIATE_TEST_SUITE_P(Registry, BackendRunContract, ::testing::ValuesIn(everyBackendAndMode()), caseName);

}  // namespace
}  // namespace slamcmp
