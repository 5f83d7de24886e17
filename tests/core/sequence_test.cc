// openSequence on the real sequences, a video, plain image and EuRoC folders made here, and every
// malformed input answered with an InputError naming the file and line.
#include "core/sequence.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "core/error.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

// A small grey image whose pixels tell which one it is.
cv::Mat testImage(int width, int height, int id) {
  cv::Mat img(height, width, CV_8UC1);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u)
      img.at<uchar>(v, u) = static_cast<uchar>((u * 7 + v * 3 + id * 40) % 256);
  return img;
}

void writeImage(const std::string& path, const cv::Mat& img) {
  ASSERT_TRUE(cv::imwrite(path, img));
}

std::string cameraYaml(int width, int height) {
  return "%YAML:1.0\n---\nimage_width: " + std::to_string(width) +
         "\nimage_height: " + std::to_string(height) +
         "\ncamera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
         "   data: [ 50., 0., 16., 0., 50., 12., 0., 0., 1. ]\n"
         "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 4\n   dt: d\n"
         "   data: [ -0.1, 0.01, 0., 0. ]\n";
}

// Every frame until next() says the sequence has ended. The frames share their pixels with what
// next() returned (cv::Mat copies are shallow): a later frame must not overwrite an earlier one.
std::vector<Frame> readAll(Sequence& seq) {
  std::vector<Frame> frames;
  Frame f;
  while (seq.frames->next(&f)) frames.push_back(f);
  return frames;
}

int countDataLines(const std::string& path) {
  std::ifstream in(path);
  int n = 0;
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#') ++n;
  return n;
}

TEST(Sequence, OpensVamrCheckerboard) {
  SLAMCMP_REQUIRE_SHARED(data);
  Sequence seq = openSequence(data + "/vamr_checkerboard");
  EXPECT_EQ(seq.kind, "tum");
  EXPECT_EQ(seq.name, "vamr_checkerboard");
  EXPECT_EQ(seq.frames->size(), 736);
  EXPECT_EQ(seq.image_size, cv::Size(752, 480));
  ASSERT_TRUE(seq.camera.has_value());
  EXPECT_EQ(seq.camera->width, 752);
  ASSERT_TRUE(seq.target.has_value());
  EXPECT_EQ(seq.target->cols, 9);
  EXPECT_EQ(seq.target->rows, 6);
  ASSERT_TRUE(seq.groundtruth.has_value());
  EXPECT_EQ(seq.groundtruth->size(), 736u);
  EXPECT_NE(seq.groundtruth_path.find("groundtruth.txt"), std::string::npos);
  for (int i = 0; i < 3; ++i) {
    Frame f;
    ASSERT_TRUE(seq.frames->next(&f));
    EXPECT_EQ(f.index, i);
    EXPECT_NEAR(f.timestamp, i / 30.0, 1e-6);
    EXPECT_EQ(f.grey.type(), CV_8UC1);
    EXPECT_EQ(f.grey.size(), seq.image_size);
    EXPECT_NE(f.source.find("img_000" + std::to_string(i + 1) + ".jpg"), std::string::npos);
  }
}

TEST(Sequence, OpensTumFreiburg1Rpy) {
  SLAMCMP_REQUIRE_SHARED(data);
  const std::string dir = data + "/tum_fr1_rpy";
  Sequence seq = openSequence(dir);
  EXPECT_EQ(seq.kind, "tum");
  EXPECT_EQ(seq.frames->size(), 250);
  EXPECT_EQ(seq.image_size, cv::Size(640, 480));
  EXPECT_TRUE(seq.camera.has_value());
  EXPECT_FALSE(seq.target.has_value());
  ASSERT_TRUE(seq.groundtruth.has_value());
  EXPECT_EQ(static_cast<int>(seq.groundtruth->size()), countDataLines(dir + "/groundtruth.txt"));
  // The first frame's timestamp is the first data line of rgb.txt.
  std::ifstream rgb(dir + "/rgb.txt");
  std::string line;
  while (std::getline(rgb, line) && line[0] == '#') {
  }
  Frame f;
  ASSERT_TRUE(seq.frames->next(&f));
  EXPECT_EQ(f.timestamp, std::stod(line.substr(0, line.find(' '))));
  EXPECT_EQ(f.grey.size(), cv::Size(640, 480));
}

