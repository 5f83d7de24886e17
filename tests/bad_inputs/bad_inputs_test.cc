// The corpus of bad inputs (issue 7, SPEC section 4): every case is answered by the slamcmp binary
// with exit code 2 and exactly one line on stderr naming the file (and the line or field) and the
// problem. Each case builds its inputs in a fresh folder: a small valid sequence spoilt in one way.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/media_plugin.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

using test::TempDir;
using test::writeText;

constexpr int kWidth = 160, kHeight = 120;

const char* kCameraYaml =
    "%YAML:1.0\n---\nimage_width: 160\nimage_height: 120\n"
    "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
    "   data: [ 150., 0., 79.5, 0., 150., 59.5, 0., 0., 1. ]\n"
    "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n"
    "   data: [ -0.1, 0.02, 0., 0., 0. ]\n";

std::string targetYaml(const std::string& cols, const std::string& rows, const std::string& square) {
  return "%YAML:1.0\n---\ntype: chessboard\ninner_corners_cols: " + cols + "\ninner_corners_rows: " + rows +
         "\nsquare_size: " + square + "\n";
}

void writeImage(const std::string& path, int width = kWidth, int height = kHeight) {
  cv::Mat grey(height, width, CV_8UC1);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) grey.at<uint8_t>(y, x) = static_cast<uint8_t>((x * 7 + y * 3) % 256);
  ASSERT_TRUE(cv::imwrite(path, grey)) << path;
}

// The bytes of a file ("" if it cannot be read).
std::string readBytes(const std::string& path) {
  std::string data;
  if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
    char buf[4096];
    for (size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) data.append(buf, n);
    std::fclose(f);
  }
  return data;
}

// The first `bytes` bytes of `path`, written back over it (a copy cut short).
void truncateFile(const std::string& path, size_t bytes) {
  const std::string data = readBytes(path);
  ASSERT_GT(data.size(), bytes) << path;
  writeText(path, data.substr(0, bytes));
}

// A PNG spoilt inside, not cut short: a byte of its image data flipped (libpng: "IDAT: CRC error"),
// or a text chunk with a wrong checksum inserted before the image data (libpng only warns).
void corruptPngData(const std::string& path) {
  std::string data = readBytes(path);
  const size_t idat = data.find("IDAT");
  ASSERT_NE(idat, std::string::npos) << path;
  data[idat + 20] = static_cast<char>(data[idat + 20] ^ 0xFF);
  writeText(path, data);
}
void insertPngTextChunkWithBadCrc(const std::string& path) {
  std::string data = readBytes(path);
  const size_t idat = data.find("IDAT");
  ASSERT_NE(idat, std::string::npos) << path;
  data.insert(idat - 4, std::string("\0\0\0\3tEXtk\0v\0\0\0\0", 15));
  writeText(path, data);
}

// A valid TUM-style sequence of three frames in `dir`: rgb/, rgb.txt, camera.yaml, target.yaml,
// groundtruth.txt. Cases then spoil one thing.
void writeSequence(const std::string& dir) {
  std::filesystem::create_directories(dir + "/rgb");
  std::string list = "# timestamp path\n";
  for (int i = 0; i < 3; ++i) {
    writeImage(dir + "/rgb/" + std::to_string(i) + ".png");
    list += std::to_string(0.1 * i) + " rgb/" + std::to_string(i) + ".png\n";
  }
  writeText(dir + "/rgb.txt", list);
  writeText(dir + "/camera.yaml", kCameraYaml);
  writeText(dir + "/target.yaml", targetYaml("9", "6", "0.04"));
  writeText(dir + "/groundtruth.txt", "0.0 0 0 -1 0 0 0 1\n0.1 0.01 0 -1 0 0 0 1\n0.2 0.02 0 -1 0 0 0 1\n");
}

const char* kGroundTruth =
    "# timestamp tx ty tz qx qy qz qw\n0.0 0 0 0 0 0 0 1\n0.1 0.1 0 0 0 0 0 1\n"
    "0.2 0.2 0.1 0 0 0 0 1\n0.3 0.3 0 0.1 0 0 0 1\n";

// What one case runs and what its one line must name.
struct Invocation {
  std::string args;
  std::vector<std::string> must_mention;
};

struct BadCase {
  std::string name;
  std::function<Invocation(const TempDir&)> make;
};

std::ostream& operator<<(std::ostream& os, const BadCase& c) { return os << c.name; }

// slamcmp run on the sequence in tmp/seq, after `spoil` changed it.
// board_partial's first 80 frames (its board slides square on in front of the camera) without
// camera.yaml: a run self-calibrates from them.
std::string boardPartialWithoutCamera(const TempDir& tmp) {
  const std::string seq = tmp.file("seq");
  EXPECT_EQ(test::runSlamcmp("synth --preset board_partial --frames 80 --supersample 1 --out " + seq).exit_code, 0);
  std::filesystem::remove(seq + "/camera.yaml");
  return seq;
}

BadCase runCase(const std::string& name, std::function<void(const std::string& seq)> spoil,
                std::vector<std::string> mention, const std::string& extra_args = "") {
  return {name, [=](const TempDir& tmp) {
            const std::string seq = tmp.file("seq");
            writeSequence(seq);
            spoil(seq);
            std::vector<std::string> m;
            for (const auto& s : mention) m.push_back(s.rfind("seq/", 0) == 0 ? tmp.file(s) : s);
            std::string args = extra_args;  // "{seq}" stands for the sequence folder
            if (const auto at = args.find("{seq}"); at != std::string::npos) args.replace(at, 5, seq);
            const std::string backend = args.find("--backend") == std::string::npos ? "--backend cslam " : "";
            return Invocation{"run " + backend + "--sequence " + seq + " --out " + tmp.file("out") + " " + args, m};
          }};
}

// slamcmp run with a spoilt rgb.txt.
BadCase rgbCase(const std::string& name, const std::string& list, const std::string& mention) {
  return runCase(name, [list](const std::string& seq) { writeText(seq + "/rgb.txt", list); },
                 {"seq/rgb.txt" + mention});
}

// slamcmp run with a spoilt camera.yaml or target.yaml.
BadCase yamlCase(const std::string& name, const std::string& file, const std::string& text,
                 const std::string& field) {
  return runCase(name, [file, text](const std::string& seq) { writeText(seq + "/" + file, text); },
                 {"seq/" + file, field});
}

// slamcmp run of `backend` with --config holding `text`; the line names the file, `field` and
// anything in `more`.
BadCase configCase(const std::string& name, const std::string& text, const std::string& field,
                   const std::string& backend = "cslam", const std::vector<std::string>& more = {}) {
  return {name, [=](const TempDir& tmp) {
            writeSequence(tmp.file("seq"));
            writeText(tmp.file("run.yaml"), text);
            std::vector<std::string> mention{tmp.file("run.yaml"), field};
            mention.insert(mention.end(), more.begin(), more.end());
            return Invocation{"run --backend " + backend + " --sequence " + tmp.file("seq") + " --out " +
                                  tmp.file("out") + " --config " + tmp.file("run.yaml"),
                              mention};
          }};
}

// slamcmp compare of `backends` with --config holding `text`; the line names the file and `what`.
BadCase compareConfigCase(const std::string& name, const std::string& text, const std::string& backends,
                          const std::string& what) {
  return {name, [=](const TempDir& tmp) {
            writeSequence(tmp.file("seq"));
            writeText(tmp.file("c.yaml"), text);
            return Invocation{"compare --sequence " + tmp.file("seq") + " --backends " + backends + " --config " +
                                  tmp.file("c.yaml") + " --out " + tmp.file("c"),
                              {tmp.file("c.yaml"), what}};
          }};
}

// An option bounded by the tiny sequence's 160x120 images, set too large in a --config.
BadCase imageBoundCase(const std::string& name, const std::string& backend, const std::string& yaml_path,
                       const std::string& value, const std::string& limit) {
  // "search.source_size" -> "search:\n    source_size: V"
  std::string yaml = "%YAML:1.0\n---\n" + backend + ":\n", indent = "  ";
  for (size_t start = 0;;) {
    const size_t dot = yaml_path.find('.', start);
    yaml += indent + yaml_path.substr(start, dot - start) + ":" + (dot == std::string::npos ? " " + value + "\n" : "\n");
    if (dot == std::string::npos) break;
    indent += "  ";
    start = dot + 1;
  }
  return configCase(name, yaml, backend + "." + yaml_path,  backend,
                    {"must be at most " + limit + " px for 160x120 images, got " + value});
}

