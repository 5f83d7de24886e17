#include "core/chessboard.h"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/options.h"

namespace slamcmp {

void ChessboardDetectorOptions::check() const {
  if (!(refine_window_fraction > 0 && refine_window_fraction < 0.5))
    throw OptionError("refine_window_fraction", "must be in (0, 0.5)");
  if (max_refine_half_window < 1) throw OptionError("max_refine_half_window", "must be >= 1");
}

void ChessboardDetectorOptions::checkImage(cv::Size image) const {
  requireWithinImage("max_refine_half_window", max_refine_half_window,
                     (std::min(image.width, image.height) - 5) / 2, image);
}

namespace {

// Mean grey level of the square whose centre is at grid coordinates (gi, gj) (corner units).
double squareMean(const cv::Mat& grey, const cv::Matx33d& H, double gi, double gj) {
  double sum = 0;
  int n = 0;
  for (double di : {-0.2, 0.0, 0.2})
    for (double dj : {-0.2, 0.0, 0.2}) {
      const cv::Vec3d p = H * cv::Vec3d(gi + di, gj + dj, 1.0);
      const int u = static_cast<int>(std::lround(p[0] / p[2]));
      const int v = static_cast<int>(std::lround(p[1] / p[2]));
      if (u < 0 || v < 0 || u >= grey.cols || v >= grey.rows) continue;
      sum += grey.at<uchar>(v, u);
      ++n;
    }
  return n ? sum / n : -1.0;
}

void flipRows(const ChessboardTarget& t, std::vector<cv::Point2f>& uv) {
  for (int j = 0; j < t.rows / 2; ++j)
    std::swap_ranges(uv.begin() + j * t.cols, uv.begin() + (j + 1) * t.cols,
                     uv.begin() + (t.rows - 1 - j) * t.cols);
}

// The index in `uv` of the corner that becomes (i, j) when the grid is turned by `quarter_turns`
// quarter turns (1 and 3 only for a square grid).
int turnedSource(const ChessboardTarget& t, int quarter_turns, int i, int j) {
  switch (quarter_turns) {
    case 1: return (t.cols - 1 - i) * t.cols + j;
    case 2: return (t.rows - 1 - j) * t.cols + (t.cols - 1 - i);
    case 3: return i * t.cols + (t.cols - 1 - j);
    default: return j * t.cols + i;
  }
}

}  // namespace

double minCornerSpacing(const ChessboardTarget& t, const std::vector<cv::Point2f>& uv) {
  double best = 1e30;
  for (int j = 0; j < t.rows; ++j)
    for (int i = 0; i < t.cols; ++i) {
      const cv::Point2f& p = uv[j * t.cols + i];
      if (i + 1 < t.cols) best = std::min(best, cv::norm(uv[j * t.cols + i + 1] - p));
      if (j + 1 < t.rows) best = std::min(best, cv::norm(uv[(j + 1) * t.cols + i] - p));
    }
  return best;
}

bool orderChessboardCorners(const cv::Mat& grey, const ChessboardTarget& t,
                            std::vector<cv::Point2f>& uv) {
  CV_Assert(static_cast<int>(uv.size()) == t.numCorners() && grey.type() == CV_8UC1);
  // Handedness: with X along i and Y along j, Z = X x Y points away from the camera exactly when
  // the grid's i and j directions turn clockwise in the image (v down).
  const cv::Point2f dx = uv[t.cols - 1] - uv[0];
  const cv::Point2f dy = uv[(t.rows - 1) * t.cols] - uv[0];
  if (dx.x * dy.y - dx.y * dy.x < 0) flipRows(t, uv);
  if (t.symmetric()) return true;  // both 180 degree turns look alike: handedness is all there is

  std::vector<cv::Point2f> grid;
  grid.reserve(uv.size());
  for (int j = 0; j < t.rows; ++j)
    for (int i = 0; i < t.cols; ++i) grid.emplace_back(static_cast<float>(i), static_cast<float>(j));
  const cv::Mat H = cv::findHomography(grid, uv, 0);
  if (H.empty()) return false;
  const cv::Matx33d Hm(H);
  // The square diagonally outside corner 0 must be black, its neighbour along X white; after a
  // 180 degree turn the colours swap (exactly one corner count is odd).
  const double diagonal = squareMean(grey, Hm, -0.5, -0.5);
  const double beside = squareMean(grey, Hm, 0.5, -0.5);
  const double diagonal_far = squareMean(grey, Hm, t.cols - 0.5, t.rows - 0.5);
  const double beside_far = squareMean(grey, Hm, t.cols - 1.5, t.rows - 0.5);
  double votes = 0;  // > 0: corner 0 is the origin; < 0: the far corner is
  if (diagonal >= 0 && beside >= 0) votes += beside - diagonal;
  if (diagonal_far >= 0 && beside_far >= 0) votes -= beside_far - diagonal_far;
  if (std::abs(votes) < 10) return false;
  if (votes < 0) std::reverse(uv.begin(), uv.end());
  return true;
}

void chooseSymmetricOrder(const ChessboardTarget& t, std::vector<cv::Point2f>& uv,
                          const std::vector<cv::Point2f>& reference) {
  CV_Assert(static_cast<int>(uv.size()) == t.numCorners());
  if (!t.symmetric()) return;
  const bool use_reference = reference.size() == uv.size();
  // Quarter turns (they keep the handedness, unlike a mirror): 2 for any symmetric board, 1 and 3
  // as well for a square one.
  const std::vector<int> turns = t.cols == t.rows ? std::vector<int>{0, 1, 2, 3} : std::vector<int>{0, 2};
  std::vector<cv::Point2f> best;
  double best_cost = 0;
  for (const int turn : turns) {
    std::vector<cv::Point2f> turned(uv.size());
    for (int j = 0; j < t.rows; ++j)
      for (int i = 0; i < t.cols; ++i) turned[j * t.cols + i] = uv[turnedSource(t, turn, i, j)];
    double cost = 0;
    if (use_reference) {
      for (size_t k = 0; k < turned.size(); ++k) {
        const cv::Point2f d = turned[k] - reference[k];
        cost += static_cast<double>(d.x) * d.x + static_cast<double>(d.y) * d.y;
      }
    } else {
      cost = cv::norm(turned.front());
    }
    if (best.empty() || cost < best_cost) best = std::move(turned), best_cost = cost;
  }
  uv = std::move(best);
}

std::vector<cv::Point2f> projectEveryBoardCorner(const CameraModel& camera, const ChessboardTarget& t,
                                                 const SE3& T_world_camera) {
  const SE3 T_camera_world = T_world_camera.inverse();
  std::vector<cv::Point2f> uv;
  for (const Vec3& p_world : t.cornersWorld()) {
    const Vec3 p_camera = T_camera_world * p_world;
    const Vec2 p = p_camera.z() > 0 ? camera.project(p_camera) : Vec2::Constant(std::nan(""));
    uv.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  }
  return uv;
}

std::vector<cv::Point2f> projectBoardCorners(const CameraModel& camera, const ChessboardTarget& t,
                                             const SE3& T_world_camera) {
  std::vector<cv::Point2f> uv = projectEveryBoardCorner(camera, t, T_world_camera);
  for (const cv::Point2f& p : uv)
    if (std::isnan(p.x)) return {};
  return uv;
}

void refineChessboardCorners(const cv::Mat& grey, const ChessboardTarget& t,
                             std::vector<cv::Point2f>& uv, const ChessboardDetectorOptions& options,
                             const CameraModel* camera) {
  const double spacing = minCornerSpacing(t, uv);
  // Window side 2w+1 under refine_window_fraction of a square, so it never reaches another corner.
  const int half = std::clamp(static_cast<int>((options.refine_window_fraction * spacing - 1) / 2), 1,
                              options.max_refine_half_window);
  refineCornersSubpixel(grey, half, uv, options.subpixel, camera);
}

bool detectChessboard(const cv::Mat& grey, const ChessboardTarget& t, std::vector<cv::Point2f>* uv,
                      const ChessboardDetectorOptions& options) {
  CV_Assert(grey.type() == CV_8UC1);
  int flags = cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE;
  if (options.fast_check) flags |= cv::CALIB_CB_FAST_CHECK;
  std::vector<cv::Point2f> corners;
  if (!cv::findChessboardCorners(grey, cv::Size(t.cols, t.rows), corners, flags)) return false;
  if (static_cast<int>(corners.size()) != t.numCorners()) return false;
  refineChessboardCorners(grey, t, corners, options);
  if (!orderChessboardCorners(grey, t, corners)) return false;
  chooseSymmetricOrder(t, corners);
  *uv = std::move(corners);
  return true;
}

}  // namespace slamcmp