TEST(Sequence, OpensVideoAndDecodesEveryFrame) {
  SLAMCMP_REQUIRE_SHARED(data);
  const std::string video = data + "/video_chessboard/chessboard.avi";
  // The target.yaml beside the video gives an 8x6 board: both counts even, so its orientation is
  // ambiguous (SPEC section 2) and it is refused; --target replaces it.
  try {
    openSequence(video);
    FAIL() << "the 8x6 target.yaml beside the video was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("video_chessboard/target.yaml"), std::string::npos)
        << e.what();
  }
  test::TempDir dir;
  SequenceOpenOptions options;
  options.target_path = dir.file("target.yaml");
  test::writeText(options.target_path,
                  "%YAML:1.0\n---\ntype: chessboard\ninner_corners_cols: 7\ninner_corners_rows: 6\n"
                  "square_size: 1.0\n");
  Sequence seq = openSequence(video, options);
  EXPECT_EQ(seq.kind, "video");
  EXPECT_EQ(seq.name, "chessboard");
  EXPECT_EQ(seq.image_size, cv::Size(1280, 720));
  EXPECT_FALSE(seq.camera.has_value());
  ASSERT_TRUE(seq.target.has_value());
  EXPECT_EQ(seq.target->cols, 7);
  EXPECT_EQ(seq.target_path, options.target_path);
  const std::vector<Frame> frames = readAll(seq);
  EXPECT_EQ(static_cast<int>(frames.size()), 241);
  if (seq.frames->size() > 0) {
    EXPECT_EQ(seq.frames->size(), static_cast<int>(frames.size()));
  }
  for (size_t i = 0; i < frames.size(); ++i) {
    ASSERT_EQ(frames[i].grey.size(), cv::Size(1280, 720)) << i;
    ASSERT_EQ(frames[i].grey.type(), CV_8UC1);
    EXPECT_EQ(frames[i].index, static_cast<int>(i));
    EXPECT_NEAR(frames[i].timestamp, i / 24.0, 1e-9);
  }
  cv::Scalar mean, stddev;
  cv::meanStdDev(frames[0].grey, mean, stddev);
  EXPECT_GT(stddev[0], 20.0);  // a decoded scene with a chessboard, not a blank frame
  EXPECT_GT(cv::norm(frames[0].grey, frames[120].grey, cv::NORM_L1), 0.0);  // the camera moves
}

TEST(Sequence, OpensPlainImageFolderInNameOrder) {
  test::TempDir dir;
  writeImage(dir.file("frame_002.png"), testImage(32, 24, 2));
  writeImage(dir.file("frame_001.png"), testImage(32, 24, 1));
  writeImage(dir.file("frame_010.jpg"), testImage(32, 24, 3));
  test::writeText(dir.file("notes.txt"), "not an image\n");
  SequenceOpenOptions options;
  options.images_fps = 10.0;
  Sequence seq = openSequence(dir.path(), options);
  EXPECT_EQ(seq.kind, "images");
  EXPECT_EQ(seq.fps, 10.0);
  EXPECT_EQ(seq.frames->size(), 3);
  EXPECT_EQ(seq.image_size, cv::Size(32, 24));
  EXPECT_FALSE(seq.camera.has_value());
  EXPECT_FALSE(seq.groundtruth.has_value());
  const std::vector<Frame> frames = readAll(seq);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_NE(frames[0].source.find("frame_001.png"), std::string::npos);
  EXPECT_NE(frames[2].source.find("frame_010.jpg"), std::string::npos);
  EXPECT_EQ(frames[1].timestamp, 0.1);
  EXPECT_EQ(cv::norm(frames[0].grey, testImage(32, 24, 1), cv::NORM_INF), 0.0);  // PNG is lossless
}

