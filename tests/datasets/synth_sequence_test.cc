// The written sequence folder reads back through core, and bad options are input errors.
#include <algorithm>
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/camera.h"
#include "core/sequence.h"
#include "core/target.h"
#include "datasets/room_scene.h"
#include "datasets/scene_yaml.h"
#include "datasets/synth_sequence.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

TEST(SynthSequence, WrittenFolderReadsBackThroughCore) {
  test::TempDir dir;
  SynthOptions options;
  options.preset = "tv3";
  options.frames = 4;
  options.seed = 2;
  options.noise = 1.0;
  options.supersample = 1;  // only the files are checked here
  writeSyntheticSequence(options, dir.path());

  Sequence seq = openSequence(dir.path());
  EXPECT_EQ(seq.kind, "tum");
  EXPECT_EQ(seq.frames->size(), 4);
  EXPECT_EQ(seq.image_size, cv::Size(640, 480));
  ASSERT_TRUE(seq.camera.has_value());
  const CameraModel expected = syntheticCamera();
  EXPECT_EQ(seq.camera->fx, expected.fx);
  EXPECT_EQ(seq.camera->cy, expected.cy);
  EXPECT_EQ(seq.camera->num_distortion, 5);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(seq.camera->distortion[k], expected.distortion[k]);
  ASSERT_TRUE(seq.target.has_value());
  EXPECT_EQ(seq.target->cols, 9);
  EXPECT_EQ(seq.target->rows, 6);
  EXPECT_EQ(seq.target->square_size, 0.04);

  // Ground truth: one pose per frame at the frame's timestamp, the motion's pose to the 1e-9 of
  // the file's digits.
  ASSERT_TRUE(seq.groundtruth.has_value());
  ASSERT_EQ(seq.groundtruth->size(), 4u);
  const CameraMotion motion("tv3", 2);
  Frame frame;
  for (int i = 0; seq.frames->next(&frame); ++i) {
    ASSERT_FALSE(frame.grey.empty());
    const StampedPose& gt = (*seq.groundtruth)[i];
    EXPECT_NEAR(frame.timestamp, i / kSyntheticFps, 1e-9);
    EXPECT_NEAR(gt.timestamp, frame.timestamp, 1e-9);
    const SE3 truth = motion.T_world_camera(frame.timestamp);
    EXPECT_LT((gt.T_world_camera.t() - truth.t()).norm(), 1e-8);
    EXPECT_LT(rotationAngle(gt.T_world_camera.R().transpose() * truth.R()), 1e-8);
  }

  // scene.yaml: the board and every surface of the scene, in the world frame.
  const SceneGeometry geometry = readSceneYaml(dir.file("scene.yaml"));
  const Scene scene = buildRoomScene(2);
  ASSERT_EQ(geometry.surfaces.size(), scene.surfaces.size());
  for (size_t k = 0; k < scene.surfaces.size(); ++k) {
    const TexturedRect& r = scene.surfaces[k];
    EXPECT_EQ(geometry.surfaces[k].name, r.name);
    EXPECT_LT((geometry.surfaces[k].origin - r.origin).norm(), 1e-9);
    EXPECT_LT((geometry.surfaces[k].edge_u - r.size_u * r.axis_u).norm(), 1e-9);
    EXPECT_LT((geometry.surfaces[k].edge_v - r.size_v * r.axis_v).norm(), 1e-9);
    EXPECT_LT((geometry.surfaces[k].normal - r.normal).norm(), 1e-9);
  }
  EXPECT_LT((geometry.board.origin - Vec3(-0.075, -0.075, 0)).norm(), 1e-9);
  EXPECT_TRUE(std::filesystem::exists(dir.file("info.yaml")));
}

// A preset at its own rate (handheld_rpy, 30 fps): frames and ground truth stamped i / 30 s, and
// info.yaml gives back the options it was rendered with, the rolling shutter among them.
TEST(SynthSequence, HandheldRpyIsStampedAtItsRateAndItsOptionsReadBack) {
  test::TempDir dir;
  SynthOptions options;
  options.preset = "handheld_rpy";
  options.frames = 3;
  options.rolling_shutter = 0.025;
  options.supersample = 1;
  writeSyntheticSequence(options, dir.path());
  Sequence seq = openSequence(dir.path());
  ASSERT_TRUE(seq.groundtruth.has_value());
  Frame frame;
  for (int i = 0; seq.frames->next(&frame); ++i) {
    EXPECT_NEAR(frame.timestamp, i / 30.0, 1e-6);
    EXPECT_NEAR((*seq.groundtruth)[i].timestamp, i / 30.0, 1e-6);
  }
  const std::optional<SynthOptions> read = readSynthInfo(dir.path());
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->preset, "handheld_rpy");
  EXPECT_EQ(read->rolling_shutter, 0.025);
}

TEST(SceneYaml, MalformedFilesAreInputErrors) {
  test::TempDir dir;
  const std::string path = dir.file("scene.yaml");
  const std::string surface =
      "{ name: s, origin: [0, 0, 0], edge_u: [1, 0, 0], edge_v: [0, 1, 0], normal: [0, 0, -1] }";
  test::writeText(path, "%YAML:1.0\nboard: " + surface + "\nsurfaces: [ " + surface + " ]\n");
  EXPECT_EQ(readSceneYaml(path).surfaces.size(), 1u);
  for (const std::string& text :
       {"%YAML:1.0\nsurfaces: [ " + surface + " ]\n",                      // no board
        "%YAML:1.0\nboard: " + surface + "\nsurfaces: []\n",              // no surfaces
        "%YAML:1.0\nboard: " + surface + "\nsurfaces: [ { name: s, origin: [0, 0] } ]\n"}) {
    test::writeText(path, text);
    EXPECT_THROW(readSceneYaml(path), InputError) << text;
  }
}

