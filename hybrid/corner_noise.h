#pragma once
// The board corners' measurement noise estimated from their own scatter about the board plane
// (an a-posteriori variance factor, as in least-squares adjustment: Förstner and Wrobel,
// "Photogrammetric Computer Vision", 2016, sec. 4.2.3). In each frame the kept corners' distances
// to the homography through them hold 2m - 8 degrees of freedom of pure corner noise, whatever
// the filter's state: the pooled sum of their squares over those degrees of freedom is the
// variance of a corner along each axis. The estimate follows the image (rendered corners 0.01 px,
// a real board 0.1-0.3 px) instead of one value set for both.
#include <vector>

namespace slamcmp {

struct CornerNoiseOptions {
  bool enabled = true;           // off: the corners keep their set pixel_sigma
  double min_pixel_sigma = 0.01;  // pixels: the estimate's floor (the homography absorbs some errors)
  double time_constant_frames = 30;  // a view's residuals weigh exp(-age / this), age in views of the board since
  int min_dof = 40;              // the set pixel_sigma until this many degrees of freedom are pooled
  template <class V>
  void visit(V& v) {
    v("enabled", enabled,
      "estimate the corners' noise from their scatter about the board plane's homography (else pixel_sigma)");
    v("min_pixel_sigma", min_pixel_sigma, "pixels, the estimate's floor");
    v("time_constant_frames", time_constant_frames,
      "a view's residuals weigh exp(-age / this), its age counted in views of the board since");
    v("min_dof", min_dof, "degrees of freedom pooled before the estimate replaces pixel_sigma");
  }
  void check() const;
};

class CornerNoise {
 public:
  CornerNoise(const CornerNoiseOptions& options, double set_pixel_sigma)
      : options_(options), set_pixel_sigma_(set_pixel_sigma) {}

  // One frame's corners: their distances to the homography through all of them, pixels.
  void add(const std::vector<double>& plane_errors_px);
  // The corner noise to use now, pixels (one axis).
  double pixelSigma() const;

 private:
  CornerNoiseOptions options_;
  double set_pixel_sigma_;
  double sum_squares_ = 0, dof_ = 0;  // decayed sums
};

}  // namespace slamcmp
