#pragma once
// A texture defined everywhere in the plane (a sum of Gaussian blobs of many sizes), so an image
// of it shifted by any sub-pixel amount is exact: no interpolation error in the "true" motion. Not
// periodic and without a dominant direction, so Lucas-Kanade has no aliasing or aperture problem,
// and blobs up to 30 px wide leave structure at the top of a 3-level pyramid (1/8 scale).
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <opencv2/core.hpp>

namespace slamcmp::test {

class BlobTexture {
 public:
  // Blobs over the rectangle [-margin, width + margin) x [-margin, height + margin).
  BlobTexture(int seed, cv::Size size, int margin = 60) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> x(-margin, size.width + margin), y(-margin, size.height + margin);
    std::uniform_real_distribution<double> amplitude(20, 45), unit(0, 1);
    const double area = (size.width + 2.0 * margin) * (size.height + 2.0 * margin);
    // Every scale covers the plane about once with its blobs' 2-sigma discs: as much fine detail
    // (corners) as coarse structure.
    for (const double sigma : {2.0, 3.0, 4.5, 7.0, 11.0, 17.0, 26.0}) {
      const int count = static_cast<int>(area / (M_PI * 4 * sigma * sigma));
      for (int k = 0; k < count; ++k)
        blobs_.push_back({x(rng), y(rng), sigma, amplitude(rng) * (unit(rng) < 0.5 ? -1 : 1)});
    }
  }

  // Grey level (8 bits, rounded) at pixel (x, y) of the texture moved by (dx, dy) pixels:
  // I(x, y) = T(x - dx, y - dy).
  cv::Mat image(cv::Size size, double dx = 0, double dy = 0) const {
    cv::Mat sum(size, CV_64F, cv::Scalar(128));
    for (const Blob& b : blobs_) {
      const double cx = b.x + dx, cy = b.y + dy, reach = 4 * b.sigma;
      const int x0 = std::max(0, static_cast<int>(std::floor(cx - reach)));
      const int x1 = std::min(size.width - 1, static_cast<int>(std::ceil(cx + reach)));
      const int y0 = std::max(0, static_cast<int>(std::floor(cy - reach)));
      const int y1 = std::min(size.height - 1, static_cast<int>(std::ceil(cy + reach)));
      const double k = -0.5 / (b.sigma * b.sigma);
      for (int v = y0; v <= y1; ++v)
        for (int u = x0; u <= x1; ++u)
          sum.at<double>(v, u) += b.amplitude * std::exp(k * ((u - cx) * (u - cx) + (v - cy) * (v - cy)));
    }
    cv::Mat out;
    sum.convertTo(out, CV_8U);  // rounds and saturates
    return out;
  }

 private:
  struct Blob {
    double x, y, sigma, amplitude;  // centre (px), size (px), grey levels
  };
  std::vector<Blob> blobs_;
};

}  // namespace slamcmp::test
