#pragma once
// Relative camera motion from two views (thesis section 3.3): the 8-point essential matrix inside
// RANSAC, refined on its inliers, the (R, t) in front of both cameras, and a degeneracy check.
// Pose direction (geometry/'s convention, camera from world, camera a being the world): T_b_a,
// p_b = R p_a + t.
#include <string>
#include <vector>

#include "core/geometry.h"
#include "geometry/ransac.h"

namespace slamcmp {

struct TwoViewOptions {
  // max_error: Sampson distance, pixels. At most 2000 samples: an all-inlier sample of 8 at the
  // smallest inlier ratio accepted (0.5) with 0.999 takes 1765 (300 drew one 69 % of the time).
  RansacOptions ransac = [] {
    RansacOptions r;
    r.max_iterations = 2000;
    return r;
  }();
  int min_inliers = 20;            // fewer: no motion
  double min_inlier_ratio = 0.5;   // fewer: no motion
  // Degeneracy: the median parallax left after removing the rotation (tiny baseline or pure
  // rotation: the translation direction is then noise).
  double min_parallax_px = 2.0;
  // Degeneracy: points on one plane fit a family of matrices to the 8-point solver (Hartley and
  // Zisserman 11.9), RANSAC's among them: a homography explaining this fraction of E's inliers
  // (at the same probability) marks the scene planar (COLMAP's max_H_inlier_ratio). A scene in
  // depth whose parallax off a plane is within the noise is taken for one too (2-4 m deep, 0.3 px
  // noise: most pairs under 3.5 px of median parallax, none over 5).
  double max_homography_inlier_ratio = 0.8;
  int refine_iterations = 5;       // Levenberg-Marquardt on the inliers' Sampson distances
  template <class V>
  void visit(V& v) {
    v("ransac", ransac, "RANSAC over the 8-point solver; max_error is a Sampson distance in pixels");
    v("min_inliers", min_inliers, "fewer inliers: no two-view motion");
    v("min_inlier_ratio", min_inlier_ratio, "smaller inlier fraction: no two-view motion");
    v("refine_iterations", refine_iterations,
      "Levenberg-Marquardt iterations on the inliers' Sampson distances (0: the 8-point solution)");
    v("min_parallax_px", min_parallax_px,
      "median rotation-compensated parallax in pixels under which the motion is degenerate");
    v("max_homography_inlier_ratio", max_homography_inlier_ratio,
      "a homography explaining this fraction of the essential matrix's inliers marks the scene planar: no motion "
      "(1: not tested)");
  }
  void check() const;
};

struct TwoViewResult {
  bool ok = false;
  std::string reason;        // why not ok
  bool degenerate = false;   // inliers found but too little parallax: T_b_a's rotation stands, its translation is noise
  bool planar = false;       // a homography explains the inliers: no motion (max_homography_inlier_ratio)
  SE3 T_b_a;                 // p_b = R p_a + t, |t| = 1 (the scale is unknown)
  std::vector<char> inliers;
  int num_inliers = 0;
  double parallax_px = 0;    // median rotation-compensated parallax of the inliers
};

// xy_a[i] and xy_b[i]: undistorted normalised coordinates of one feature in views a and b.
// focal_px converts normalised distances to pixels for the thresholds.
TwoViewResult estimateTwoViewMotion(const std::vector<Vec2>& xy_a, const std::vector<Vec2>& xy_b,
                                    double focal_px, const TwoViewOptions& options);

// The essential matrix of a motion: E = [t]x R (b^T E a = 0 for a and b in normalised coordinates).
inline Mat3 essentialFromMotion(const SE3& T_b_a) { return skew(T_b_a.t()) * T_b_a.R(); }

// Levenberg-Marquardt on the Sampson distances of xy_a[i] <-> xy_b[i] (normalised coordinates)
// over the motion's 5 degrees of freedom (rotation, and the translation direction on the unit
// sphere), from T_b_a; numeric Jacobian. cauchy_scale > 0 (normalised units): the Cauchy loss
// c^2 log(1 + r^2 / c^2) instead of the squares, iteratively reweighted (tracks far off the motion
// barely pull it). *cost: the loss at the result. Throws std::invalid_argument if the sizes differ
// or cauchy_scale is negative or not finite.
SE3 refineTwoViewMotion(const SE3& T_b_a, const std::vector<Vec2>& xy_a, const std::vector<Vec2>& xy_b,
                        int iterations, double cauchy_scale = 0, double* cost = nullptr);

}  // namespace slamcmp
