#pragma once
// Image primitives the back-ends share.
#include <vector>

#include <opencv2/core.hpp>

#include "core/geometry.h"

namespace slamcmp {

// Grey 8-bit from grey, BGR or BGRA of 8 or 16 bits, or floating point in 0..1 (a view when it
// already is 8-bit grey).
cv::Mat toGrey(const cv::Mat& image);

// Level 0 is the image itself; each further level halves (OpenCV pyrDown).
std::vector<cv::Mat> buildPyramid(const cv::Mat& grey, int levels);

// Bilinear sample at (u, v) in pixel-centre coordinates; false if the 2x2 support is outside.
bool sampleBilinear(const cv::Mat& grey, double u, double v, double* value);

// Grey-level standard deviation of a patch.
double patchStdDev(const cv::Mat& patch);

}  // namespace slamcmp
