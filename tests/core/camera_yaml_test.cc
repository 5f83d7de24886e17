// camera.yaml: the real files, a write/read round trip, and every malformed case answered with an
// InputError that names the file and the field.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/camera.h"
#include "core/error.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

TEST(CameraYaml, ReadsVamrCamera) {
  SLAMCMP_REQUIRE_SHARED(data);
  const CameraModel c = readCameraYaml(data + "/vamr_checkerboard/camera.yaml");
  EXPECT_EQ(c.width, 752);
  EXPECT_EQ(c.height, 480);
  EXPECT_EQ(c.fx, 4.2050671199999999e+02);
  EXPECT_EQ(c.fy, 4.2061094000000003e+02);
  EXPECT_EQ(c.cx, 3.5520829800000001e+02);
  EXPECT_EQ(c.cy, 2.5033678699999999e+02);
  EXPECT_EQ(c.skew, 0.0);
  EXPECT_EQ(c.num_distortion, 5);
  EXPECT_EQ(c.distortion[0], -2.9660775599966921e-01);
  EXPECT_EQ(c.distortion[1], 8.0816841245402546e-02);
  for (int i = 2; i < 8; ++i) EXPECT_EQ(c.distortion[i], 0.0) << i;
}

TEST(CameraYaml, ReadsTumFreiburg1Camera) {
  SLAMCMP_REQUIRE_SHARED(data);
  const CameraModel c = readCameraYaml(data + "/tum_fr1_rpy/camera.yaml");
  EXPECT_EQ(c.width, 640);
  EXPECT_EQ(c.height, 480);
  EXPECT_EQ(c.fx, 5.1730640800000003e+02);
  EXPECT_EQ(c.fy, 5.1646921499999996e+02);
  EXPECT_EQ(c.cx, 3.1864303999999998e+02);
  EXPECT_EQ(c.cy, 2.5531398899999999e+02);
  EXPECT_EQ(c.num_distortion, 5);
  const std::array<double, 5> d = {2.6238299999999998e-01, -9.5310399999999995e-01,
                                   -5.3579999999999999e-03, 2.6280000000000001e-03,
                                   1.1633140000000000e+00};
  for (int i = 0; i < 5; ++i) EXPECT_EQ(c.distortion[i], d[i]) << i;
}

TEST(CameraYaml, WriteReadRoundTripKeepsEveryValue) {
  test::TempDir dir;
  for (int n : {4, 5, 8}) {
    CameraModel c;
    c.width = 1280;
    c.height = 720;
    c.fx = 1001.123456789012;
    c.fy = 999.987654321098;
    c.cx = 640.5;
    c.cy = 359.25;
    c.num_distortion = n;
    for (int i = 0; i < n; ++i) c.distortion[i] = 0.01 * (i + 1) * (i % 2 ? -1 : 1) + 1e-13;
    const std::string path = dir.file("camera" + std::to_string(n) + ".yaml");
    writeCameraYaml(path, c, 0.25);
    const CameraModel back = readCameraYaml(path);
    EXPECT_EQ(back.width, c.width);
    EXPECT_EQ(back.height, c.height);
    EXPECT_EQ(back.K(), c.K());
    EXPECT_EQ(back.num_distortion, n);
    EXPECT_EQ(back.distortion, c.distortion);
  }
}

// A calibration that estimated skew (Zhang's published one: 0.204494 px of fx 832.5) is read as written.
TEST(CameraYaml, ReadsARealisticSkew) {
  test::TempDir dir;
  CameraModel c;
  c.width = 640;
  c.height = 480;
  c.fx = 832.5;
  c.fy = 832.53;
  c.cx = 303.959;
  c.cy = 206.585;
  c.skew = 0.204494;
  c.num_distortion = 4;
  writeCameraYaml(dir.file("camera.yaml"), c);
  EXPECT_EQ(readCameraYaml(dir.file("camera.yaml")).skew, c.skew);
}

// The body of a valid camera.yaml with one part replaced.
std::string cameraYaml(const std::string& size = "image_width: 640\nimage_height: 480\n",
                       const std::string& K =
                           "   rows: 3\n   cols: 3\n   dt: d\n"
                           "   data: [ 500., 0., 320., 0., 500., 240., 0., 0., 1. ]\n",
                       const std::string& dist =
                           "   rows: 1\n   cols: 5\n   dt: d\n"
                           "   data: [ -0.1, 0.01, 0., 0., 0. ]\n") {
  return "%YAML:1.0\n---\n" + size + "camera_matrix: !!opencv-matrix\n" + K +
         "distortion_coefficients: !!opencv-matrix\n" + dist;
}

struct BadCameraCase {
  std::string name;
  std::string content;  // "" means: no file at all
  std::string field;    // the message must name it ("" when the whole file is at fault)
};

