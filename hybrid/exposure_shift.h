#pragma once
// A motion-blurred frame shows each board corner where it was on average over the exposure, which
// is where it was at mid-exposure only while the image moves at a constant rate. Accelerating at
// a (pixels/s^2), a corner exposed for T seconds is seen a T^2 / 24 off (the mean of a t^2 / 2
// over t in [-T/2, T/2]), every corner alike: a shift the board's own pose takes up, which no
// scatter about the board shows and a constant-velocity filter does not predict (tv1 rendered
// with `synth --blur 3`: the corners' mean up to 0.08 px off; hybrid's NEES 65 where the
// unblurred render scores 2.5).
//
// The shift's covariance for the next frame is (T^2 / 24 |a|)^2 per axis, a measured from the
// corners kept in the last three frames. T is the exposure (seconds, at most max_exposure of the
// frame interval), estimated from the board's edges, which widen across themselves by
// (T v.n)^2 / 12 (pixels^2; hybrid/edge_width.h) when the image moves at v pixels/s. Over the run
// the edges' spread is fitted as s0 + T^2 (v.n)^2 / 12 by least squares, and T^2 taken at the
// fit's lower bound (the slope less two standard errors, counted over the frames fitted): no
// shift until the edges show a blur beyond doubt, so that an unblurred run stays as it was. In
// seconds, not frames: frame times that jitter leave a shutter's time as it is. On tv1's first
// 120 frames rendered with `--blur 3` (the shutter open the whole frame) T is 0.91-0.95 of the
// frame interval; unblurred, and with noise (2 grey levels), 0 throughout, where the fit itself
// gives 0.03-0.09 of it (the edges' spread varies by a hundredth of a pixel^2 with where they
// fall between pixels) and its upper bound 0.13 (either moved unblurred runs: wall_turn seed 51's
// ATE 0.62 -> 0.71 mm, seed 9's gap 0.9998 -> 1.003 of its allowance).
//
// Only the corners' mean acceleration is held, the image's translation: a roll or a change of
// scale accelerates the corners apart, and their shifts (each T^2 / 24 of its own acceleration)
// then cancel in the mean though each is there.
#include <vector>

#include <opencv2/core.hpp>

#include "core/geometry.h"

namespace slamcmp {

struct ExposureShiftOptions {
  double max_exposure = 1.0;  // the longest the shutter can be open, over the frame interval; 0: no shift
  int min_corners = 4;        // corners kept in each of the three frames, for an acceleration
  template <class V>
  void visit(V& v) {
    v("max_exposure", max_exposure,
      "the longest the shutter can be open, over the frame interval (1 bounds every camera; 0: no shared shift); "
      "the exposure is estimated from the board's edges within it");
    v("min_corners", min_corners, "corners kept in each of the last three frames for the board's image acceleration");
  }
  void check() const;
};

class ExposureShift {
 public:
  explicit ExposureShift(const ExposureShiftOptions& options) : options_(options) {}

  // The corners kept in the frame at `timestamp` (ids on a board `cols` corners wide, distorted
  // pixels in `grey`); an empty set when the board was not measured.
  void addFrame(double timestamp, const cv::Mat& grey, int cols, const std::vector<int>& ids,
                const std::vector<cv::Point2f>& uv);
  // The covariance (pixels^2) of the shift every corner of the next frame shares: zero until three
  // evenly spaced frames have measured the same corners.
  const Mat2& covariance() const { return covariance_; }
  // Forgets the last frames' corners (a restart), not the exposure fitted so far.
  void forgetFrames() {
    frames_.clear();
    covariance_.setZero();
  }
  // The exposure fitted so far, seconds (its lower bound; 0 before the edges show a blur).
  double exposure() const;

 private:
  struct CornerFrame {
    double timestamp = 0;
    std::vector<int> ids;
    std::vector<cv::Point2f> uv;
    const cv::Point2f* find(int id) const;
  };
  // A corner kept in the last three frames: where it is now, its velocity and acceleration.
  struct CornerMotion {
    int id = 0;
    Vec2 uv, velocity, acceleration;
  };
  std::vector<CornerMotion> cornerMotions() const;  // of frames_, three in a row
  // Each edge between two such corners: its spread against its motion across it.
  void measureEdges(const cv::Mat& grey, int cols, const std::vector<CornerMotion>& motions);
  ExposureShiftOptions options_;
  std::vector<CornerFrame> frames_;  // the last three, oldest first
  Mat2 covariance_ = Mat2::Zero();
  // The least-squares sums of spread y (pixels^2) against x = (v.n)^2 / 12 (v in pixels/s) over
  // every edge fitted.
  double n_ = 0, sx_ = 0, sy_ = 0, sxx_ = 0, sxy_ = 0, syy_ = 0;
  int frames_fitted_ = 0;    // frames whose edges are in those sums
  int frames_since_fit_ = 0;  // frames in a row since the last whose edges were fitted
};

}  // namespace slamcmp