// slamcmp eval of an estimate holding `text` (named `file`) against a valid ground truth.
BadCase evalCase(const std::string& name, const std::string& file, const std::string& text,
                 const std::string& mention) {
  return {name, [=](const TempDir& tmp) {
            writeText(tmp.file("gt.txt"), kGroundTruth);
            writeText(tmp.file(file), text);
            return Invocation{"eval --groundtruth " + tmp.file("gt.txt") + " --estimate " + tmp.file(file),
                              {tmp.file(file) + mention}};
          }};
}

std::string camera(const std::string& matrix_data, const std::string& distortion) {
  return "%YAML:1.0\n---\nimage_width: 160\nimage_height: 120\n"
         "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ " +
         matrix_data + " ]\ndistortion_coefficients: [ " + distortion + " ]\n";
}
const char* kK = "150., 0., 79.5, 0., 150., 59.5, 0., 0., 1.";

// A camera.yaml with `fx fy cx cy` (160x120 images).
std::string cameraWithIntrinsics(const std::string& fx, const std::string& fy, const std::string& cx,
                                 const std::string& cy) {
  return camera(fx + ", 0., " + cx + ", 0., " + fy + ", " + cy + ", 0., 0., 1.", "0, 0, 0, 0");
}

// kCameraYaml with the `dt` of its camera_matrix (first) or distortion_coefficients (second) set.
std::string cameraWithDt(bool distortion, const std::string& dt) {
  std::string text = kCameraYaml;
  size_t at = text.find("dt: d");
  if (distortion) at = text.find("dt: d", at + 1);
  return text.replace(at, 5, "dt: " + dt);
}

// slamcmp run on a EuRoC folder in tmp whose cam0/sensor.yaml holds these values; the line names
// sensor.yaml's `field` and says `what`.
BadCase eurocSensorYamlCase(const std::string& name, const std::string& t_bs, const std::string& resolution,
                            const std::string& intrinsics, const std::string& field, const std::string& what,
                            const std::string& distortion = "0, 0, 0, 0") {
  return {name, [=](const TempDir& tmp) {
            const std::string cam = tmp.file("mav0/cam0");
            std::filesystem::create_directories(cam + "/data");
            writeImage(cam + "/data/1.png");
            writeImage(cam + "/data/2.png");
            writeText(cam + "/data.csv", "#timestamp [ns],filename\n1000000000,1.png\n1050000000,2.png\n");
            writeText(cam + "/sensor.yaml",
                      "%YAML:1.0\nsensor_type: camera\nT_BS:\n  cols: 4\n  rows: 4\n  data: [" + t_bs +
                          "]\nresolution: [" + resolution + "]\nintrinsics: [" + intrinsics +
                          "]\ndistortion_coefficients: [" + distortion + "]\n");
            return Invocation{"run --backend cslam --sequence " + tmp.path() + " --out " + tmp.file("o"),
                              {cam + "/sensor.yaml: " + field, what}};
          }};
}
const char* kIdentity4 = "1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1";
BadCase eurocSensorCase(const std::string& name, const std::string& t_bs) {
  return eurocSensorYamlCase(name, t_bs, "160, 120", "150, 150, 79.5, 59.5", "T_BS", "not a rotation");
}
BadCase eurocIntrinsicsCase(const std::string& name, const std::string& intrinsics, const std::string& what) {
  return eurocSensorYamlCase(name, kIdentity4, "160, 120", intrinsics, "intrinsics", what);
}
BadCase eurocResolutionCase(const std::string& name, const std::string& resolution) {
  return eurocSensorYamlCase(name, kIdentity4, resolution, "150, 150, 79.5, 59.5", "resolution",
                             "must be two whole numbers of pixels");
}

// A command line whose option `option` is given as '' (an unset shell variable): a usage error.
BadCase emptyOptionCase(const std::string& name, const std::string& command, const std::string& option) {
  return {name, [=](const TempDir& tmp) {
            writeSequence(tmp.file("seq"));
            std::string args = command;
            for (size_t at; (at = args.find("{seq}")) != std::string::npos;) args.replace(at, 5, tmp.file("seq"));
            for (size_t at; (at = args.find("{tmp}")) != std::string::npos;) args.replace(at, 5, tmp.path());
            return Invocation{args, {option, "is empty"}};
          }};
}

// A symbolic link at `link` (inside the sequence) pointing to itself.
void symlinkLoop(const std::string& link) {
  std::filesystem::remove(link);
  std::filesystem::create_symlink(link, link);
}

