#pragma once
// Image primitives the back-ends share.
#include <vector>

#include <opencv2/core.hpp>

#include "core/geometry.h"

namespace slamcmp {

// Grey 8-bit from grey, BGR or BGRA (a view when it already is).
cv::Mat toGrey(const cv::Mat& image);

// Level 0 is the image itself; each further level halves (OpenCV pyrDown).
std::vector<cv::Mat> buildPyramid(const cv::Mat& grey, int levels);

// Bilinear sample at (u, v) in pixel-centre coordinates; false if the 2x2 support is outside.
bool sampleBilinear(const cv::Mat& grey, double u, double v, double* value);

// A size x size patch (size odd) centred at `centre` with sub-pixel accuracy, as CV_32F.
// Returns false if any sample falls outside the image.
bool extractPatch(const cv::Mat& grey, const Vec2& centre, int size, cv::Mat* patch);

// Normalised cross-correlation of two patches of the same size (CV_32F or CV_8U) in [-1, 1];
// 0 if either is flat.
double normalisedCrossCorrelation(const cv::Mat& a, const cv::Mat& b);

// Grey-level standard deviation of a patch.
double patchStdDev(const cv::Mat& patch);

}  // namespace slamcmp