TEST(SynthSequence, BadOptionsAreInputErrors) {
  test::TempDir dir;
  const auto rejects = [&](auto change) {
    SynthOptions options;
    options.frames = 1;
    change(options);
    EXPECT_THROW(writeSyntheticSequence(options, dir.path()), InputError);
  };
  rejects([](SynthOptions& o) { o.preset = "tv9"; });
  rejects([](SynthOptions& o) { o.seed = -1; });
  rejects([](SynthOptions& o) { o.frames = -3; });
  rejects([](SynthOptions& o) { o.noise = -1; });
  rejects([](SynthOptions& o) { o.noise = std::nan(""); });
  rejects([](SynthOptions& o) { o.noise = 256; });
  rejects([](SynthOptions& o) { o.blur = -0.5; });
  rejects([](SynthOptions& o) { o.illumination = 1.5; });
  rejects([](SynthOptions& o) { o.supersample = 0; });
  rejects([](SynthOptions& o) { o.rolling_shutter = -0.01; });
  rejects([](SynthOptions& o) { o.rolling_shutter = std::nan(""); });
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));  // nothing written before the check
}

// A shorter render into the folder of a longer one: its rgb/ holds its own frames only (a user's
// own files there stay).
TEST(SynthSequence, ARenderReplacesAnEarlierOnesFrames) {
  test::TempDir dir;
  SynthOptions options;
  options.supersample = 1;
  options.frames = 4;
  writeSyntheticSequence(options, dir.path());
  test::writeText(dir.file("rgb/notes.png"), "the user's");
  options.frames = 2;
  writeSyntheticSequence(options, dir.path());
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir.file("rgb")))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"000000.png", "000001.png", "notes.png"}));
  // Not a render's folder (no info.yaml): a user's own numbered frames there stay.
  test::TempDir user;
  std::filesystem::create_directories(user.file("rgb"));
  test::writeText(user.file("rgb/000007.png"), "the user's");
  writeSyntheticSequence(options, user.path());
  EXPECT_TRUE(std::filesystem::exists(user.file("rgb/000007.png")));
}

// compare's trials render a synthetic sequence anew from its info.yaml only while the folder is
// that render: a copy resized, cut or given another board is not.
TEST(SynthSequence, AFolderChangedFromItsRenderIsToldApart) {
  for (const char* preset : {"tv1", "handheld_rpy", "roll_distortion"}) {
    test::TempDir dir;
    SynthOptions options;
    options.preset = preset;
    options.frames = 3;
    options.supersample = 1;
    options.seed = 4;
    writeSyntheticSequence(options, dir.path());
    const auto info = readSynthInfo(dir.path());
    ASSERT_TRUE(info.has_value());
    EXPECT_EQ(differenceFromItsRender(dir.path(), *info), "") << preset;
    if (std::string(preset) != "tv1") continue;
    std::string rgb;
    for (const std::string& line : test::readLines(dir.file("rgb.txt"))) rgb += line + "\n";
    test::writeText(dir.file("rgb.txt"), rgb.substr(0, rgb.rfind('\n', rgb.size() - 2) + 1));
    EXPECT_EQ(differenceFromItsRender(dir.path(), *info), "rgb.txt lists 2 frames, info.yaml 3");
    test::writeText(dir.file("rgb.txt"), rgb);
    ChessboardTarget target = readTargetYaml(dir.file("target.yaml"), true);
    target.square_size *= 2;
    writeTargetYaml(dir.file("target.yaml"), target);
    EXPECT_EQ(differenceFromItsRender(dir.path(), *info), "target.yaml is not the rendered board");
    target.square_size /= 2;
    writeTargetYaml(dir.file("target.yaml"), target);
    cv::Mat image = cv::imread(dir.file("rgb/000000.png"), cv::IMREAD_UNCHANGED), half;
    cv::resize(image, half, cv::Size(320, 240));
    cv::imwrite(dir.file("rgb/000000.png"), half);
    EXPECT_EQ(differenceFromItsRender(dir.path(), *info), "its images are not the render's size");
    CameraModel camera = readCameraYaml(dir.file("camera.yaml"));
    camera.fx *= 0.5;
    writeCameraYaml(dir.file("camera.yaml"), camera);
    EXPECT_EQ(differenceFromItsRender(dir.path(), *info), "camera.yaml is not the preset's camera");
  }
}

TEST(SynthSequence, UnwritableOutputIsAnInputError) {
  test::TempDir dir;
  test::writeText(dir.file("a_file"), "x");
  SynthOptions options;
  options.frames = 1;
  EXPECT_THROW(writeSyntheticSequence(options, dir.file("a_file") + "/seq"), InputError);
}

TEST(SynthSequence, FrameCountDefaultsToThePresetLength) {
  SynthOptions options;
  for (const auto& [preset, frames] : {std::pair{"tv1", 337}, {"tv2", 335}, {"tv3", 318}, {"tv4", 402}}) {
    options.preset = preset;
    EXPECT_EQ(options.frameCount(), frames);
  }
  options.frames = 10000;
  EXPECT_EQ(options.frameCount(), 10000);
}

}  // namespace
}  // namespace slamcmp