std::vector<BadCase> cases() {
  const std::string k3 = "0.0 rgb/0.png\n0.1 rgb/1.png\n0.2 rgb/2.png\n";
  return {
      // The sequence itself.
      {"MissingSequence",
       [](const TempDir& tmp) {
         return Invocation{"run --backend cslam --sequence " + tmp.file("nope") + " --out " + tmp.file("o"),
                           {tmp.file("nope"), "does not exist"}};
       }},
      {"EmptyFolder",
       [](const TempDir& tmp) {
         return Invocation{"run --backend cslam --sequence " + tmp.path() + " --out " + tmp.file("o"),
                           {tmp.path(), "no rgb.txt and no image files"}};
       }},
      // rgb.txt lines.
      rgbCase("RgbEmpty", "", ": lists no frames"),
      rgbCase("RgbOnlyComments", "# nothing\n\n   \n", ": lists no frames"),
      // Found by the reliability probe: a folder was said to list no frames (as ground truth's reader says).
      runCase("RgbListIsAFolder",
              [](const std::string& seq) {
                std::filesystem::remove(seq + "/rgb.txt");
                std::filesystem::create_directory(seq + "/rgb.txt");
              },
              {"seq/rgb.txt: is a folder, not a text file"}),
      rgbCase("RgbMissingPath", "0.0 rgb/0.png\n0.1\n", ":2: expected 'timestamp path'"),
      rgbCase("RgbExtraField", "0.0 rgb/0.png 7\n", ":1: expected 'timestamp path', found more fields"),
      rgbCase("RgbTimestampNotNumber", "zero rgb/0.png\n", ":1: timestamp 'zero' is not a number"),
      rgbCase("RgbTimestampNaN", "0.0 rgb/0.png\nnan rgb/1.png\n", ":2: timestamp is not finite"),
      rgbCase("RgbTimestampInfinite", "0.0 rgb/0.png\ninf rgb/1.png\n", ":2: timestamp is not finite"),
      // Found by the reliability probe: 2e300 was accepted and cut trajectory.txt's lines at 255 characters.
      rgbCase("RgbTimestampHuge", "0.0 rgb/0.png\n2e300 rgb/1.png\n",
              ":2: timestamp 2e+300 is not plausible as seconds (beyond 1e+11 s)"),
      rgbCase("RgbTimestampNanoseconds", "1403715572212143183 rgb/0.png\n",
              ":1: timestamp 1.40372e+18 is not plausible as seconds (beyond 1e+11 s): it looks like nanoseconds"),
      rgbCase("RgbTimestampsOutOfOrder", "0.1 rgb/0.png\n0.0 rgb/1.png\n", ":2: timestamp goes back in time"),
      rgbCase("RgbTimestampDuplicated", "0.1 rgb/0.png\n0.1 rgb/1.png\n", ":2: duplicate timestamp"),
      rgbCase("RgbTruncatedLastLine", k3.substr(0, k3.size() - 8), ":3: image"),
      rgbCase("RgbImageMissing", "0.0 rgb/0.png\n0.1 rgb/7.png\n", ":2: image"),
      // Found by fuzz_sequence_list: a name too long for the file system threw filesystem_error (exit 1).
      rgbCase("RgbImageNameTooLong", "0.0 " + std::string(300, 'g') + ".png\n", ":1: image"),
      rgbCase("RgbBinaryGarbage", std::string("\x89\x00\xff\xfe garbage\n", 13), ":1:"),
      // Images.
      runCase("FirstImageUnreadableBytes",
              [](const std::string& seq) { writeText(seq + "/rgb/0.png", "this is not a PNG"); },
              {"seq/rgb/0.png", "cannot be decoded"}),
      runCase("FirstImageEmptyFile", [](const std::string& seq) { writeText(seq + "/rgb/0.png", ""); },
              {"seq/rgb/0.png", "cannot be decoded"}),
      runCase("FirstImageTruncatedPng", [](const std::string& seq) { truncateFile(seq + "/rgb/0.png", 300); },
              {"seq/rgb/0.png", "cannot be decoded"}),
      runCase("FirstImageTruncatedJpeg",
              [](const std::string& seq) {
                cv::Mat noise(kHeight, kWidth, CV_8UC1);
                cv::randu(noise, 0, 255);
                ASSERT_TRUE(cv::imwrite(seq + "/rgb/0.jpg", noise));
                truncateFile(seq + "/rgb/0.jpg", 2000);
                writeText(seq + "/rgb.txt", "0.0 rgb/0.jpg\n0.1 rgb/1.png\n");
              },
              {"seq/rgb/0.jpg", "cannot be decoded"}),
      runCase("ImagesOfMixedSizes", [](const std::string& seq) { writeImage(seq + "/rgb/1.png", 80, 60); },
              {"seq/rgb/1.png", "80x60"}),
      {"ImageFolderOfMixedSizes",
       [](const TempDir& tmp) {
         writeImage(tmp.file("a.png"));
         writeImage(tmp.file("b.png"), 100, 100);
         writeText(tmp.file("target.yaml"), targetYaml("9", "6", "0.04"));
         return Invocation{"run --backend cslam --sequence " + tmp.path() + " --out " + tmp.file("o"),
                           {tmp.file("b.png"), "100x100"}};
       }},
      // camera.yaml.
      yamlCase("CameraEmpty", "camera.yaml", "", "is empty"),
      yamlCase("CameraTruncated", "camera.yaml", std::string(kCameraYaml).substr(0, 150), "YAML"),
      yamlCase("CameraNotOpenCvYaml", "camera.yaml", "image_width: 160\n", "%YAML:1.0"),
      yamlCase("CameraMissingField", "camera.yaml", "%YAML:1.0\n---\nimage_width: 160\n", "image_height"),
      yamlCase("CameraMatrixNaN", "camera.yaml",
               camera("150., 0., 79.5, 0., .nan, 59.5, 0., 0., 1.", "0, 0, 0, 0"), "camera_matrix"),
      yamlCase("CameraDistortionInfinite", "camera.yaml", camera(kK, "0, .inf, 0, 0"),
               "distortion_coefficients"),
      yamlCase("CameraDistortionCount", "camera.yaml", camera(kK, "0, 0, 0"), "distortion_coefficients"),
      yamlCase(
          "CameraMatrixHuge", "camera.yaml",
          "%YAML:1.0\n---\nimage_width: 160\nimage_height: 120\ncamera_matrix: !!opencv-matrix\n"
          "   rows: 100000\n   cols: 100000\n   dt: d\n   data: [ 1. ]\ndistortion_coefficients: [0,0,0,0]\n",
          "camera_matrix"),
      yamlCase("CameraOtherImageSize", "camera.yaml",
               std::string(kCameraYaml).replace(std::string(kCameraYaml).find("160"), 3, "320"),
               "320x120 but the images are 160x120"),
      {"CameraOptionMissing",
       [](const TempDir& tmp) {
         writeSequence(tmp.file("seq"));
         return Invocation{"run --backend cslam --sequence " + tmp.file("seq") + " --out " + tmp.file("o") +
                               " --camera " + tmp.file("no.yaml"),
                           {tmp.file("no.yaml"), "cannot be opened"}};
       }},
      // target.yaml: board sizes and values.
      yamlCase("BoardZero", "target.yaml", targetYaml("0", "0", "0.04"), "at least 3x3"),
      yamlCase("BoardLargerThanImages", "target.yaml", targetYaml("61", "40", "0.04"),
               "cannot be seen in 160x120 images"),
      yamlCase("BoardSquareNaN", "target.yaml", targetYaml("9", "6", ".nan"), "square_size"),
      yamlCase("BoardSquareNegative", "target.yaml", targetYaml("9", "6", "-0.04"), "square_size"),
      yamlCase("BoardCountNotInteger", "target.yaml", targetYaml("9.5", "6", "0.04"), "inner_corners_cols"),
      yamlCase(
          "BoardWrongType", "target.yaml",
          "%YAML:1.0\n---\ntype: circles\ninner_corners_cols: 9\ninner_corners_rows: 6\nsquare_size: 0.04\n",
          "type"),
      yamlCase("BoardMalformedYaml", "target.yaml", "%YAML:1.0\n---\ninner_corners_cols: [9\n", "YAML"),
      // Found by fuzz_camera_yaml and fuzz_target_yaml: a top level that is not a map made OpenCV
      // assert (exit 1, two lines).
      yamlCase("CameraTopLevelList", "camera.yaml", "%YAML:1.0\n- image_width\n- 160\n", "top level"),
      yamlCase("BoardTopLevelList", "target.yaml", "%YAML:1.0\n---\n- 9\n- 6\n", "top level"),
      // Found by fuzz_camera_yaml: OpenCV's parser threw std::length_error (exit 1).
      yamlCase("CameraParserLengthError", "camera.yaml",
               "%YAML:1.0\nhmerrix: !!openc-matrix\n   rows:03\n   :00000", "not valid YAML"),
      // Found by fuzz_target_yaml: OpenCV 4.6's parser looped forever; libyaml now refuses it first.
      yamlCase("BoardParserHang", "target.yaml", "%YAML:1.0\n---a:1\nb: --W-\n", "not valid YAML"),
      configCase("ConfigTopLevelList", "%YAML:1.0\n- cslam\n", "top level"),
      // The --config options file.
      configCase("ConfigMalformed", "%YAML:1.0\n---\ncslam: [1, 2\n", "YAML"),
      configCase("ConfigUnknownOption", "%YAML:1.0\n---\ncslam:\n  no_such_option: 3\n", "cslam.no_such_option"),
      configCase("ConfigWrongType", "%YAML:1.0\n---\ncslam:\n  board:\n    track: perhaps\n", "cslam.board.track"),
      configCase("ConfigNaN", "%YAML:1.0\n---\ncslam:\n  board:\n    max_grid_error_px: .nan\n",
                 "cslam.board.max_grid_error_px"),
      configCase("ConfigSectionNotMap", "%YAML:1.0\n---\ncslam: 3\n", "cslam"),
      // Found by the reliability probe: a typo in another back-end's section passed unseen until
      // that back-end ran (in a compare, after hours of the others).
      configCase("ConfigTypoInAnotherBackEndsSection", "%YAML:1.0\n---\ncslam:\n  lk_levels: 3\nmonoslam:\n  bogus: 1\n",
                 "monoslam.bogus", "cslam", {"unknown option"}),
      configCase("ConfigBadValueInAnotherBackEndsSection",
                 "%YAML:1.0\n---\nhybrid:\n  corners:\n    pixel_sigma: -1\n",
                 "hybrid.corners.pixel_sigma", "monoslam", {"must be positive"}),
      // Found by the reliability probe: OpenCV keeps an integer's low 32 bits (4294967305 was run as 9).
      configCase("ConfigIntegerWraps", "%YAML:1.0\n---\ncslam:\n  lk_window_px: 4294967305\n", "cslam.lk_window_px",
                 "cslam", {"4294967305 is out of range"}),
      configCase("ConfigIntegerJustOutOfRange", "%YAML:1.0\n---\ncslam:\n  lk_levels: 2147483648\n",
                 "cslam.lk_levels", "cslam", {"2147483648 is out of range"}),
      configCase("ConfigIntegerWrapsInHex", "%YAML:1.0\n---\ncslam:\n  lk_levels: 0x100000003\n", "cslam.lk_levels",
                 "cslam", {"0x100000003 is out of range"}),
      configCase("ConfigIntegerAsLargeReal", "%YAML:1.0\n---\ncslam:\n  lk_levels: 3.0e9\n", "cslam.lk_levels",
                 "cslam", {"must be an integer from -2e9 to 2e9"}),
      // Found by the reliability probe: a skew of 1e6 ran (435 m of error).
      yamlCase("CameraSkewHuge", "camera.yaml", camera("150., 1e6, 79.5, 0., 150., 59.5, 0., 0., 1.", "0, 0, 0, 0"),
               "camera_matrix: skew (K[0][1]) 1e+06 px is not plausible"),
      yamlCase("CameraSkewNegative", "camera.yaml", camera("150., -2., 79.5, 0., 150., 59.5, 0., 0., 1.", "0, 0, 0, 0"),
               "camera_matrix: skew (K[0][1]) -2 px is not plausible (expected at most 1.5 px"),
      yamlCase("CameraSizeWraps", "camera.yaml",
               std::string(kCameraYaml).replace(std::string(kCameraYaml).find("160"), 3, "4294967456"),
               "image_width: 4294967456 is out of range"),
      // Ground truth and EuRoC lists beside a sequence.
      runCase("GroundTruthShortLine",
              [](const std::string& seq) {
                writeText(seq + "/groundtruth.txt", "0.0 0 0 -1 0 0 0 1\n0.1 0 0\n");
              },
              {"seq/groundtruth.txt:2", "fields"}),
      // Found by the reliability probe: a folder was said to hold no pose (camera.yaml's reader says
      // what it is).
      runCase("GroundTruthIsAFolder",
              [](const std::string& seq) {
                std::filesystem::remove(seq + "/groundtruth.txt");
                std::filesystem::create_directory(seq + "/groundtruth.txt");
              },
              {"seq/groundtruth.txt: is a folder"}),
      runCase("GroundTruthTimestampHuge",
              [](const std::string& seq) {
                writeText(seq + "/groundtruth.txt", "0.0 0 0 -1 0 0 0 1\n1e300 0 0 -1 0 0 0 1\n");
              },
              {"seq/groundtruth.txt:2", "not plausible as seconds"}),
      {"EurocListWithoutComma",
       [](const TempDir& tmp) {
         std::filesystem::create_directories(tmp.file("mav0/cam0/data"));
         writeImage(tmp.file("mav0/cam0/data/1.png"));
         writeText(tmp.file("mav0/cam0/data.csv"), "#timestamp [ns],filename\n1000000000 1.png\n");
         return Invocation{"run --backend cslam --sequence " + tmp.path() + " --out " + tmp.file("o"),
                           {tmp.file("mav0/cam0/data.csv") + ":2", "timestamp,filename"}};
       }},
      {"EurocImageNameTooLong",  // found by fuzz_sequence_list, as RgbImageNameTooLong
       [](const TempDir& tmp) {
         std::filesystem::create_directories(tmp.file("mav0/cam0/data"));
         writeText(tmp.file("mav0/cam0/data.csv"),
                   "#timestamp [ns],filename\n1000000000," + std::string(300, 'g') + "\n");
         return Invocation{"run --backend cslam --sequence " + tmp.path() + " --out " + tmp.file("o"),
                           {tmp.file("mav0/cam0/data.csv") + ":2", "does not exist"}};
       }},
      {"SequenceNameTooLong",
       [](const TempDir& tmp) {
         const std::string seq = tmp.file(std::string(300, 's'));
         return Invocation{"run --backend cslam --sequence " + seq + " --out " + tmp.file("o"), {seq}};
       }},
      // Videos that cannot be opened.
      {"VideoGarbage",
       [](const TempDir& tmp) {
         writeText(tmp.file("clip.avi"), "RIFF not really a video at all");
         return Invocation{
             "run --backend cslam --sequence " + tmp.file("clip.avi") + " --out " + tmp.file("o"),
             {tmp.file("clip.avi"), "video"}};
       }},
      {"VideoEmpty",
       [](const TempDir& tmp) {
         writeText(tmp.file("clip.mp4"), "");
         return Invocation{
             "run --backend cslam --sequence " + tmp.file("clip.mp4") + " --out " + tmp.file("o"),
             {tmp.file("clip.mp4"), "video"}};
       }},
      // Output folders that cannot be written.
      {"RunOutUnderRegularFile",
       [](const TempDir& tmp) {
         writeSequence(tmp.file("seq"));
         writeText(tmp.file("file"), "x");
         return Invocation{
             "run --backend cslam --sequence " + tmp.file("seq") + " --out " + tmp.file("file/out"),
             {tmp.file("file/out"), "cannot be created"}};
       }},
      {"SynthOutUnderRegularFile",
       [](const TempDir& tmp) {
         writeText(tmp.file("file"), "x");
         return Invocation{"synth --preset tv1 --frames 1 --out " + tmp.file("file/out"),
                           {tmp.file("file/out")}};
       }},
      // Command-line values.
      runCase(
          "MaxFramesNegative", [](const std::string&) {}, {"--max-frames", "-1"}, "--max-frames -1"),
      runCase(
          "InitManualFileMalformed", [](const std::string& seq) { writeText(seq + "/pose.txt", "0 1 2\n"); },
          {"seq/pose.txt:1", "fields"}, "--backend monoslam --init manual:{seq}/pose.txt"),
      // Found by the reliability probe: the poses after the first were ignored silently.
      runCase(
          "InitManualFileTwoPoses",
          [](const std::string& seq) {
            writeText(seq + "/pose.txt", "# first camera\n0.0 0 0 -1 0 0 0 1\n\n0.1 0.01 0 -1 0 0 0 1\n");
          },
          {"seq/pose.txt:4", "a second pose", "(it holds 2)"}, "--backend monoslam --init manual:{seq}/pose.txt"),
      // Back-end options through the registry.
      runCase(
          "InitRefusedByABackEndWithoutIt", [](const std::string&) {}, {"--init", "cslam takes no --init"},
          "--init groundtruth"),
      runCase(
          "ModeUnknown", [](const std::string&) {}, {"--mode", "no mode 'fast'", "combined"}, "--mode fast"),
      runCase(
          "SetUnknownOption", [](const std::string&) {}, {"cslam.features.max_feature", "unknown option"},
          "--set cslam.features.max_feature=10"),
      runCase(
          "SetValueNotANumber", [](const std::string&) {}, {"cslam.lk_levels", "integer"}, "--set cslam.lk_levels=three"),
      runCase(
          "SetOutOfRangeNamesTheFullPath", [](const std::string&) {},
          {"cslam.map_refinement.max_iterations", ">= 0"}, "--set cslam.map_refinement.max_iterations=-1"),
      runCase(
          "SetWithoutSection", [](const std::string&) {}, {"--set lk_levels=2", "SECTION.KEY=VALUE"},
          "--set lk_levels=2"),
      runCase(
          "SetForAnotherBackEnd", [](const std::string&) {}, {"--set monoslam.search.patch_size=9", "cslam"},
          "--set monoslam.search.patch_size=9"),
      runCase(
          "ConfigRangeErrorNamesFileAndPath",
          [](const std::string& seq) { writeText(seq + "/run.yaml", "%YAML:1.0\n---\ncslam:\n  map_refinement:\n    max_iterations: -3\n"); },
          {"seq/run.yaml: cslam.map_refinement.max_iterations", ">= 0"}, "--config {seq}/run.yaml"),
      runCase(
          "ConfigMisspeltSection",
          [](const std::string& seq) { writeText(seq + "/run.yaml", "%YAML:1.0\n---\ncslm:\n  lk_levels: 2\n"); },
          {"seq/run.yaml: cslm", "unknown back-end"}, "--config {seq}/run.yaml"),
      // Trajectories given to eval: TUM, EuRoC, KITTI.
      {"EvalNoAssociation",
       [](const TempDir& tmp) {
         writeText(tmp.file("gt.txt"), kGroundTruth);
         writeText(tmp.file("est.txt"), "100 0 0 0 0 0 0 1\n101 1 0 0 0 0 0 1\n");
         return Invocation{"eval --groundtruth " + tmp.file("gt.txt") + " --estimate " + tmp.file("est.txt"),
                           {tmp.file("est.txt"), tmp.file("gt.txt"), "--max-diff"}};
       }},
      evalCase("EvalEstimateMissing", "absent.txt", "", ""),
      evalCase("EvalEstimateEmpty", "est.txt", "", ": holds no pose"),
      // TUM or KITTI (the format is detected from the first line) and EuRoC (from .csv).
      {"EvalEstimateIsAFolder",
       [](const TempDir& tmp) {
         writeText(tmp.file("gt.txt"), kGroundTruth);
         std::filesystem::create_directory(tmp.file("est.txt"));
         return Invocation{"eval --groundtruth " + tmp.file("gt.txt") + " --estimate " + tmp.file("est.txt"),
                           {tmp.file("est.txt") + ": is a folder"}};
       }},
      {"EvalEurocEstimateIsAFolder",
       [](const TempDir& tmp) {
         writeText(tmp.file("gt.txt"), kGroundTruth);
         std::filesystem::create_directory(tmp.file("est.csv"));
         return Invocation{"eval --groundtruth " + tmp.file("gt.txt") + " --estimate " + tmp.file("est.csv"),
                           {tmp.file("est.csv") + ": is a folder"}};
       }},
      evalCase("TumTruncatedLine", "est.txt", "0.0 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 1\n0.2 0 0 0",
               ":3: has 4 fields"),
      evalCase("TumNotNumber", "est.txt", "0.0 0 0 0 0 0 0 1\n0.1 0 zero 0 0 0 0 1\n",
               ":2: a field is not a number"),
      evalCase("TumNaN", "est.txt", "0.0 0 0 0 0 0 0 1\n0.1 0 0 nan 0 0 0 1\n", ":2: NaN or infinite"),
      evalCase("TumInfinite", "est.txt", "0.0 0 0 0 0 0 0 1\n0.1 0 0 1e999 0 0 0 1\n", ":2: NaN or infinite"),
      evalCase("TumTimestampHuge", "est.txt", "0.0 0 0 0 0 0 0 1\n2e300 0 0 0 0 0 0 1\n",
               ":2: timestamp 2e+300 is not plausible as seconds"),
      evalCase("TumZeroQuaternion", "est.txt", "0.0 0 0 0 0 0 0 0\n", ":1: quaternion norm"),
      evalCase("TumOutOfOrder", "est.txt", "0.1 0 0 0 0 0 0 1\n0.0 0 0 0 0 0 0 1\n",
               ":2: timestamp goes back"),
      evalCase("EurocTooFewFields", "est.csv", "#timestamp,p_x\n1000000000,0,0,0,1,0,0\n",
               ":2: has 7 fields"),
      evalCase("EurocOutOfOrder", "est.csv", "#t\n2000000000,0,0,0,1,0,0,0\n1000000000,0,0,0,1,0,0,0\n",
               ":3: timestamp goes back"),
      evalCase("KittiNotRotation", "est.txt", "2 0 0 0 0 2 0 0 0 0 2 0\n",
               ":1: the 3x3 part is not a rotation"),
      evalCase("KittiElevenFields", "est.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n",
               ":2: has 11 fields"),
      // Found by the reliability probe: KITTI poses of different counts were paired by index silently.
      {"KittiOfAnotherLength",
       [](const TempDir& tmp) {
         const std::string pose = "1 0 0 0 0 1 0 0 0 0 1 0\n";
         writeText(tmp.file("gt.txt"), pose + pose + pose + pose);
         writeText(tmp.file("est.txt"), pose + pose + pose);
         return Invocation{"eval --groundtruth " + tmp.file("gt.txt") + " --estimate " + tmp.file("est.txt"),
                           {tmp.file("est.txt") + " against " + tmp.file("gt.txt"), "must have as many: 3 against 4"}};
       }},
      evalCase("UnknownFieldCount", "est.txt", "1 2 3 4 5\n", ":1: has 5 fields"),
      {"EvalAlignUnknown",
       [](const TempDir& tmp) {
         writeText(tmp.file("gt.txt"), kGroundTruth);
         return Invocation{"eval --groundtruth " + tmp.file("gt.txt") + " --estimate " + tmp.file("gt.txt") +
                               " --align sideways",
                           {"--align", "sideways"}};
       }},
      {"EvalClockOffsetNotFinite",
       [](const TempDir& tmp) {
         writeText(tmp.file("gt.txt"), kGroundTruth);
         return Invocation{"eval --groundtruth " + tmp.file("gt.txt") + " --estimate " + tmp.file("gt.txt") +
                               " --t-offset inf",
                           {"--t-offset", "finite"}};
       }},
      // run --overlay outputs that cannot be written.
      runCase(
          "OverlayFolderUnderRegularFile", [](const std::string&) {}, {"seq/rgb.txt/frames", "cannot be created"},
          "--overlay {seq}/rgb.txt/frames"),
      runCase(
          "OverlayVideoUnderRegularFile", [](const std::string&) {}, {"seq/rgb.txt/clip.avi", "cannot be created"},
          "--overlay {seq}/rgb.txt/clip.avi"),
      runCase(
          "OverlayUnsupportedContainer", [](const std::string&) {}, {"seq/clip.gif", "'.gif'", ".avi, .mp4, .mkv"},
          "--overlay {seq}/clip.gif"),
      // Maps and scenes given to eval --map --scene, and a run beside a spoilt scene.yaml.
      {"MapPlyNotPly",
       [](const TempDir& tmp) {
         writeText(tmp.file("map.ply"), "x y z\n0 0 0\n");
         writeText(tmp.file("scene.yaml"), "%YAML:1.0\n---\nsurfaces: []\n");
         return Invocation{"eval --map " + tmp.file("map.ply") + " --scene " + tmp.file("scene.yaml"),
                           {tmp.file("map.ply") + ":1", "not a PLY file"}};
       }},
      {"MapPlyShortVertexLine",
       [](const TempDir& tmp) {
         writeText(tmp.file("map.ply"),
                   "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                   "property float z\nend_header\n0 0 0\n1 2\n");
         writeText(tmp.file("scene.yaml"), "%YAML:1.0\n---\nsurfaces: []\n");
         return Invocation{"eval --map " + tmp.file("map.ply") + " --scene " + tmp.file("scene.yaml"),
                           {tmp.file("map.ply") + ":9", "too few values"}};
       }},
      {"MapPlyBinaryCutShort",
       [](const TempDir& tmp) {
         writeText(tmp.file("map.ply"),
                   "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                   "property float z\nend_header\n0123456789ab0123");
         writeText(tmp.file("scene.yaml"), "%YAML:1.0\n---\nsurfaces: []\n");
         return Invocation{"eval --map " + tmp.file("map.ply") + " --scene " + tmp.file("scene.yaml"),
                           {tmp.file("map.ply"), "ends before vertex 1 of 2"}};
       }},
      // Found by grepping for readers that open a file without openTextFile: a folder was said to
      // have "no end_header line".
      {"MapPlyIsAFolder",
       [](const TempDir& tmp) {
         std::filesystem::create_directory(tmp.file("map.ply"));
         writeText(tmp.file("scene.yaml"), "%YAML:1.0\n---\nsurfaces: []\n");
         return Invocation{"eval --map " + tmp.file("map.ply") + " --scene " + tmp.file("scene.yaml"),
                           {tmp.file("map.ply") + ": is a folder, not a text file"}};
       }},
      {"SceneYamlMissingEdge",
       [](const TempDir& tmp) {
         writeText(tmp.file("map.ply"),
                   "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                   "property float z\nend_header\n0 0 0\n");
         writeText(tmp.file("scene.yaml"),
                   "%YAML:1.0\n---\nboard:\n  name: board\n  origin: [0, 0, 0]\n  edge_u: [1, 0, 0]\n"
                   "  normal: [0, 0, -1]\nsurfaces: []\n");
         return Invocation{"eval --map " + tmp.file("map.ply") + " --scene " + tmp.file("scene.yaml"),
                           {tmp.file("scene.yaml"), "board.edge_v"}};
       }},
      runCase("RunSceneYamlWithoutBoard",
              [](const std::string& seq) { writeText(seq + "/scene.yaml", "%YAML:1.0\n---\nsurfaces: []\n"); },
              {"seq/scene.yaml", "board"}),
      // Issue 11: empty option values, for every command that takes them.
      emptyOptionCase("RunOutEmpty", "run --backend cslam --sequence {seq} --out ''", "--out"),
      emptyOptionCase("RunSequenceEmpty", "run --backend cslam --sequence '' --out {tmp}/o", "--sequence"),
      emptyOptionCase("RunConfigEmpty", "run --backend cslam --sequence {seq} --out {tmp}/o --config ''",
                      "--config"),
      emptyOptionCase("RunCameraEmpty", "run --backend cslam --sequence {seq} --out {tmp}/o --camera ''",
                      "--camera"),
      emptyOptionCase("RunTargetEmpty", "run --backend cslam --sequence {seq} --out {tmp}/o --target ''",
                      "--target"),
      emptyOptionCase("RunOverlayEmpty", "run --backend cslam --sequence {seq} --out {tmp}/o --overlay ''",
                      "--overlay"),
      emptyOptionCase("SynthOutEmpty", "synth --preset tv1 --frames 1 --out ''", "--out"),
      // --frames 0 rendered the preset's 337 frames; a count past any disk was rendered until it filled.
      BadCase{"SynthZeroFrames",
              [](const TempDir& tmp) {
                return Invocation{"synth --preset tv1 --frames 0 --out " + tmp.file("s"), {"--frames", "at least 1"}};
              }},
      BadCase{"SynthTooManyFrames",
              [](const TempDir& tmp) {
                return Invocation{"synth --preset tv1 --frames 2000000000 --out " + tmp.file("s"),
                                  {"--frames", "must be in [1, 100000]"}};
              }},
      // Noise beyond the grey scale overflowed the 8-bit conversion: black frames, exit 0.
      BadCase{"SynthNoiseBeyondTheGreyScale",
              [](const TempDir& tmp) {
                return Invocation{"synth --preset tv1 --frames 1 --noise 1e10 --out " + tmp.file("s"),
                                  {"--noise", "must be in [0, 255] grey levels"}};
              }},
      emptyOptionCase("CalibrateSequenceEmpty",
                      "calibrate --sequence '' --target {seq}/target.yaml --out {tmp}/c.yaml", "--sequence"),
      emptyOptionCase("CalibrateTargetEmpty", "calibrate --sequence {seq} --target '' --out {tmp}/c.yaml",
                      "--target"),
      emptyOptionCase("CalibrateOutEmpty", "calibrate --sequence {seq} --target {seq}/target.yaml --out ''",
                      "--out"),
      {"CalibrateSubpixelUnknown",
       [](const TempDir& tmp) {
         writeSequence(tmp.file("seq"));
         return Invocation{"calibrate --sequence " + tmp.file("seq") + " --target " + tmp.file("seq") +
                               "/target.yaml --out " + tmp.file("c.yaml") + " --subpixel bilinear",
                           {"--subpixel", "bilinear"}};
       }},
      configCase("ConfigSubpixelMethodUnknown",
                 "%YAML:1.0\n---\ncslam:\n  board:\n    detector:\n      subpixel:\n        method: bilinear\n",
                 "cslam.board.detector.subpixel.method"),
      configCase("ConfigMinVarianceFactorAboveOne", "%YAML:1.0\n---\nhybrid:\n  search:\n    min_variance_factor: 2\n",
                 "hybrid.search.min_variance_factor", "hybrid"),
      configCase("ConfigMapDriftFractionNegative", "%YAML:1.0\n---\ncslam:\n  fusion:\n    map_drift_fraction: -0.01\n",
                 "cslam.fusion.map_drift_fraction"),
      configCase("ConfigCornerNoiseFloorZero",
                 "%YAML:1.0\n---\nhybrid:\n  corners:\n    noise:\n      enabled: 1\n      min_pixel_sigma: 0\n",
                 "hybrid.corners.noise.min_pixel_sigma", "hybrid"),
      emptyOptionCase("CompareOutEmpty", "compare --sequence {seq} --out ''", "--out"),
      emptyOptionCase("CompareSequenceEmpty", "compare --sequence '' --out {tmp}/c", "--sequence"),
      emptyOptionCase("ReproduceOutEmpty", "reproduce --frames 1 --out ''", "--out"),
      emptyOptionCase("EvalEstimatePathEmpty", "eval --groundtruth {seq}/groundtruth.txt --estimate ''", "--estimate"),
      // Issue 11: a key written twice (OpenCV keeps the first silently).
      yamlCase("CameraKeyTwice", "camera.yaml", std::string(kCameraYaml) + "image_width: 320\n",
               "image_width: written twice in one mapping (lines 3 and 15)"),
      yamlCase("BoardKeyTwice", "target.yaml", targetYaml("9", "6", "0.04") + "square_size: 0.4\n",
               "square_size: written twice"),
      yamlCase("CameraMatrixKeyTwice", "camera.yaml",
               std::string(kCameraYaml).replace(std::string(kCameraYaml).find("   dt: d"), 0, "   rows: 1\n"),
               "camera_matrix.rows: written twice"),
      configCase("ConfigKeyTwice", "%YAML:1.0\n---\ncslam:\n  lk_levels: 2\n  lk_levels: 3\n",
                 "cslam.lk_levels: written twice"),
      configCase("ConfigSectionTwice", "%YAML:1.0\n---\ncslam:\n  lk_levels: 2\ncslam:\n  lk_levels: 3\n",
                 "cslam: written twice"),
      // Issue 11: integer matrices would be rounded or wrapped.
      yamlCase("CameraMatrixEightBit", "camera.yaml", cameraWithDt(false, "u"), "camera_matrix.dt"),
      yamlCase("CameraMatrixInteger", "camera.yaml", cameraWithDt(false, "i"), "camera_matrix.dt"),
      yamlCase("CameraDistortionInteger", "camera.yaml", cameraWithDt(true, "i"), "distortion_coefficients.dt"),
      // Issue 11: numbers a camera or a board cannot have.
      yamlCase("CameraFocalTiny", "camera.yaml", cameraWithIntrinsics("0.5", "150.", "79.5", "59.5"),
               "camera_matrix: fx 0.5 px is not plausible for 160x120 images"),
      yamlCase("CameraFocalHuge", "camera.yaml", cameraWithIntrinsics("150.", "1e9", "79.5", "59.5"),
               "camera_matrix: fy 1e+09 px is not plausible"),
      yamlCase("CameraPrincipalPointFarRight", "camera.yaml", cameraWithIntrinsics("150.", "150.", "5000.", "59.5"),
               "camera_matrix: cx 5000 px is far outside"),
      yamlCase("CameraPrincipalPointFarAbove", "camera.yaml", cameraWithIntrinsics("150.", "150.", "79.5", "-200."),
               "camera_matrix: cy -200 px is far outside"),
      yamlCase("BoardTwoRows", "target.yaml", targetYaml("9", "2", "0.04"), "inner_corners_rows: a chessboard needs at least 3x3"),
      yamlCase("BoardTwoCols", "target.yaml", targetYaml("2", "7", "0.04"), "inner_corners_cols: a chessboard needs at least 3x3"),
      yamlCase("BoardSquareInMillimetres", "target.yaml", targetYaml("9", "6", "40"), "square_size: is 40 m"),
      yamlCase("BoardSquareTiny", "target.yaml", targetYaml("9", "6", "1e-7"), "square_size: is 1e-07 m"),
      yamlCase("BoardSquareInfinite", "target.yaml", targetYaml("9", "6", ".inf"), "square_size"),
      // Issue 11: file system errors name the path (were filesystem_error, exit 1, or "missing").
      runCase("CameraYamlSymlinkLoop", [](const std::string& seq) { symlinkLoop(seq + "/camera.yaml"); },
              {"seq/camera.yaml", "cannot be read", "symbolic links"}),
      runCase("TargetYamlSymlinkLoop", [](const std::string& seq) { symlinkLoop(seq + "/target.yaml"); },
              {"seq/target.yaml", "cannot be read", "symbolic links"}),
      runCase("GroundTruthSymlinkLoop", [](const std::string& seq) { symlinkLoop(seq + "/groundtruth.txt"); },
              {"seq/groundtruth.txt", "cannot be read", "symbolic links"}),
      runCase("RgbListSymlinkLoop", [](const std::string& seq) { symlinkLoop(seq + "/rgb.txt"); },
              {"seq/rgb.txt", "cannot be read", "symbolic links"}),
      {"SequenceSymlinkLoop",
       [](const TempDir& tmp) {
         symlinkLoop(tmp.file("loop"));
         return Invocation{"run --backend cslam --sequence " + tmp.file("loop") + " --out " + tmp.file("o"),
                           {tmp.file("loop"), "cannot be read", "symbolic links"}};
       }},
      {"EurocSensorYamlSymlinkLoop",
       [](const TempDir& tmp) {
         std::filesystem::create_directories(tmp.file("mav0/cam0/data"));
         writeImage(tmp.file("mav0/cam0/data/1.png"));
         writeText(tmp.file("mav0/cam0/data.csv"), "#timestamp [ns],filename\n1000000000,1.png\n");
         symlinkLoop(tmp.file("mav0/cam0/sensor.yaml"));
         return Invocation{"run --backend cslam --sequence " + tmp.path() + " --out " + tmp.file("o"),
                           {tmp.file("mav0/cam0/sensor.yaml"), "cannot be read"}};
       }},
      runCase(
          "CameraOptionIsAFolder", [](const std::string&) {}, {"seq/rgb", "is a folder"}, "--camera {seq}/rgb"),
      // Issue 11: --max-frames 0 is said as such.
      runCase(
          "MaxFramesZero", [](const std::string&) {}, {"--max-frames 0: nothing to run"}, "--max-frames 0"),
      {"CompareMaxFramesZero",
       [](const TempDir& tmp) {
         writeSequence(tmp.file("seq"));
         return Invocation{"compare --sequence " + tmp.file("seq") + " --out " + tmp.file("c") + " --max-frames 0",
                           {"--max-frames 0: nothing to run"}};
       }},
      // Found by the reliability probe: compare --trials reads info.yaml, whose errors were two lines
      // of OpenCV's text; it is read as every other YAML file is (core/yaml.h).
      {"CompareTrialsInfoYamlMalformed",
       [](const TempDir& tmp) {
         writeSequence(tmp.file("seq"));
         writeText(tmp.file("seq/info.yaml"), "# slamcmp synth\npreset: [\n");
         return Invocation{"compare --sequence " + tmp.file("seq") + " --backends cslam --trials 2 --out " +
                               tmp.file("c"),
                           {tmp.file("seq/info.yaml"), "is not valid YAML", "at line 3"}};
       }},
      {"CompareTrialsInfoYamlKeyTwice",
       [](const TempDir& tmp) {
         writeSequence(tmp.file("seq"));
         writeText(tmp.file("seq/info.yaml"), "preset: \"tv1\"\nseed: 1\nseed: 2\n");
         return Invocation{"compare --sequence " + tmp.file("seq") + " --backends cslam --trials 2 --out " +
                               tmp.file("c"),
                           {tmp.file("seq/info.yaml") + ": seed: written twice in one mapping (lines 2 and 3)"}};
       }},
      // compare --collect of a folder whose plan.json is a folder (was exit 1: "basic_filebuf::underflow
      // error reading the file: Is a directory", naming no file).
      {"CollectPlanJsonIsAFolder",
       [](const TempDir& tmp) {
         std::filesystem::create_directory(tmp.file("plan.json"));
         return Invocation{"compare --collect " + tmp.path(),
                           {tmp.file("plan.json") + ": is a folder, not a text file"}};
       }},
      // compare --config: a value its back-end refuses; a file for none of the back-ends compared.
      compareConfigCase("CompareConfigValueRefused", "%YAML:1.0\n---\nhybrid:\n  corners:\n    pixel_sigma: -1\n",
                        "hybrid", "hybrid.corners.pixel_sigma: must be positive"),
      compareConfigCase("CompareConfigNoSectionForTheBackEnds",
                        "%YAML:1.0\n---\nhybrid:\n  corners:\n    pixel_sigma: 0.1\n", "cslam",
                        "no section for a back-end among --backends"),
      // Issue 11: a byte-order mark before rgb.txt's first line is skipped: the list is read (this
      // tiny sequence then ends without the board), and a bad first timestamp is named without it.
      runCase("RgbByteOrderMarkSkipped",
              [k3](const std::string& seq) { writeText(seq + "/rgb.txt", "\xEF\xBB\xBF" + k3); },
              {"the board never appeared"}),
      rgbCase("RgbByteOrderMarkThenBadTimestamp", "\xEF\xBB\xBFzero rgb/0.png\n",
              ":1: timestamp 'zero' is not a number"),
      rgbCase("RgbUtf16", std::string("\xFF\xFE" "0\0.\0", 6), ": starts with a UTF-16 byte-order mark"),
      // A byte-order mark before camera.yaml's %YAML or groundtruth.txt's first line was "not valid
      // YAML" and "a field is not a number" (on a comment line): both are read.
      runCase("CameraYamlByteOrderMarkSkipped",
              [](const std::string& seq) { writeText(seq + "/camera.yaml", "\xEF\xBB\xBF" + std::string(kCameraYaml)); },
              {"the board never appeared"}),
      runCase("GroundTruthByteOrderMarkSkipped",
              [](const std::string& seq) {
                writeText(seq + "/groundtruth.txt", "\xEF\xBB\xBF# timestamp tx ty tz qx qy qz qw\n"
                                                    "0.0 0 0 -1 0 0 0 1\n0.1 0.01 0 -1 0 0 0 1\n0.2 0.02 0 -1 0 0 0 1\n");
              },
              {"the board never appeared"}),
      // Issue 11: a EuRoC T_BS that is no rotation.
      eurocSensorCase("EurocTbsAllZeros", "0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1"),
      eurocSensorCase("EurocTbsScaled", "2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1"),
      eurocSensorCase("EurocTbsReflection", "1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1"),
      // Issue 16: sensor.yaml's numbers are checked as camera.yaml's are.
      eurocIntrinsicsCase("EurocFocalTiny", "0.5, 150, 79.5, 59.5", "fx 0.5 px is not plausible for 160x120 images"),
      eurocIntrinsicsCase("EurocFocalHuge", "150, 1e9, 79.5, 59.5", "fy 1e+09 px is not plausible"),
      eurocIntrinsicsCase("EurocFocalNegative", "-150, 150, 79.5, 59.5", "fx -150 px is not plausible"),
      eurocIntrinsicsCase("EurocFocalNaN", "150, .nan, 79.5, 59.5", "must be finite"),
      eurocIntrinsicsCase("EurocPrincipalPointFarLeft", "150, 150, -900, 59.5", "cx -900 px is far outside"),
      eurocResolutionCase("EurocResolutionFraction", "160.5, 120"),
      eurocResolutionCase("EurocResolutionHuge", "1e300, 120"),
      eurocResolutionCase("EurocResolutionZero", "160, 0"),
      // Issue 16: a lens model that folds inside the image (core/distortion_fold.h), radially, through
      // its tangential terms, or at the rational model's pole; the 160x120 image's corner is at
      // normalised radius 0.67.
      yamlCase("CameraDistortionFoldsRadially", "camera.yaml", camera(kK, "-5, 0, 0, 0"),
               "distortion_coefficients: the lens model folds inside the image"),
      yamlCase("CameraDistortionFoldsWithinTheMargin", "camera.yaml", camera(kK, "-0.3, 0, 0, 0"),
               "distortion_coefficients: the lens model folds inside the image"),
      yamlCase("CameraDistortionFoldsTangentially", "camera.yaml", camera(kK, "0, 0, 0.5, 0"),
               "distortion_coefficients: the lens model folds near pixel"),
      yamlCase("CameraDistortionRationalPole", "camera.yaml", camera(kK, "0, 0, 0, 0, 0, 1, 0, 0"),
               "distortion_coefficients: the lens model folds inside the image"),
      eurocSensorYamlCase("EurocDistortionFolds", kIdentity4, "160, 120", "150, 150, 79.5, 59.5",
                          "distortion_coefficients", "the lens model folds inside the image", "-5, 0, 0, 0"),
      // Issue 16: windows, borders, patches and distances bounded by the image size (here 160x120),
      // checked once the first frame is read (they made OpenCV allocate without limit or fail an
      // assertion on a region of interest).
      imageBoundCase("MonoslamPatchSourceLargerThanImages", "monoslam", "search.source_size", "301", "120"),
      imageBoundCase("MonoslamCornerBoxWiderThanImages", "monoslam", "feature_init.box_width", "400", "160"),
      imageBoundCase("MonoslamCornerBoxTallerThanImages", "monoslam", "feature_init.box_height", "121", "120"),
      imageBoundCase("MonoslamRefineWindowLargerThanImages", "monoslam", "board.max_refine_half_window", "100000",
                     "57"),
      imageBoundCase("HybridBorderAcrossTheImage", "hybrid", "corners.border_px", "60", "59"),
      imageBoundCase("HybridRefineWindowLargerThanImages", "hybrid", "corners.detector.max_refine_half_window",
                     "58", "57"),
      imageBoundCase("CslamLkWindowLargerThanImages", "cslam", "lk_window_px", "100001", "120"),
      imageBoundCase("CslamFeatureBorderAcrossTheImage", "cslam", "features.border_px", "70", "59"),
      imageBoundCase("CslamFeatureBlockLargerThanImages", "cslam", "features.block_size", "2001", "120"),
      imageBoundCase("CslamFeatureSpacingBeyondTheImage", "cslam", "features.min_distance_px", "1e+300", "160"),
      imageBoundCase("CslamRefineWindowLargerThanImages", "cslam", "board.detector.max_refine_half_window",
                     "2147483647", "57"),
      // Found by fuzz_options: a --config of only the %YAML header made OpenCV assert listing the
      // sections of an empty document (exit 1); it holds none, so the defaults run (and this tiny
      // sequence ends without the board).
      runCase(
          "ConfigHeaderOnly", [](const std::string& seq) { writeText(seq + "/run.yaml", "%YAML:1.0\n"); },
          {"the board never appeared"}, "--config {seq}/run.yaml"),
      // ... and those no image size makes sensible: memory for every initialising ray.
      configCase("MonoslamParticlesAbsurd", "%YAML:1.0\n---\nmonoslam:\n  feature_init:\n    particles: 2000000000\n",
                 "monoslam.feature_init.particles", "monoslam", {"must be in [2, 100000]"}),
      // Issue 16: a corrupt image says our one line, with the decoder's complaint in it; libpng's
      // and libjpeg's own lines are captured, not printed.
      runCase("FirstImageCorruptPngData", [](const std::string& seq) { corruptPngData(seq + "/rgb/0.png"); },
              {"seq/rgb/0.png", "cannot be decoded as an image (libpng error: IDAT"}),
      runCase("FirstImageCorruptJpegData",
              [](const std::string& seq) {
                cv::Mat noise(kHeight, kWidth, CV_8UC1);
                cv::randu(noise, 0, 255);
                ASSERT_TRUE(cv::imwrite(seq + "/rgb/0.jpg", noise));
                std::string data = readBytes(seq + "/rgb/0.jpg");
                for (size_t i = 1000; i < 1100; ++i) data[i] = '\0';  // inside the scan, its end marker kept
                writeText(seq + "/rgb/0.jpg", data);
                writeText(seq + "/rgb.txt", "0.0 rgb/0.jpg\n0.1 rgb/1.png\n");
              },
              {"seq/rgb/0.jpg", "cannot be decoded as an image (Corrupt JPEG data"}),
      // A PNG libpng only warns about is whole: read without its warning (this tiny sequence then
      // ends without the board, the one line).
      runCase("PngWarningIsNotPrinted",
              [](const std::string& seq) {
                for (int i = 0; i < 3; ++i) insertPngTextChunkWithBadCrc(seq + "/rgb/" + std::to_string(i) + ".png");
              },
              {"the board never appeared"}),
      // Issue 16: --overlay on timestamps in another unit than seconds names the frame rate they imply.
      runCase(
          "OverlayOnNanosecondTimestamps",
          [](const std::string& seq) {
            writeText(seq + "/rgb.txt", "1000000000 rgb/0.png\n1100000000 rgb/1.png\n1200000000 rgb/2.png\n");
          },
          {"seq/clip.avi", "imply 1e-08 fps", "nanoseconds (1e+09 times seconds)"}, "--overlay {seq}/clip.avi"),
      // No camera file, and a board seen square on in every frame (board_partial slides in front of
      // it): the views do not determine the focal length, and the run says so (it self-calibrated
      // from such views at fx 950 for 525, and said "too few views" when refused).
      BadCase{"SelfCalibrationFromParallelViews",
              [](const TempDir& tmp) {
                const std::string seq = boardPartialWithoutCamera(tmp);
                return Invocation{"run --backend cslam --sequence " + seq + " --out " + tmp.file("out") +
                                      " --set cslam.calibration.max_frames=70",
                                  {"no camera file, and self-calibration failed: 12 distinct board views",
                                   "parallel views do not determine the focal length"}};
              }},
      // No camera file and a run shorter than calibration.max_frames with fewer views than max_views:
      // never calibrated, and said so (it said "only 12 distinct board views (need 8)").
      BadCase{"SelfCalibrationNotReachedBeforeTheEnd",
              [](const TempDir& tmp) {
                const std::string seq = boardPartialWithoutCamera(tmp);
                return Invocation{"run --backend cslam --sequence " + seq + " --out " + tmp.file("out"),
                                  {"the run ended before self-calibrating: 12 distinct board views",
                                   "lower calibration.max_frames"}};
              }},
      // The sequence's list given for the sequence: FFmpeg opened it as a 640x400 video (its tty
      // demuxer) and the camera file was blamed for the size.
      BadCase{"ListFileForTheSequence",
              [](const TempDir& tmp) {
                const std::string seq = tmp.file("seq");
                writeSequence(seq);
                return Invocation{"run --backend cslam --sequence " + seq + "/rgb.txt --out " + tmp.file("out"),
                                  {seq + "/rgb.txt: is a text file, not a video", "give its folder"}};
              }},
      runCase(
          "OverlayOnMillisecondTimestamps",
          [](const std::string& seq) { writeText(seq + "/rgb.txt", "0 rgb/0.png\n100 rgb/1.png\n200 rgb/2.png\n"); },
          {"seq/clip.avi", "imply 0.01 fps", "milliseconds (1000 times seconds)"}, "--overlay {seq}/clip.avi"),
  };
}

class BadInput : public ::testing::TestWithParam<BadCase> {};

int lineCount(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

TEST_P(BadInput, ExitsTwoWithOneLineNamingTheProblem) {
  TempDir tmp;
  const Invocation run = GetParam().make(tmp);
  if (HasFatalFailure()) return;
  const test::CommandResult r = test::runSlamcmp(run.args);
  EXPECT_EQ(r.exit_code, 2) << run.args << "\nstderr: " << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << run.args << "\nstderr: " << r.err;
  for (const std::string& m : run.must_mention)
    EXPECT_NE(r.err.find(m), std::string::npos) << "stderr should name '" << m << "': " << r.err;
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadInput, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<BadCase>& info) { return info.param.name; });

// `synth --out ''` is refused before anything is rendered: nothing lands in the current folder.
TEST(EmptyOut, SynthWritesNothingIntoTheCurrentFolder) {
  // What synth writes into its --out (other tests may write elsewhere in this folder meanwhile).
  const std::vector<std::string> outputs{"rgb", "rgb.txt", "camera.yaml", "target.yaml", "groundtruth.txt",
                                         "scene.yaml", "info.yaml"};
  std::vector<std::string> present;
  for (const auto& name : outputs)
    if (std::filesystem::exists(name)) present.push_back(name);
  const test::CommandResult r = test::runSlamcmp("synth --preset tv1 --frames 1 --out ''");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  for (const auto& name : outputs) {
    if (std::find(present.begin(), present.end(), name) == present.end()) {
      EXPECT_FALSE(std::filesystem::exists(name)) << name << " was written into the current folder";
    }
  }
}

// A refused compare leaves --out as it found it, as a refused run does: a fresh --out is not
// created, and one that exists gets no runs/, logs/ or figures/ (a probe found them left empty when
// a trial's info.yaml was refused after they were made).
TEST(RefusedCompare, LeavesOutAsItFoundIt) {
  TempDir tmp;
  writeSequence(tmp.file("seq"));
  writeText(tmp.file("seq/rgb.txt"), "0.0 rgb/7.png\n");
  const test::CommandResult run =
      test::runSlamcmp("run --backend cslam --sequence " + tmp.file("seq") + " --out " + tmp.file("run"));
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_FALSE(std::filesystem::exists(tmp.file("run"))) << "a refused run created its --out";

  writeSequence(tmp.file("seq"));
  writeText(tmp.file("seq/info.yaml"), "# slamcmp synth\npreset: [\n");
  const std::string compare = "compare --sequence " + tmp.file("seq") + " --backends cslam --trials 2 --out ";
  const test::CommandResult fresh = test::runSlamcmp(compare + tmp.file("c"));
  EXPECT_EQ(fresh.exit_code, 2) << fresh.err;
  EXPECT_NE(fresh.err.find("info.yaml"), std::string::npos) << fresh.err;
  EXPECT_FALSE(std::filesystem::exists(tmp.file("c"))) << "a refused compare created its --out";

  std::filesystem::create_directory(tmp.file("d"));
  writeText(tmp.file("d/notes.txt"), "the user's own file\n");
  const test::CommandResult existing = test::runSlamcmp(compare + tmp.file("d"));
  EXPECT_EQ(existing.exit_code, 2) << existing.err;
  std::vector<std::string> left;
  for (const auto& entry : std::filesystem::directory_iterator(tmp.file("d")))
    left.push_back(entry.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"notes.txt"});
}

// A symmetric board (both counts even, or both odd) is not bad input: one warning line naming
// target.yaml, and the run goes on. (This tiny sequence never shows the board, so the run then
// ends with the one line that says so, exit 2; tests/cslam/symmetric_board_test.cc runs one that
// does.)
TEST(SymmetricBoard, RunWarnsOnceAndGoesOn) {
  for (const auto& [cols, rows] : {std::pair<std::string, std::string>{"8", "6"}, {"9", "7"}}) {
    TempDir tmp;
    writeSequence(tmp.file("seq"));
    writeText(tmp.file("seq/target.yaml"), targetYaml(cols, rows, "0.04"));
    const test::CommandResult r =
        test::runSlamcmp("run --backend cslam --sequence " + tmp.file("seq") + " --out " + tmp.file("out"));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    ASSERT_EQ(lineCount(r.err), 2) << r.err;
    EXPECT_EQ(r.err.find(tmp.file("seq/target.yaml") + ": the " + cols + "x" + rows + " board is symmetric"), 0u)
        << r.err;
    EXPECT_NE(r.err.find("the board never appeared"), std::string::npos) << r.err;
  }
}

// A video cut short (an interrupted copy): the run covers the frames that could be read, and says
// how many the file promised, on stderr and in summary.json (issue 16; it ended with exit 0 and
// nothing said).
TEST(TruncatedVideo, MissingFramesAreReported) {
  TempDir tmp;
  const auto rendered = test::runSlamcmp("synth --preset tv1 --frames 20 --supersample 1 --out " + tmp.file("tv1"));
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  const std::string video = tmp.file("clip.avi");
  {
    const cv::Mat first = cv::imread(tmp.file("tv1/rgb/000000.png"));
    auto writer = mediaPlugin(video).createVideo(video, "MJPG", 10, first.size());
    ASSERT_NE(writer, nullptr);
    for (int i = 0; i < 20; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "tv1/rgb/%06d.png", i);
      writer->write(cv::imread(tmp.file(name)));
    }
  }
  truncateFile(video, readBytes(video).size() / 2);
  if (HasFatalFailure()) return;
  const std::string out = tmp.file("out");
  const test::CommandResult r = test::runSlamcmp("run --backend cslam --sequence " + video + " --camera " +
                                                 tmp.file("tv1/camera.yaml") + " --target " +
                                                 tmp.file("tv1/target.yaml") + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream file(out + "/summary.json");
  const nlohmann::json summary = nlohmann::json::parse(file);
  const int frames = summary["frames"].get<int>();
  EXPECT_GE(frames, 3);
  EXPECT_LT(frames, 20);
  EXPECT_EQ(summary["frames_expected"], 20);
  EXPECT_EQ(summary["frames_missing"], 20 - frames);
  EXPECT_EQ(r.err, video + ": warning: the file says 20 frames but only " + std::to_string(frames) +
                       " could be read (cut short?); the results cover those\n");
}

}  // namespace
}  // namespace slamcmp
