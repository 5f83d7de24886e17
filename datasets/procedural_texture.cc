#include "datasets/procedural_texture.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace slamcmp {

namespace {

constexpr int kShift = 4;  // sub-texel vertex precision of the polygon drawing (1/16 texel)

struct ShapeScale {
  double min_size, max_size;  // metres
  double per_square_metre;    // shapes per m^2
};

// Coarse to fine: large shapes give structure at a distance, small ones the corners and the
// distinctive patches seen close up (an 11x11 patch spans about 1 to 2 cm at 0.5 to 1.2 m).
constexpr ShapeScale kScales[] = {{0.08, 0.25, 20}, {0.025, 0.08, 200}, {0.006, 0.025, 2500}};

cv::Point fixedPoint(double x, double y) {
  return cv::Point(static_cast<int>(std::lround(x * (1 << kShift))),
                   static_cast<int>(std::lround(y * (1 << kShift))));
}

void drawShape(cv::Mat& image, cv::RNG& rng, double size_texels) {
  const double cx = rng.uniform(0.0, static_cast<double>(image.cols));
  const double cy = rng.uniform(0.0, static_cast<double>(image.rows));
  const int grey = rng.uniform(10, 246);
  const cv::Scalar colour(grey);
  const double a = 0.5 * size_texels;
  const double b = a * rng.uniform(0.35, 1.0);
  const double angle = rng.uniform(0.0, CV_PI);
  const int kind = rng.uniform(0, 10);
  if (kind < 5) {  // rectangle: four sharp corners
    const double c = std::cos(angle), s = std::sin(angle);
    std::vector<cv::Point> corners;
    for (const auto& [du, dv] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
      corners.push_back(fixedPoint(cx + du * a * c - dv * b * s, cy + du * a * s + dv * b * c));
    cv::fillConvexPoly(image, corners, colour, cv::LINE_AA, kShift);
  } else if (kind < 7) {  // triangle
    std::vector<cv::Point> corners;
    for (int k = 0; k < 3; ++k) {
      const double phi = angle + k * 2.0 * CV_PI / 3.0 + rng.uniform(-0.5, 0.5);
      corners.push_back(fixedPoint(cx + a * std::cos(phi), cy + a * std::sin(phi)));
    }
    cv::fillConvexPoly(image, corners, colour, cv::LINE_AA, kShift);
  } else {  // ellipse: blobs between the corners
    cv::ellipse(image, fixedPoint(cx, cy),
                cv::Size(static_cast<int>(a * (1 << kShift)), static_cast<int>(b * (1 << kShift))),
                angle * 180.0 / CV_PI, 0, 360, colour, cv::FILLED, cv::LINE_AA, kShift);
  }
}

}  // namespace

cv::Mat makeClutterTexture(double size_u, double size_v, double texel, std::uint64_t seed) {
  const int width = std::max(2, static_cast<int>(std::ceil(size_u / texel)));
  const int height = std::max(2, static_cast<int>(std::ceil(size_v / texel)));
  cv::RNG rng(seed * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull);
  cv::Mat image(height, width, CV_8U, cv::Scalar(rng.uniform(90, 170)));
  const double area = size_u * size_v;
  for (const ShapeScale& scale : kScales) {
    const int count = static_cast<int>(std::ceil(area * scale.per_square_metre));
    for (int k = 0; k < count; ++k) {
      // Sizes uniform in log scale: as many small shapes of each size as large ones.
      const double size = scale.min_size * std::pow(scale.max_size / scale.min_size, rng.uniform(0.0, 1.0));
      drawShape(image, rng, size / texel);
    }
  }
  // Fine grain (paper, paint): makes flat areas textured and every patch unique.
  cv::Mat grain(height, width, CV_16S);
  rng.fill(grain, cv::RNG::NORMAL, 0, 10);
  cv::GaussianBlur(grain, grain, cv::Size(3, 3), 0.7);
  cv::Mat out;
  cv::add(image, grain, out, cv::noArray(), CV_8U);
  return out;
}

}  // namespace slamcmp
