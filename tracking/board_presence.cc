#include "tracking/board_presence.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/statistics.h"

namespace slamcmp {

void BoardPresenceOptions::check() const {
  if (!(response_fraction > 0 && response_fraction <= 1)) throw OptionError("response_fraction", "must be in (0, 1]");
  if (!(min_corner_fraction > 0 && min_corner_fraction <= 1))
    throw OptionError("min_corner_fraction", "must be in (0, 1]");
}

namespace {

// The ring's 16 samples as offsets into the image's rows (ChESS's ring, sample n at angle n * 22.5
// degrees): samples n and n + 8 are opposite, n and n + 4 a quarter turn apart.
std::array<ptrdiff_t, 16> ringOffsets(size_t step, int radius) {
  std::array<ptrdiff_t, 16> offsets{};
  for (int n = 0; n < 16; ++n) {
    const double angle = 2 * M_PI * n / 16;
    const int dx = static_cast<int>(std::lround(radius * std::cos(angle)));
    const int dy = static_cast<int>(std::lround(radius * std::sin(angle)));
    offsets[n] = static_cast<ptrdiff_t>(dy) * static_cast<ptrdiff_t>(step) + dx;
  }
  return offsets;
}

// Five times ChESS (Bennett & Lasenby 2014, eqs. 1-4) at `p`: the sum response (opposite samples
// alike, a quarter turn apart unlike: X-junctions), minus the diff response (opposite samples
// unlike: edges), minus 16 times the difference of the ring's mean from the centre's 5-pixel mean
// (blobs). Five times, to stay in integers (within +-30600: 16 bits).
inline int response5(const uchar* p, const std::array<ptrdiff_t, 16>& ring, ptrdiff_t step) {
  int I[16];
  int ring_sum = 0;
  for (int n = 0; n < 16; ++n) ring_sum += I[n] = p[ring[n]];
  int sum = 0, diff = 0;
  for (int n = 0; n < 4; ++n) sum += std::abs(I[n] + I[n + 8] - I[n + 4] - I[n + 12]);
  for (int n = 0; n < 8; ++n) diff += std::abs(I[n] - I[n + 8]);
  const int centre_sum = p[0] + p[-1] + p[1] + p[-step] + p[step];
  return 5 * (sum - diff) - std::abs(5 * ring_sum - 16 * centre_sum);
}

}  // namespace

double chessResponse(const cv::Mat& grey, int x, int y, int radius) {
  CV_Assert(grey.type() == CV_8UC1);
  return response5(grey.ptr<uchar>(y) + x, ringOffsets(grey.step, radius), static_cast<ptrdiff_t>(grey.step)) / 5.0;
}

void BoardPresence::seen(const cv::Mat& grey, const std::vector<cv::Point2f>& uv, double spacing) {
  // The ring within a square of the board's corner (a fifth of the spacing), at most ChESS's own 5.
  const int radius = std::clamp(static_cast<int>(0.2 * spacing), 2, 5);
  const int border = radius + 2;
  const std::array<ptrdiff_t, 16> ring = ringOffsets(grey.step, radius);
  const ptrdiff_t step = static_cast<ptrdiff_t>(grey.step);
  std::vector<double> responses;
  for (const cv::Point2f& c : uv) {
    const int x = static_cast<int>(std::lround(c.x)), y = static_cast<int>(std::lround(c.y));
    if (x < border || y < border || x >= grey.cols - border || y >= grey.rows - border) continue;
    // The sub-pixel corner lies between pixels: the strongest of the nearest 3x3.
    int best = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) best = std::max(best, response5(grey.ptr<uchar>(y + dy) + x + dx, ring, step));
    responses.push_back(best);
  }
  if (responses.empty()) return;
  radius_ = radius;
  reference_response_ = median(responses);
}

bool BoardPresence::mayHoldBoard(const cv::Mat& grey, const cv::Rect& region, int num_corners) const {
  if (!options_.enabled || !learnt()) return true;
  CV_Assert(grey.type() == CV_8UC1);
  const int border = radius_ + 1;
  const cv::Rect inner = region & cv::Rect(border, border, grey.cols - 2 * border, grey.rows - 2 * border);
  if (inner.empty()) return false;
  const ptrdiff_t step = static_cast<ptrdiff_t>(grey.step);
  const std::array<ptrdiff_t, 16> ring = ringOffsets(grey.step, radius_);
  cv::Mat responses(inner.size(), CV_16S);  // 16 bits: cv::dilate takes them
  for (int y = 0; y < inner.height; ++y) {
    const uchar* p = grey.ptr<uchar>(inner.y + y) + inner.x;
    short* out = responses.ptr<short>(y);
    for (int x = 0; x < inner.width; ++x) out[x] = static_cast<short>(response5(p + x, ring, step));
  }
  // X-junctions: local maxima (5x5) over the bar.
  cv::Mat strongest;
  cv::dilate(responses, strongest, cv::Mat(), cv::Point(-1, -1), 2);
  const int bar = static_cast<int>(std::ceil(options_.response_fraction * reference_response_));  // times five, as the responses
  const int needed = static_cast<int>(std::ceil(options_.min_corner_fraction * num_corners));
  int junctions = 0;
  for (int y = 0; y < inner.height; ++y) {
    const short* r = responses.ptr<short>(y);
    const short* s = strongest.ptr<short>(y);
    for (int x = 0; x < inner.width; ++x)
      if (r[x] >= bar && r[x] >= s[x] && ++junctions >= needed) return true;
  }
  return false;
}

bool PresenceGatedDetector::detect(const cv::Mat& grey, const cv::Rect& region, std::vector<cv::Point2f>* uv) {
  if (!presence_.mayHoldBoard(grey, region, target_.numCorners())) return false;
  std::vector<cv::Point2f> found;
  if (!detectChessboard(grey(region), target_, &found, detector_)) return false;
  for (cv::Point2f& p : found) p += cv::Point2f(static_cast<float>(region.x), static_cast<float>(region.y));
  seen(grey, found);
  *uv = std::move(found);
  return true;
}

void PresenceGatedDetector::seen(const cv::Mat& grey, const std::vector<cv::Point2f>& uv) {
  presence_.seen(grey, uv, minCornerSpacing(target_, uv));
}

}  // namespace slamcmp
