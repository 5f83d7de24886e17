// Image primitives: normalised cross-correlation, sub-pixel patches, grey conversion, pyramids.
#include "core/image.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <random>

namespace slamcmp {
namespace {

cv::Mat randomImage(int width, int height, unsigned seed) {
  cv::Mat img(height, width, CV_8UC1);
  cv::RNG rng(seed);
  rng.fill(img, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(img, img, cv::Size(5, 5), 1.0);  // some spatial correlation, like a real image
  return img;
}

TEST(Image, NccOfAPatchWithItselfItsNegativeAndAFlatPatch) {
  const cv::Mat img = randomImage(64, 48, 1);
  const cv::Mat patch = img(cv::Rect(10, 10, 11, 11)).clone();
  EXPECT_NEAR(normalisedCrossCorrelation(patch, patch), 1.0, 1e-12);
  cv::Mat negative;
  cv::subtract(cv::Scalar(255), patch, negative);
  EXPECT_NEAR(normalisedCrossCorrelation(patch, negative), -1.0, 1e-12);
  const cv::Mat flat(11, 11, CV_8UC1, cv::Scalar(77));
  EXPECT_EQ(normalisedCrossCorrelation(patch, flat), 0.0);
  EXPECT_EQ(normalisedCrossCorrelation(flat, flat), 0.0);
  // Invariant to gain and offset, in float as well.
  cv::Mat brighter;
  patch.convertTo(brighter, CV_32F, 0.5, 40.0);
  EXPECT_NEAR(normalisedCrossCorrelation(patch, brighter), 1.0, 1e-6);
  // Unrelated patches correlate weakly.
  const cv::Mat other = randomImage(64, 48, 2)(cv::Rect(30, 20, 11, 11)).clone();
  EXPECT_LT(std::abs(normalisedCrossCorrelation(patch, other)), 0.8);
}

TEST(Image, ExtractPatchSamplesBilinearlyAtSubPixelCentres) {
  const cv::Mat img = randomImage(80, 60, 3);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(8.0, 70.0), v(8.0, 50.0);
  for (int k = 0; k < 20; ++k) {
    const Vec2 centre(u(rng), v(rng));
    cv::Mat patch;
    ASSERT_TRUE(extractPatch(img, centre, 11, &patch));
    ASSERT_EQ(patch.type(), CV_32F);
    ASSERT_EQ(patch.size(), cv::Size(11, 11));
    for (int r = 0; r < 11; ++r)
      for (int c = 0; c < 11; ++c) {
        double expected;
        ASSERT_TRUE(sampleBilinear(img, centre.x() + c - 5, centre.y() + r - 5, &expected));
        EXPECT_NEAR(patch.at<float>(r, c), expected, 0.02) << "at " << centre.transpose();
      }
  }
  // At an integer centre the patch is the pixels themselves (OpenCV interpolates in float).
  cv::Mat patch;
  ASSERT_TRUE(extractPatch(img, Vec2(20, 30), 5, &patch));
  for (int r = 0; r < 5; ++r)
    for (int c = 0; c < 5; ++c)
      EXPECT_NEAR(patch.at<float>(r, c), img.at<uchar>(28 + r, 18 + c), 0.01);
  // Beyond the border there is no patch.
  EXPECT_FALSE(extractPatch(img, Vec2(3.5, 30), 11, &patch));
  EXPECT_FALSE(extractPatch(img, Vec2(40, 56.2), 11, &patch));
}

TEST(Image, SampleBilinearInterpolatesAndRefusesOutside) {
  cv::Mat img = (cv::Mat_<uchar>(2, 2) << 0, 100, 200, 40);
  double value;
  ASSERT_TRUE(sampleBilinear(img, 0.25, 0.5, &value));
  // Row 0 at u = 0.25: 25; row 1: 160; halfway: 92.5.
  EXPECT_DOUBLE_EQ(value, 92.5);
  ASSERT_TRUE(sampleBilinear(img, 0.0, 0.0, &value));
  EXPECT_DOUBLE_EQ(value, 0.0);
  EXPECT_FALSE(sampleBilinear(img, 1.0, 0.0, &value));  // the 2x2 support leaves the image
  EXPECT_FALSE(sampleBilinear(img, -0.1, 0.0, &value));
}

TEST(Image, GreyConversionAndPyramid) {
  cv::Mat bgr(30, 40, CV_8UC3, cv::Scalar(10, 100, 200));
  const cv::Mat grey = toGrey(bgr);
  ASSERT_EQ(grey.type(), CV_8UC1);
  EXPECT_NEAR(grey.at<uchar>(5, 5), 0.114 * 10 + 0.587 * 100 + 0.299 * 200, 1.0);
  cv::Mat grey16(30, 40, CV_16UC1, cv::Scalar(65535));
  EXPECT_EQ(toGrey(grey16).at<uchar>(0, 0), 255);
  const auto pyramid = buildPyramid(randomImage(64, 48, 5), 3);
  ASSERT_EQ(pyramid.size(), 3u);
  EXPECT_EQ(pyramid[1].size(), cv::Size(32, 24));
  EXPECT_EQ(pyramid[2].size(), cv::Size(16, 12));
  EXPECT_NEAR(patchStdDev(cv::Mat(5, 5, CV_8UC1, cv::Scalar(9))), 0.0, 1e-12);
  const cv::Mat two = (cv::Mat_<uchar>(1, 2) << 0, 20);
  EXPECT_NEAR(patchStdDev(two), 10.0, 1e-12);
}

}  // namespace
}  // namespace slamcmp