// A folder given as ".", ".." or with a trailing slash is named as itself: compare renders trial k
// of a sequence into sequences/seed<k>/<name>, and ".." put every trial into one folder.
TEST(Sequence, NamedAsItsFolderHoweverThePathIsWritten) {
  test::TempDir dir;
  const std::string seq_dir = dir.file("my_seq");
  std::filesystem::create_directories(seq_dir + "/sub");
  writeImage(seq_dir + "/frame_001.png", testImage(32, 24, 1));
  SequenceOpenOptions options;
  options.images_fps = 10.0;
  const std::filesystem::path cwd = std::filesystem::current_path();
  std::filesystem::current_path(seq_dir + "/sub");
  const std::string up = openSequence("..", options).name;
  std::filesystem::current_path(seq_dir);
  const std::string here = openSequence(".", options).name;
  const std::string here_slash = openSequence("./", options).name;
  std::filesystem::current_path(cwd);
  EXPECT_EQ(up, "my_seq");
  EXPECT_EQ(here, "my_seq");
  EXPECT_EQ(here_slash, "my_seq");
  EXPECT_EQ(openSequence(seq_dir + "/", options).name, "my_seq");
}

// Numbered names without zeros in front play in their numbers' order, not their bytes'; decimal
// timestamps (trailing zeros trimmed) in theirs.
TEST(Sequence, PlainImageFolderNumbersInOrderOfValue) {
  test::TempDir dir;
  const std::vector<std::string> names = {"0.125.png",  "0.25.png",    "0.5.png",      "0.75.png",     "2.5.png",
                                          "10.05.png",  "10.1.png",    "frame1.png",   "frame2.png",   "frame9.png",
                                          "frame10.png", "frame11.png", "frame011.png", "frame100.png", "frame100a.png",
                                          "framez.png", "img.2.png",   "img.10.png"};
  for (size_t k = 0; k < names.size(); ++k) writeImage(dir.file(names[names.size() - 1 - k]), testImage(8, 6, 0));
  SequenceOpenOptions options;
  options.images_fps = 10.0;
  Sequence seq = openSequence(dir.path(), options);
  const std::vector<Frame> frames = readAll(seq);
  ASSERT_EQ(frames.size(), names.size());
  for (size_t k = 0; k < names.size(); ++k) EXPECT_EQ(frames[k].source, dir.file(names[k])) << k;
}

