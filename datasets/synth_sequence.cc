#include "datasets/synth_sequence.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/options.h"
#include "core/progress.h"
#include "core/target.h"
#include "core/text_file.h"
#include "core/trajectory.h"
#include "core/yaml.h"
#include "datasets/room_scene.h"
#include "datasets/scene_renderer.h"
#include "datasets/scene_yaml.h"

namespace slamcmp {

namespace fs = std::filesystem;

void SynthOptions::check() const {
  findMotionPreset(preset);
  if (seed < 0) throw InputError("--seed", "must be >= 0, got " + std::to_string(seed));
  // A bound on what one command may write: 100000 frames are about 15 GB of PNG.
  constexpr int kMaxFrames = 100000;
  if (frames < 0 || frames > kMaxFrames)
    throw InputError("--frames", "must be in [1, " + std::to_string(kMaxFrames) + "] (or left out for the preset's), got " +
                                     std::to_string(frames));
  // Beyond the grey scale's span the 8-bit conversion overflows (1e10 gave black frames).
  if (!(noise >= 0) || !(noise <= 255)) throw InputError("--noise", "must be in [0, 255] grey levels");
  if (!(blur >= 0) || !(blur <= 100)) throw InputError("--blur", "must be in [0, 100] pixels");
  if (!(lens_blur >= 0) || !(lens_blur <= 5)) throw InputError("--lens-blur", "must be in [0, 5] pixels");
  if (!(illumination >= 0) || !(illumination < 1))
    throw InputError("--illumination", "must be in [0, 1)");
  if (!(rolling_shutter >= 0) || !(rolling_shutter <= 1))
    throw InputError("--rolling-shutter", "must be in [0, 1] seconds");
  if (supersample < 1 || supersample > 8)
    throw InputError("--supersample", "must be in [1, 8], got " + std::to_string(supersample));
}

int SynthOptions::frameCount() const { return frames > 0 ? frames : findMotionPreset(preset).frames; }

namespace {

// Frame i's image, relative to the sequence folder, and its line in rgb.txt.
std::string frameImage(int i) {
  char name[32];
  std::snprintf(name, sizeof name, "rgb/%06d.png", i);
  return name;
}

std::string rgbListLine(int i, double fps) {
  char line[64];
  std::snprintf(line, sizeof line, "%.6f %s", i / fps, frameImage(i).c_str());
  return line;
}

// A file name frameImage gives (six digits and .png): synth's own frames in rgb/.
bool isFrameImageName(const std::string& name) {
  return name.size() == 10 && name.compare(6, 4, ".png") == 0 && name.find_first_not_of("0123456789") == 6;
}

void writeTextFile(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw InputError(path.string(), "cannot be written");
}

}  // namespace

std::optional<SynthOptions> readSynthInfo(const std::string& sequence_dir) {
  const fs::path info = fs::path(sequence_dir) / "info.yaml";
  std::error_code ec;
  if (!fs::is_regular_file(info, ec)) return std::nullopt;
  // info.yaml is YAML without OpenCV's "%YAML:1.0" first line (a comment says what it is).
  const YamlFile yaml(info.string(), YamlFile::Header::Optional);
  SynthOptions options;
  readOptions(yaml.root(), info.string(), options);
  try {
    options.check();
  } catch (const InputError& e) {
    throw InputError(info.string(), e.what());
  }
  return options;
}

std::string differenceFromItsRender(const std::string& sequence_dir, const SynthOptions& info) {
  const fs::path dir(sequence_dir);
  try {
    const CameraModel rendered = syntheticCamera(info.preset);
    const CameraModel camera = readCameraYaml((dir / "camera.yaml").string());
    // As written and read back: to the text's precision.
    const auto same = [](double a, double b) { return std::abs(a - b) <= 1e-9 * (1 + std::abs(b)); };
    bool same_camera = camera.width == rendered.width && camera.height == rendered.height && same(camera.fx, rendered.fx) &&
                       same(camera.fy, rendered.fy) && same(camera.cx, rendered.cx) && same(camera.cy, rendered.cy) &&
                       camera.num_distortion == rendered.num_distortion;
    for (int k = 0; k < rendered.num_distortion; ++k) same_camera = same_camera && same(camera.distortion[k], rendered.distortion[k]);
    if (!same_camera) return "camera.yaml is not the preset's camera";
    const ChessboardTarget target = readTargetYaml((dir / "target.yaml").string(), true);
    const ChessboardTarget board = syntheticTarget();
    if (target.cols != board.cols || target.rows != board.rows || target.square_size != board.square_size)
      return "target.yaml is not the rendered board";
    const double fps = findMotionPreset(info.preset).fps;
    std::vector<std::string> lines;  // rgb.txt's, but its comments
    std::ifstream list = openTextFile((dir / "rgb.txt").string());
    for (std::string line; std::getline(list, line);)
      if (!line.empty() && line[0] != '#') lines.push_back(line);
    if (static_cast<int>(lines.size()) != info.frameCount())
      return "rgb.txt lists " + std::to_string(lines.size()) + " frames, info.yaml " + std::to_string(info.frameCount());
    for (size_t i = 0; i < lines.size(); ++i)
      if (lines[i] != rgbListLine(static_cast<int>(i), fps))
        return "rgb.txt's line for frame " + std::to_string(i) + " is not the render's";
    const cv::Mat first = cv::imread((dir / frameImage(0)).string(), cv::IMREAD_UNCHANGED);
    if (first.cols != rendered.width || first.rows != rendered.height) return "its images are not the render's size";
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void writeSyntheticSequence(const SynthOptions& options, const std::string& out_dir) {
  options.check();
  const fs::path out(out_dir);
  std::error_code ec;
  fs::create_directories(out / "rgb", ec);
  if (ec || !fs::is_directory(out / "rgb"))
    throw InputError(out_dir, "cannot create the output folder: " + ec.message());

  const CameraModel camera = syntheticCamera(options.preset);
  const Scene scene = buildRoomScene(static_cast<std::uint64_t>(options.seed));
  const CameraMotion motion(options.preset, static_cast<std::uint64_t>(options.seed));
  const MotionPreset& preset = findMotionPreset(options.preset);
  // An earlier sequence's lists and frames go first: an interruption must not leave them beside
  // this one's files, nor a longer render's frames beyond this one's in rgb/ (only in an earlier
  // render's folder, its info.yaml, and by synth's names: a user's numbered frames stay).
  const bool earlier_render = fs::is_regular_file(out / "info.yaml", ec);
  for (const char* list : {"rgb.txt", "groundtruth.txt"}) fs::remove(out / list, ec);
  std::vector<fs::path> old_frames;
  if (earlier_render) {
    for (fs::directory_iterator it(out / "rgb", ec), end; !ec && it != end; it.increment(ec)) {
      if (isFrameImageName(it->path().filename().string())) old_frames.push_back(it->path());
    }
  }
  for (const fs::path& frame : old_frames) fs::remove(frame, ec);
  writeCameraYaml((out / "camera.yaml").string(), camera);
  writeTargetYaml((out / "target.yaml").string(), scene.target);
  writeSceneYaml((out / "scene.yaml").string(), scene);
  // info.yaml records the options, frames included: compare --trials renders each trial from it.
  const auto writeInfo = [&](const SynthOptions& written) {
    std::ostringstream info;
    info << "# slamcmp synth: a synthetic sequence, " << preset.description << ", " << preset.fps << " fps\n"
         << describeOptions(written);
    writeTextFile(out / "info.yaml", info.str());
  };
  writeInfo(options);

  const SceneRenderer renderer(camera, scene, options.supersample);
  const FrameEffects effects{options.lens_blur, options.noise, options.blur, options.illumination,
                             options.rolling_shutter};
  const auto pose_at = [&motion](double t) { return motion.T_world_camera(t); };
  const int frames = options.frameCount();
  Trajectory groundtruth;
  std::string rgb_list =
      "# synthetic sequence: timestamp image (slamcmp synth --preset " + options.preset + ")\n";
  Progress progress("synth " + options.preset, frames);
  const auto writeLists = [&] {
    writeTextFile(out / "rgb.txt", rgb_list);
    writeTumTrajectory((out / "groundtruth.txt").string(), groundtruth);
  };
  for (int i = 0; i < frames; ++i) {
    if (interruptRequested()) {  // what is rendered stays a sequence of its own, and says how long
      if (groundtruth.empty()) {
        fs::remove(out / "info.yaml", ec);  // it would describe frames that are not there
        throw Interrupted("interrupted before the first frame: " + out.string() + " holds no sequence");
      }
      SynthOptions rendered = options;
      rendered.frames = i;
      writeInfo(rendered);
      writeLists();
      throw Interrupted("interrupted: " + out.string() + " holds the first " + std::to_string(i) + " of " +
                        std::to_string(frames) + " frames");
    }
    const double t = i / preset.fps;
    const cv::Mat image = renderer.renderFrame(pose_at, t, 1.0 / preset.fps, effects,
                                               static_cast<std::uint64_t>(options.seed), i);
    const fs::path image_path = out / frameImage(i);
    bool written = false;
    try {
      written = cv::imwrite(image_path.string(), image, {cv::IMWRITE_PNG_COMPRESSION, 1});
    } catch (const cv::Exception&) {
    }
    if (!written) throw InputError(image_path.string(), "cannot be written");
    rgb_list += rgbListLine(i, preset.fps) + "\n";
    groundtruth.push_back({t, motion.T_world_camera(t)});
    progress.update(i + 1);
  }
  progress.finish();
  writeLists();
}

}  // namespace slamcmp
