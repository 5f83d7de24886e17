#include "hybrid/exposure_shift.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "hybrid/edge_width.h"

namespace slamcmp {

void ExposureShiftOptions::check() const {
  if (!(max_exposure >= 0 && max_exposure <= 1)) throw OptionError("max_exposure", "must be in [0, 1]");
  if (min_corners < 1) throw OptionError("min_corners", "must be >= 1");
}

const cv::Point2f* ExposureShift::CornerFrame::find(int id) const {
  const auto it = std::find(ids.begin(), ids.end(), id);
  return it == ids.end() ? nullptr : &uv[static_cast<size_t>(it - ids.begin())];
}

double ExposureShift::exposure() const {
  if (frames_fitted_ < 2 || n_ < 3) return 0;  // a slope needs two motions
  const double vxx = sxx_ - sx_ * sx_ / n_, vxy = sxy_ - sx_ * sy_ / n_, vyy = syy_ - sy_ * sy_ / n_;
  if (!(vxx > 1e-12 * sxx_)) return 0;  // the board has not moved across its edges unevenly yet
  const double slope = vxy / vxx;
  // A frame's edges share its motion and much of their error: its standard error counted over
  // frames, not edges (one frame's alone put wall_turn seed 7's unblurred start at 0.57 of its
  // frame interval).
  const double standard_error = std::sqrt(std::max(0.0, (vyy - slope * vxy) / (n_ - 2)) / vxx * n_ / frames_fitted_);
  return std::sqrt(std::max(0.0, slope - 2 * standard_error));
}

std::vector<ExposureShift::CornerMotion> ExposureShift::cornerMotions() const {
  // Over uneven steps h1, h2: the velocity at this frame's time by the second-order backward
  // difference (the last step alone lags by half the acceleration), the acceleration by the
  // second divided difference; pixels/s and pixels/s^2.
  const CornerFrame &first = frames_[0], &last = frames_[1], &now = frames_[2];
  const double h1 = last.timestamp - first.timestamp, h2 = now.timestamp - last.timestamp;
  const double c_now = (2 * h2 + h1) / (h2 * (h1 + h2)), c_last = -(h1 + h2) / (h1 * h2),
               c_first = h2 / (h1 * (h1 + h2));
  std::vector<CornerMotion> motions;
  for (size_t k = 0; k < now.ids.size(); ++k) {
    const cv::Point2f *u1 = last.find(now.ids[k]), *u0 = first.find(now.ids[k]);
    if (!u1 || !u0) continue;
    const Vec2 p2(now.uv[k].x, now.uv[k].y), p1(u1->x, u1->y), p0(u0->x, u0->y);
    motions.push_back({now.ids[k], p2, c_now * p2 + c_last * p1 + c_first * p0,
                       ((p2 - p1) / h2 - (p1 - p0) / h1) * (2.0 / (h1 + h2))});
  }
  return motions;
}

void ExposureShift::measureEdges(const cv::Mat& grey, int cols, const std::vector<CornerMotion>& motions) {
  CV_Assert(cols > 0);
  int max_id = -1;
  for (const CornerMotion& c : motions) max_id = std::max(max_id, c.id);
  std::vector<int> motion_of(static_cast<size_t>(max_id + 1), -1);  // by corner id
  for (size_t k = 0; k < motions.size(); ++k) motion_of[static_cast<size_t>(motions[k].id)] = static_cast<int>(k);
  for (const CornerMotion& a : motions) {
    // The edges to the next corner along the row and along the column.
    for (const int other : {a.id % cols + 1 < cols ? a.id + 1 : -1, a.id + cols}) {
      if (other < 0 || other > max_id || motion_of[static_cast<size_t>(other)] < 0) continue;
      const CornerMotion& b = motions[static_cast<size_t>(motion_of[static_cast<size_t>(other)])];
      const Vec2 along = b.uv - a.uv;
      const double length = along.norm();
      if (!(length > 4)) continue;
      const Vec2 normal(-along.y() / length, along.x() / length);
      // Halfway between the corners the edge is a step between two squares, a quarter square or
      // more from either junction.
      const auto spread = edgeSpread(grey, 0.5 * (a.uv + b.uv), normal, std::min(0.3 * length, 8.0));
      if (!spread) continue;
      const double across = normal.dot(0.5 * (a.velocity + b.velocity));
      const double x = across * across / 12.0;
      n_ += 1;
      sx_ += x;
      sy_ += *spread;
      sxx_ += x * x;
      sxy_ += x * *spread;
      syy_ += *spread * *spread;
    }
  }
}

void ExposureShift::addFrame(double timestamp, const cv::Mat& grey, int cols, const std::vector<int>& ids,
                             const std::vector<cv::Point2f>& uv) {
  frames_.push_back({timestamp, ids, uv});
  if (frames_.size() > 3) frames_.erase(frames_.begin());
  covariance_.setZero();
  if (options_.max_exposure <= 0 || frames_.size() < 3) return;
  const double dt1 = frames_[1].timestamp - frames_[0].timestamp, dt2 = frames_[2].timestamp - frames_[1].timestamp;
  // Frames in a row: over a skipped frame (a step more than 1.5 times the other) neither the
  // motion nor the acceleration is a frame's.
  if (!(dt1 > 0 && dt2 > 0) || std::max(dt1, dt2) > 1.5 * std::min(dt1, dt2)) return;
  const std::vector<CornerMotion> motions = cornerMotions();
  // The exposure is the camera's: once the fit holds kSettledFrames frames, one frame in
  // kSettledInterval adds to it (the edges cost 0.06 ms a frame, a twentieth of hybrid's).
  constexpr int kSettledFrames = 30, kSettledInterval = 10;
  if (frames_fitted_ < kSettledFrames || ++frames_since_fit_ >= kSettledInterval) {
    frames_since_fit_ = 0;
    const double edges = n_;
    measureEdges(grey, cols, motions);
    if (n_ > edges) ++frames_fitted_;
  }
  if (static_cast<int>(motions.size()) < options_.min_corners) return;
  Vec2 acceleration = Vec2::Zero();
  for (const CornerMotion& c : motions) acceleration += c.acceleration;
  acceleration /= static_cast<double>(motions.size());
  const double exposure_s = std::min(exposure(), options_.max_exposure * dt2);
  const double sigma = exposure_s * exposure_s / 24.0 * acceleration.norm();
  covariance_ = Mat2::Identity() * sigma * sigma;
}

}  // namespace slamcmp