TEST(Sequence, OpensEurocFolderWithCameraAndBodyGroundTruth) {
  test::TempDir dir;
  const std::string cam = dir.file("mav0/cam0");
  std::filesystem::create_directories(cam + "/data");
  std::filesystem::create_directories(dir.file("mav0/state_groundtruth_estimate0"));
  writeImage(cam + "/data/1403715273262142976.png", testImage(40, 30, 0));
  writeImage(cam + "/data/1403715273312143104.png", testImage(40, 30, 1));
  test::writeText(cam + "/data.csv",
                  "#timestamp [ns],filename\n1403715273262142976,1403715273262142976.png\n"
                  "1403715273312143104,1403715273312143104.png\n");
  // Camera 0.1 m along the body's x, turned 90 degrees about the body's z.
  test::writeText(cam + "/sensor.yaml",
                  "%YAML:1.0\nsensor_type: camera\ncomment: test\nT_BS:\n  cols: 4\n  rows: 4\n"
                  "  data: [0.0, -1.0, 0.0, 0.1,\n         1.0, 0.0, 0.0, 0.0,\n"
                  "         0.0, 0.0, 1.0, 0.0,\n         0.0, 0.0, 0.0, 1.0]\n"
                  "rate_hz: 20\nresolution: [40, 30]\ncamera_model: pinhole\n"
                  "intrinsics: [45.6, 45.7, 19.5, 14.5]\ndistortion_model: radial-tangential\n"
                  "distortion_coefficients: [-0.28, 0.07, 0.0002, 1.7e-05]\n");
  test::writeText(dir.file("mav0/state_groundtruth_estimate0/data.csv"),
                  "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], "
                  "q_RS_y [], q_RS_z []\n"
                  "1403715273262142976,1.0,2.0,3.0,1.0,0.0,0.0,0.0\n"
                  "1403715273312143104,1.5,2.0,3.0,1.0,0.0,0.0,0.0\n");
  Sequence seq = openSequence(dir.path());
  EXPECT_EQ(seq.kind, "euroc");
  EXPECT_EQ(seq.frames->size(), 2);
  EXPECT_EQ(seq.image_size, cv::Size(40, 30));
  ASSERT_TRUE(seq.camera.has_value());
  EXPECT_EQ(seq.camera->fx, 45.6);
  EXPECT_EQ(seq.camera->cy, 14.5);
  EXPECT_EQ(seq.camera->num_distortion, 4);
  EXPECT_EQ(seq.camera->distortion[3], 1.7e-05);
  ASSERT_TRUE(seq.groundtruth.has_value());
  ASSERT_EQ(seq.groundtruth->size(), 2u);
  // T_world_camera = T_world_body * T_body_camera.
  const SE3& T = seq.groundtruth->at(1).T_world_camera;
  EXPECT_LT((T.t() - Vec3(1.6, 2.0, 3.0)).norm(), 1e-12);
  EXPECT_LT((T.R() * Vec3(1, 0, 0) - Vec3(0, 1, 0)).norm(), 1e-12);
  const std::vector<Frame> frames = readAll(seq);
  ASSERT_EQ(frames.size(), 2u);
  // The same nanoseconds give the same seconds in the image list and the ground truth.
  EXPECT_EQ(frames[0].timestamp, seq.groundtruth->at(0).timestamp);
  EXPECT_EQ(frames[1].timestamp, seq.groundtruth->at(1).timestamp);
  EXPECT_NEAR(frames[0].timestamp, 1403715273.262142976, 1e-6);
  EXPECT_NEAR(frames[1].timestamp - frames[0].timestamp, 0.05, 1e-6);
}

// A EuRoC list written in seconds would put its frames nanoseconds apart; a Kalibr fisheye's
// sensor.yaml would be read as a pinhole with radial-tangential distortion.
TEST(Sequence, EurocSecondsAndOtherCameraModelsAreRefused) {
  test::TempDir dir;
  const std::string cam = dir.file("mav0/cam0");
  std::filesystem::create_directories(cam + "/data");
  writeImage(cam + "/data/a.png", testImage(40, 30, 0));
  writeImage(cam + "/data/b.png", testImage(40, 30, 1));
  const auto refused = [&](const std::string& where, const std::string& said) {
    try {
      openSequence(dir.path());
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(said), std::string::npos) << e.what();
    }
  };
  test::writeText(cam + "/data.csv", "#timestamp [ns],filename\n0.05,a.png\n0.10,b.png\n");
  refused(cam + "/data.csv", "are these seconds?");
  test::writeText(cam + "/data.csv", "#timestamp [ns],filename\n50000000,a.png\n100000000,b.png\n");
  const std::string sensor =
      "%YAML:1.0\nT_BS:\n  cols: 4\n  rows: 4\n  data: [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0,\n"
      "         0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]\nresolution: [40, 30]\n"
      "intrinsics: [45.6, 45.7, 19.5, 14.5]\ndistortion_coefficients: [-0.28, 0.07, 0.0002, 1.7e-05]\n";
  test::writeText(cam + "/sensor.yaml", sensor + "camera_model: pinhole\ndistortion_model: equidistant\n");
  refused(cam + "/sensor.yaml: distortion_model", "'equidistant' is not read");
  test::writeText(cam + "/sensor.yaml", sensor + "camera_model: ds\n");
  refused(cam + "/sensor.yaml: camera_model", "'ds' is not read");
  test::writeText(cam + "/sensor.yaml", sensor + "camera_model: pinhole\ndistortion_model: radtan\n");
  const Sequence seq = openSequence(dir.path());
  ASSERT_TRUE(seq.camera.has_value());
  EXPECT_EQ(seq.fps, 20.0);
}

