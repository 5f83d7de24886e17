#include "core/image.h"

#include <cmath>

#include <opencv2/imgproc.hpp>

namespace slamcmp {

cv::Mat toGrey(const cv::Mat& image) {
  if (image.channels() == 1 && image.depth() == CV_8U) return image;
  // cvtColor takes 8 and 16-bit and single floats: any other depth is made a float first.
  const int depth = image.depth();
  cv::Mat colour = image;
  if (depth != CV_8U && depth != CV_16U && depth != CV_32F) image.convertTo(colour, CV_32F);
  cv::Mat grey;
  if (colour.channels() == 3) cv::cvtColor(colour, grey, cv::COLOR_BGR2GRAY);
  else if (colour.channels() == 4) cv::cvtColor(colour, grey, cv::COLOR_BGRA2GRAY);
  else grey = colour;
  // Floating point images (PFM, EXR, TIFF) hold 0..1, as OpenCV shows and writes them; 16 bits
  // 0..65535; other integers are grey levels as they are (saturated).
  const double scale = depth == CV_16U ? 1.0 / 257.0 : depth == CV_32F || depth == CV_64F ? 255.0 : 1.0;
  if (grey.depth() != CV_8U) grey.convertTo(grey, CV_8U, scale);
  return grey;
}

std::vector<cv::Mat> buildPyramid(const cv::Mat& grey, int levels) {
  std::vector<cv::Mat> pyramid;
  cv::buildPyramid(grey, pyramid, std::max(0, levels - 1));
  return pyramid;
}

bool sampleBilinear(const cv::Mat& grey, double u, double v, double* value) {
  const int u0 = static_cast<int>(std::floor(u));
  const int v0 = static_cast<int>(std::floor(v));
  if (u0 < 0 || v0 < 0 || u0 + 1 >= grey.cols || v0 + 1 >= grey.rows) return false;
  const double a = u - u0, b = v - v0;
  const uchar* r0 = grey.ptr<uchar>(v0) + u0;
  const uchar* r1 = grey.ptr<uchar>(v0 + 1) + u0;
  *value = (1 - b) * ((1 - a) * r0[0] + a * r0[1]) + b * ((1 - a) * r1[0] + a * r1[1]);
  return true;
}

double patchStdDev(const cv::Mat& patch) {
  cv::Scalar mean, stddev;
  cv::meanStdDev(patch, mean, stddev);
  return stddev[0];
}

}  // namespace slamcmp
