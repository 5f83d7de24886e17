#pragma once
// Sub-pixel refinement of chessboard corners (X-junctions) by Foerstner's gradient orthogonality:
// the corner q minimises sum_p w(p - q) (g(p) . (p - q))^2 over the pixels p of a window, g the
// image gradient. For a point-symmetric junction the integral form is exact; the sum over pixels
// is close to it when the gradient varies smoothly from pixel to pixel. cv::cornerSubPix solves
// the same equations on a window resampled bilinearly at the estimate, and bilinear resampling
// skews a sharp edge by its sub-pixel phase: on the renders its corners sit up to 0.05 px off
// towards the nearest half pixel (0.035 px RMS), the same in every frame, so nothing averages it
// out. Here the gradients are taken on the pixel grid of the image smoothed by a Gaussian, with
// weights that fall smoothly to zero at the window's edge (no pixel enters or leaves the sum with
// a jump as q moves): 0.006-0.013 px RMS on the same corners (squares 40 to 16 px). Real views:
// `slamcmp calibrate` on Bouguet's images reprojects to 0.40 px (cv::cornerSubPix 0.48), its focal
// lengths 0.02-0.08 % from the published ones (0.27-0.36 %).
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"

namespace slamcmp {

struct SubpixelCornerOptions {
  static inline const std::vector<std::string> kMethods{"gradient", "opencv"};
  // "gradient" (the method above) or "opencv" (cv::cornerSubPix, the thesis's and SceneLib's).
  // hybrid's corners take gradient (its own default since session 21); not yet this struct's
  // default, cslam's: with it three regressions at shortened length move (cslam's calibration mode
  // finds wall_turn's returning board a frame late at supersample 1; board_leaves' half-board
  // frames, 2x better with the whole board 3x better, hold 1.1 of it where the test holds 1.0;
  // hybrid's tracked points, board_leaves seeds 1 and 2, just over the away allowance).
  std::string method = "opencv";
  // The Gaussian smoothing before the gradients, pixels, at most half the half window beyond
  // 1.5 px: on the renders (lens blur 0.7 px; half window 5, before the radius grew) the corners'
  // RMS error was 0.024 px without it, 0.014 with 1.0, 0.011 with 1.5.
  double smoothing_sigma_px = 1.5;
  int max_iterations = 30;
  double epsilon_px = 0.001;  // the iteration stops when the corner moves less than this
  // gradient, with the camera given: the junction's edges taken straight where they are, in the
  // undistorted image. A lens bends them within the window and the fit in the image leans
  // outwards under barrel distortion: roll_distortion's corners (k1 -0.32) sat 0.0036 / 0.0056 px
  // out at 75 / 125 px from the centre, so the board looked 7e-5 too large and hybrid's camera
  // sat 32 um too near it in every frame, 3 times its std (0.0001 px and 0.1 um taken straight;
  // tv1's k1 -0.1: 0.0016 px, 8 um). 55 % more per corner (bench_stages BM_CornerRefinement).
  bool undistorted = true;
  template <class V>
  void visit(V& v) {
    v("method", method,
      "gradient (Foerstner's gradient orthogonality on the smoothed pixel grid) or opencv (cv::cornerSubPix, "
      "biased by up to 0.05 px towards the nearest half pixel)");
    v("smoothing_sigma_px", smoothing_sigma_px,
      "gradient: Gaussian smoothing of the image before the gradients (at most half the half window beyond "
      "1.5 px), pixels");
    v("max_iterations", max_iterations, "iterations at most per corner");
    v("epsilon_px", epsilon_px, "the iteration stops when the corner moves less than this, pixels");
    v("undistorted", undistorted,
      "gradient, with the camera known: the junction's edges taken straight in the undistorted image (a lens "
      "bends them)");
  }
  void check() const;
};

// Refines each corner of `uv` (distorted pixels) in a window of half side `half_window` pixels.
// A corner the gradient method cannot place (its window holds no junction, it runs out of the
// window, the window leaves the image: motion blur, a corner at the border) is refined by
// cv::cornerSubPix instead, as before this method. `camera` (optional): the lens that took `grey`,
// the whole image (options.undistorted).
void refineCornersSubpixel(const cv::Mat& grey, int half_window, std::vector<cv::Point2f>& uv,
                           const SubpixelCornerOptions& options, const CameraModel* camera = nullptr);

}  // namespace slamcmp
