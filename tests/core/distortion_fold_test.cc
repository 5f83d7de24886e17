// The fold check on lens models (core/distortion_fold.h): every real camera in ../shared/datasets
// and every published calibration there passes, and on those the projection is one-to-one over the
// image (undistorting a pixel and distorting it again gives it back); models that fold inside the
// image, radially, through their tangential terms or at a pole of the rational model, are refused
// with a message naming the file and distortion_coefficients.
#include <gtest/gtest.h>

#include <string>

#include "core/camera.h"
#include "core/distortion_fold.h"
#include "core/error.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

CameraModel camera(int width, int height, double fx, double fy, double cx, double cy,
                   const std::array<double, 8>& distortion, int num_distortion = 5) {
  CameraModel c;
  c.width = width;
  c.height = height;
  c.fx = fx, c.fy = fy, c.cx = cx, c.cy = cy;
  c.distortion = distortion;
  c.num_distortion = num_distortion;
  return c;
}

// The 160x120 camera of the bad-input corpus with another distortion.
CameraModel small(const std::array<double, 8>& distortion, int num_distortion = 5) {
  return camera(160, 120, 150, 150, 79.5, 59.5, distortion, num_distortion);
}

// Every pixel of a 32x24 grid over the image (corners included) comes back from
// distort(undistort(pixel)).
void expectRoundTripOverImage(const CameraModel& c) {
  for (int i = 0; i <= 32; ++i)
    for (int j = 0; j <= 24; ++j) {
      const Vec2 uv(-0.5 + c.width * i / 32.0, -0.5 + c.height * j / 24.0);
      const Vec2 back = c.pixelFromNormalised(c.distort(c.undistortPixel(uv)));
      EXPECT_LT((back - uv).norm(), 1e-6) << uv.transpose();
    }
}

TEST(DistortionFold, AcceptsTheRealCameraFiles) {
  SLAMCMP_REQUIRE_SHARED(data);
  // tum_fr1_rpy's k1 0.262, k2 -0.953, k3 1.163 bends its radial map most, and stays increasing.
  for (const std::string file : {"/vamr_checkerboard/camera.yaml", "/tum_fr1_rpy/camera.yaml",
                                 "/calibration/opencv_left/left_intrinsics.yml"}) {
    const CameraModel c = readCameraYaml(data + file);
    EXPECT_EQ(distortionFold(c), "") << file;
    expectRoundTripOverImage(c);
  }
}

TEST(DistortionFold, AcceptsThePublishedCalibrations) {
  // calibration/bouguet's Calib_Results_reference_n20.txt and calibration/zhang's
  // calibration-result-zhang-withdistortion.txt (640x480 both).
  CameraModel bouguet = camera(640, 480, 657.463, 657.947, 303.137, 242.569,
                               {-0.254026, 0.121435, -0.000209, 0.0000194, 0, 0, 0, 0});
  CameraModel zhang = camera(640, 480, 832.5, 832.53, 303.959, 206.585, {-0.228601, 0.190353, 0, 0, 0, 0, 0, 0}, 4);
  zhang.skew = 0.204494;
  for (const CameraModel& c : {bouguet, zhang}) {
    EXPECT_EQ(distortionFold(c), "");
    expectRoundTripOverImage(c);
  }
}

TEST(DistortionFold, AcceptsStrongButMonotonicLenses) {
  EXPECT_EQ(distortionFold(small({-0.2, 0, 0, 0, 0, 0, 0, 0})), "");  // peaks at 0.86, past 1.1x the corner
  EXPECT_EQ(distortionFold(small({5, 0, 0, 0, 0, 0, 0, 0})), "");     // strong pincushion: never folds
  EXPECT_EQ(distortionFold(small({0, 0, 0.2, 0, 0, 0, 0, 0})), "");
  EXPECT_EQ(distortionFold(small({})), "");
}

struct FoldCase {
  std::string name;
  CameraModel camera;
  std::string says;  // in the message
};
void PrintTo(const FoldCase& c, std::ostream* os) { *os << c.name; }

class FoldingLens : public ::testing::TestWithParam<FoldCase> {};

TEST_P(FoldingLens, IsRefusedNamingTheFileAndField) {
  const FoldCase& fold = GetParam();
  EXPECT_NE(distortionFold(fold.camera).find(fold.says), std::string::npos) << distortionFold(fold.camera);
  try {
    checkPlausibleIntrinsics(fold.camera, "camera.yaml", "camera_matrix");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("camera.yaml: distortion_coefficients: the lens model folds", 0), 0)
        << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, FoldingLens,
    ::testing::Values(
        // r (1 - 5 r^2) peaks at r = 0.26, a third of the way to the corner (r = 0.67).
        FoldCase{"k1_minus_5", small({-5, 0, 0, 0, 0, 0, 0, 0}), "stops growing at normalised radius 0.17"},
        // Peaks at r = 0.82, which maps to 0.54: inside the corner.
        FoldCase{"k1_minus_half", small({-0.5, 0, 0, 0, 0, 0, 0, 0}), "stops growing"},
        // r (1 - 0.3 r^2) peaks at 0.70: past the corner, short of 1.1x it.
        FoldCase{"k1_folding_within_the_margin", small({-0.3, 0, 0, 0, 0, 0, 0, 0}), "but must grow to 0.733"},
        FoldCase{"k3_minus_2", small({0, 0, 0, 0, -2, 0, 0, 0}), "stops growing at normalised radius 0.55"},
        // The rational model's denominator 1 + r^2 bends r / (1 + r^2) back at r = 1 (0.5 distorted).
        FoldCase{"k4_rational", small({0, 0, 0, 0, 0, 1, 0, 0}, 8), "stops growing at normalised radius 0.5"},
        FoldCase{"p1_tangential", small({0, 0, 0.5, 0, 0, 0, 0, 0}), "tangential terms"},
        FoldCase{"p2_tangential", small({0, 0, 0, -0.6, 0, 0, 0, 0}), "tangential terms"}),
    [](const ::testing::TestParamInfo<FoldCase>& info) { return info.param.name; });

}  // namespace
}  // namespace slamcmp
