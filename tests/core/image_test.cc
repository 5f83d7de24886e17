// Image primitives: bilinear sampling, grey conversion, pyramids, patch contrast.
#include "core/image.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace slamcmp {
namespace {

cv::Mat randomImage(int width, int height, unsigned seed) {
  cv::Mat img(height, width, CV_8UC1);
  cv::RNG rng(seed);
  rng.fill(img, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(img, img, cv::Size(5, 5), 1.0);  // some spatial correlation, like a real image
  return img;
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
  // Floating point images hold 0..1 (PFM, EXR): a mid grey stays mid grey, beyond 1 saturates.
  const cv::Mat grey32 = (cv::Mat_<float>(1, 3) << 0.f, 0.5f, 1.5f);
  EXPECT_EQ(toGrey(grey32).at<uchar>(0, 1), 128);
  EXPECT_EQ(toGrey(grey32).at<uchar>(0, 2), 255);
  cv::Mat bgr64(2, 2, CV_64FC3, cv::Scalar(0.25, 0.25, 0.25));
  EXPECT_EQ(toGrey(bgr64).at<uchar>(1, 1), 64);
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
