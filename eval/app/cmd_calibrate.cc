#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>

#include "core/camera.h"
#include "core/chessboard.h"
#include "core/error.h"
#include "core/sequence.h"
#include "core/target.h"
#include "core/text_file.h"
#include "core/yaml.h"
#include "core/self_calibration.h"
#include "eval/app/commands.h"

namespace slamcmp {

void addCalibrateCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("calibrate",
                                 "calibrate the camera (intrinsics and distortion, Zhang's method) from "
                                 "the chessboard views of a sequence, video or image folder; writes camera.yaml");
  struct Args {
    std::string sequence, target, out, subpixel = SubpixelCornerOptions{}.method;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--sequence", args->sequence, "sequence folder (rgb.txt), image folder or video file")->check(nonEmptyPath())->required();
  cmd->add_option("--target", args->target, "target.yaml of the chessboard")->check(nonEmptyPath())->required();
  cmd->add_option("--out", args->out, "camera.yaml to write")->check(nonEmptyPath())->required();
  cmd->add_option("--subpixel", args->subpixel,
                  "corner refinement: opencv (cv::cornerSubPix) or gradient (core/subpixel_corner.h: Bouguet's "
                  "images 0.40 px against 0.48)")
      ->check(CLI::IsMember(SubpixelCornerOptions::kMethods))
      ->capture_default_str();
  cmd->callback([args] {
    // --out names the camera file to write: a YAML file, and an existing file that is not one (the
    // target, rgb.txt, an image) would be replaced by it, and the sequence broken. A camera file
    // whose values are refused (a folding lens, another image size) is one, to be replaced.
    const std::string extension = lowerExtension(args->out);
    if (extension != ".yaml" && extension != ".yml")
      throw InputError("--out", args->out + ": a camera file is written as YAML: name it .yaml or .yml");
    std::error_code unreadable;  // a path that cannot be looked at: the write below says so
    if (std::filesystem::exists(args->out, unreadable)) {
      bool camera_file = false;
      try {
        camera_file = YamlFile(args->out).has("camera_matrix");
      } catch (const std::exception&) {  // InputError; OpenCV's parser on a binary file
      }
      if (!camera_file)
        throw InputError("--out", args->out + " exists and is not a camera file: calibrate would overwrite it");
    }
    SequenceOpenOptions open;
    open.read_camera = false;
    open.target_path = args->target;
    open.allow_symmetric_target = true;  // intrinsics do not depend on the board's orientation
    Sequence seq = openSequence(args->sequence, open);
    SelfCalibrationOptions options;
    if (seq.kind == "images") {
      // A folder of photos is a set of chosen views: keep them all.
      options.min_view_change = 0;
      options.max_views = std::max(options.max_views, seq.frames->size());
    }
    ChessboardDetectorOptions detector;
    detector.subpixel.method = args->subpixel;
    const CalibrationResult r =
        calibrateFromFrames(*seq.frames, *seq.target, seq.image_size, options, args->sequence, detector);
    if (const auto folder = std::filesystem::path(args->out).parent_path(); !folder.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(folder, ec);
      if (ec) throw InputError(args->out, "its folder cannot be created: " + ec.message());
    }
    writeCameraYaml(args->out, r.camera, r.rms_px);
    std::cout << "calibrated from " << r.views << " views: fx " << r.camera.fx << " fy " << r.camera.fy << " cx "
              << r.camera.cx << " cy " << r.camera.cy << ", rms " << r.rms_px << " px"
              << (r.note.empty() ? "" : " (" + r.note + ")") << " -> " << args->out << "\n";
  });
}

}  // namespace slamcmp