// A TUM folder with three valid 32x24 images a.png, b.png, c.png and the given rgb.txt.
class TumFolder {
 public:
  explicit TumFolder(const std::string& rgb_txt) {
    for (int i = 0; i < 3; ++i)
      writeImage(dir_.file(std::string(1, static_cast<char>('a' + i)) + ".png"),
                 testImage(32, 24, i));
    test::writeText(dir_.file("rgb.txt"), rgb_txt);
  }
  const test::TempDir& dir() const { return dir_; }

 private:
  test::TempDir dir_;
};

struct BadRgbList {
  std::string name;
  std::string content;
  std::string where;  // "rgb.txt:2"
};

// gtest prints the parameter by its name.
void PrintTo(const BadRgbList& c, std::ostream* os) { *os << c.name; }

class BadRgbLists : public ::testing::TestWithParam<BadRgbList> {};

TEST_P(BadRgbLists, ThrowsNamingFileAndLine) {
  const BadRgbList& bad = GetParam();
  TumFolder folder(bad.content);
  try {
    openSequence(folder.dir().path());
    FAIL() << "accepted " << bad.name;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(folder.dir().file(bad.where)), std::string::npos) << message;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadRgbLists,
    ::testing::Values(
        BadRgbList{"missing_image", "# list\n1.0 a.png\n2.0 missing.png\n", "rgb.txt:3"},
        BadRgbList{"bad_timestamp", "1.0 a.png\n2.0x b.png\n", "rgb.txt:2"},
        BadRgbList{"nan_timestamp", "nan a.png\n", "rgb.txt:1"},
        BadRgbList{"duplicate_timestamp", "1.0 a.png\n1.0 b.png\n", "rgb.txt:2"},
        BadRgbList{"decreasing_timestamp", "1.0 a.png\n2.0 b.png\n1.5 c.png\n", "rgb.txt:3"},
        BadRgbList{"extra_fields", "1.0 a.png\n2.0 b.png depth/b.png\n", "rgb.txt:2"},
        BadRgbList{"missing_path", "1.0 a.png\n2.0\n", "rgb.txt:2"},
        BadRgbList{"empty_list", "# timestamp filename\n\n", "rgb.txt"},
        BadRgbList{"huge_timestamp", "1.0 a.png\n2e300 b.png\n", "rgb.txt:2"},
        BadRgbList{"nanosecond_timestamp", "1403715572212143183 a.png\n", "rgb.txt:1"}),
    [](const auto& info) { return info.param.name; });

TEST(Sequence, RateIsTheMedianSpacingOfTheTimestamps) {
  TumFolder folder("1.00 a.png\n1.05 b.png\n1.10 c.png\n1.30 a.png\n");  // one frame dropped
  EXPECT_NEAR(openSequence(folder.dir().path()).fps, 20.0, 1e-9);
  TumFolder single("5.0 a.png\n");
  EXPECT_EQ(openSequence(single.dir().path()).fps, 30.0);
}

TEST(Sequence, CameraOfAnotherSizeIsRefused) {
  TumFolder folder("1.0 a.png\n2.0 b.png\n");
  test::writeText(folder.dir().file("camera.yaml"), cameraYaml(640, 480));
  try {
    openSequence(folder.dir().path());
    FAIL() << "a 640x480 camera accepted for 32x24 images";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(folder.dir().file("camera.yaml")), std::string::npos)
        << e.what();
  }
  // The right size is accepted, and --camera overrides the file beside the sequence.
  const std::string other = folder.dir().file("other.yaml");
  test::writeText(other, cameraYaml(32, 24));
  SequenceOpenOptions options;
  options.camera_path = other;
  const Sequence seq = openSequence(folder.dir().path(), options);
  ASSERT_TRUE(seq.camera.has_value());
  EXPECT_EQ(seq.camera_path, other);
}