// gtest prints the parameter by its name.
void PrintTo(const BadCameraCase& c, std::ostream* os) { *os << c.name; }

class BadCameraYaml : public ::testing::TestWithParam<BadCameraCase> {};

TEST_P(BadCameraYaml, ThrowsInputErrorNamingFileAndField) {
  const BadCameraCase& bad = GetParam();
  test::TempDir dir;
  const std::string path = dir.file("camera.yaml");
  if (!bad.content.empty()) test::writeText(path, bad.content);
  try {
    readCameraYaml(path);
    FAIL() << "accepted: " << bad.name;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(bad.field), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadCameraYaml,
    ::testing::Values(
        BadCameraCase{"missing_file", "", ""}, BadCameraCase{"empty_file", "\n", ""},
        BadCameraCase{"malformed_yaml", "%YAML:1.0\n---\nimage_width: [640\nimage_height: : 480\n",
                      ""},
        BadCameraCase{"missing_width", cameraYaml("image_height: 480\n"), "image_width"},
        BadCameraCase{"width_not_integer", cameraYaml("image_width: wide\nimage_height: 480\n"),
                      "image_width"},
        BadCameraCase{"matrix_2x3",
                      cameraYaml("image_width: 640\nimage_height: 480\n",
                                 "   rows: 2\n   cols: 3\n   dt: d\n"
                                 "   data: [ 500., 0., 320., 0., 500., 240. ]\n"),
                      "camera_matrix"},
        BadCameraCase{"matrix_bad_bottom_row",
                      cameraYaml("image_width: 640\nimage_height: 480\n",
                                 "   rows: 3\n   cols: 3\n   dt: d\n"
                                 "   data: [ 500., 0., 320., 0., 500., 240., 0., 0., 2. ]\n"),
                      "camera_matrix"},
        BadCameraCase{"six_distortion_coefficients",
                      cameraYaml("image_width: 640\nimage_height: 480\n",
                                 "   rows: 3\n   cols: 3\n   dt: d\n"
                                 "   data: [ 500., 0., 320., 0., 500., 240., 0., 0., 1. ]\n",
                                 "   rows: 1\n   cols: 6\n   dt: d\n"
                                 "   data: [ -0.1, 0.01, 0., 0., 0., 0. ]\n"),
                      "distortion_coefficients"},
        BadCameraCase{"skew_implausible",  // at most 0.01 fx = 5 px
                      cameraYaml("image_width: 640\nimage_height: 480\n",
                                 "   rows: 3\n   cols: 3\n   dt: d\n"
                                 "   data: [ 500., 5.5, 320., 0., 500., 240., 0., 0., 1. ]\n"),
                      "camera_matrix: skew (K[0][1]) 5.5 px is not plausible"},
        BadCameraCase{"nan_focal",
                      cameraYaml("image_width: 640\nimage_height: 480\n",
                                 "   rows: 3\n   cols: 3\n   dt: d\n"
                                 "   data: [ .nan, 0., 320., 0., 500., 240., 0., 0., 1. ]\n"),
                      "camera_matrix"},
        BadCameraCase{"nan_distortion",
                      cameraYaml("image_width: 640\nimage_height: 480\n",
                                 "   rows: 3\n   cols: 3\n   dt: d\n"
                                 "   data: [ 500., 0., 320., 0., 500., 240., 0., 0., 1. ]\n",
                                 "   rows: 1\n   cols: 5\n   dt: d\n"
                                 "   data: [ -0.1, .nan, 0., 0., 0. ]\n"),
                      "distortion_coefficients"},
        BadCameraCase{"negative_focal",
                      cameraYaml("image_width: 640\nimage_height: 480\n",
                                 "   rows: 3\n   cols: 3\n   dt: d\n"
                                 "   data: [ -500., 0., 320., 0., 500., 240., 0., 0., 1. ]\n"),
                      "camera_matrix"},
        BadCameraCase{"zero_height", cameraYaml("image_width: 640\nimage_height: 0\n"),
                      "image size"},
        // r (1 - 5 r^2) stops growing at a quarter of the way to the corner (core/distortion_fold.h).
        BadCameraCase{"distortion_folding_inside_the_image",
                      cameraYaml("image_width: 640\nimage_height: 480\n",
                                 "   rows: 3\n   cols: 3\n   dt: d\n"
                                 "   data: [ 500., 0., 320., 0., 500., 240., 0., 0., 1. ]\n",
                                 "   rows: 1\n   cols: 5\n   dt: d\n"
                                 "   data: [ -5., 0., 0., 0., 0. ]\n"),
                      "distortion_coefficients: the lens model folds"}),
    [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace slamcmp