TEST(Sequence, CorruptImageIsAnEmptyFrameNotACrash) {
  TumFolder folder("1.0 a.png\n2.0 corrupt.png\n3.0 b.png\n");
  test::writeText(folder.dir().file("corrupt.png"), "\x89PNG\r\n\x1a\n this is not a PNG body");
  Sequence seq = openSequence(folder.dir().path());
  const std::vector<Frame> frames = readAll(seq);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_FALSE(frames[0].grey.empty());
  EXPECT_TRUE(frames[1].grey.empty());
  EXPECT_EQ(frames[1].index, 1);
  EXPECT_EQ(frames[1].timestamp, 2.0);
  EXPECT_NE(frames[1].source.find("corrupt.png"), std::string::npos);
  EXPECT_FALSE(frames[2].grey.empty());
}

TEST(Sequence, CorruptFirstImageIsRefused) {
  TumFolder folder("1.0 corrupt.png\n2.0 a.png\n");
  test::writeText(folder.dir().file("corrupt.png"), "garbage");
  try {
    openSequence(folder.dir().path());
    FAIL() << "a sequence whose first image cannot be decoded was opened";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(folder.dir().file("corrupt.png")), std::string::npos)
        << e.what();
  }
}

TEST(Sequence, ImageOfAnotherSizeMidSequenceThrows) {
  TumFolder folder("1.0 a.png\n2.0 b.png\n3.0 big.png\n");
  writeImage(folder.dir().file("big.png"), testImage(40, 30, 5));
  Sequence seq = openSequence(folder.dir().path());
  Frame f;
  ASSERT_TRUE(seq.frames->next(&f));
  ASSERT_TRUE(seq.frames->next(&f));
  try {
    seq.frames->next(&f);
    FAIL() << "a 40x30 image accepted in a 32x24 sequence";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(folder.dir().file("big.png")), std::string::npos)
        << e.what();
  }
}

TEST(Sequence, MissingPathAndEmptyFolderAreRefused) {
  test::TempDir dir;
  EXPECT_THROW(openSequence(dir.file("nowhere")), InputError);
  EXPECT_THROW(openSequence(dir.path()), InputError);  // no rgb.txt, no images
  test::writeText(dir.file("clip.avi"), "not a video");
  EXPECT_THROW(openSequence(dir.file("clip.avi")), InputError);
}

}  // namespace
}  // namespace slamcmp

namespace slamcmp {
namespace {

// stderr is the process's: while a frame is decoded on the prefetching thread, the tracker or a
// library may write too. Only the decoders' words about broken pixels fail the frame; the other
// lines are said again, libpng's warnings about extra chunks dropped.
TEST(DecoderMessages, OnlyTheDecodersComplaintsFailAFrame) {
  const DecoderMessages m = sortDecoderMessages(
      "[ WARN:0@1.2] global loadsave.cpp (1) a log line of OpenCV's\n"
      "libpng warning: iCCP: known incorrect sRGB profile\n"
      "Corrupt JPEG data: premature end of data segment\n"
      "a debug line of the tracker's\n"
      "libpng error: IDAT: CRC error\n");
  EXPECT_EQ(m.complaint, "Corrupt JPEG data: premature end of data segment");
  EXPECT_EQ(m.others, "[ WARN:0@1.2] global loadsave.cpp (1) a log line of OpenCV's\na debug line of the tracker's\n");
  const DecoderMessages quiet = sortDecoderMessages("libpng warning: tEXt: extra chunk\nsomeone else's line\n");
  EXPECT_TRUE(quiet.complaint.empty());
  EXPECT_EQ(quiet.others, "someone else's line\n");
}

}  // namespace
}  // namespace slamcmp
