#include "geometry/two_view_motion.h"

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/error.h"
#include "core/statistics.h"
#include "geometry/essential_eight_point.h"
#include "geometry/two_view_estimators.h"

namespace slamcmp {

void TwoViewOptions::check() const {
  if (min_inliers < 8) throw OptionError("min_inliers", "must be >= 8");
  if (!(min_inlier_ratio >= 0 && min_inlier_ratio <= 1)) throw OptionError("min_inlier_ratio", "must be in [0, 1]");
  if (refine_iterations < 0) throw OptionError("refine_iterations", "must be >= 0");
  if (!(max_homography_inlier_ratio > 0 && max_homography_inlier_ratio <= 1))
    throw OptionError("max_homography_inlier_ratio", "must be in (0, 1]");
  if (min_parallax_px < 0) throw OptionError("min_parallax_px", "must be >= 0");
}

namespace {

constexpr int kMaxLocalRefits = 10;

// The refinement's residual: a correspondence whose distance is not defined for this motion (at
// both epipoles) tells nothing about it.
double sampsonResidual(const Mat3& E, const Vec2& xy_a, const Vec2& xy_b) {
  const double r = signedSampsonDistance(E, xy_a, xy_b);
  return std::isfinite(r) ? r : 0.0;
}

}  // namespace

SE3 refineTwoViewMotion(const SE3& T_b_a, const std::vector<Vec2>& a, const std::vector<Vec2>& b, int iterations,
                        double cauchy_scale, double* final_cost) {
  if (a.size() != b.size()) throw std::invalid_argument("refineTwoViewMotion: views of different sizes");
  if (!(cauchy_scale >= 0 && std::isfinite(cauchy_scale)))
    throw std::invalid_argument("refineTwoViewMotion: cauchy_scale must be finite and >= 0");
  using Vec5 = Eigen::Matrix<double, 5, 1>;
  const int n = static_cast<int>(a.size());
  auto apply = [](const SE3& T, const Vec5& d) {
    // Tangent basis of the sphere at t.
    const Vec3 t = T.t().normalized();
    Vec3 e1 = t.cross(std::abs(t.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).normalized();
    const Vec3 e2 = t.cross(e1);
    return SE3(rotationFromRotvec(d.head<3>()) * T.R(), (t + d(3) * e1 + d(4) * e2).normalized());
  };
  auto residuals = [&](const SE3& T, Eigen::VectorXd* r) {
    const Mat3 E = essentialFromMotion(T);
    for (int i = 0; i < n; ++i) (*r)(i) = sampsonResidual(E, a[i], b[i]);
  };
  const double c2 = cauchy_scale * cauchy_scale;
  auto cost = [&](const Eigen::VectorXd& r) {
    if (c2 <= 0) return r.squaredNorm();
    // c^2 sum log(1 + x), x = r^2 / c^2, as c^2 log prod (1 + x): one log1p every few tracks instead
    // of one a track (log1p was a fifth of the refinement's time). The product is held as q = prod - 1,
    // q <- q + x + q x, so a small x keeps its digits (no 1 + x is formed); q <= 1e100 and a factor
    // <= 1e100 cannot overflow.
    double log_sum = 0, q = 0;
    for (Eigen::Index i = 0; i < r.size(); ++i) {
      const double x = r(i) * r(i) / c2;
      if (x > 1e100) {
        log_sum += std::log1p(x);
        continue;
      }
      q += x + q * x;
      if (q > 1e100) log_sum += std::log1p(q), q = 0;
    }
    return c2 * (log_sum + std::log1p(q));
  };
  SE3 T = T_b_a;
  Eigen::VectorXd r(n), rc(n);
  residuals(T, &r);
  double r_cost = cost(r);
  double lambda = 1e-3;
  Eigen::MatrixXd J(n, 5);
  for (int it = 0; it < iterations; ++it) {
    // Forward differences, the five columns in one pass over the tracks.
    std::array<Mat3, 5> E_step;
    for (int k = 0; k < 5; ++k) E_step[k] = essentialFromMotion(apply(T, 1e-7 * Vec5::Unit(k)));
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < 5; ++k) J(i, k) = (sampsonResidual(E_step[k], a[i], b[i]) - r(i)) / 1e-7;
    Eigen::VectorXd rw = r;
    if (c2 > 0) {  // iteratively reweighted: the Cauchy loss's weight 1 / (1 + r^2 / c^2) at the current residuals
      const Eigen::VectorXd sqrt_w = (1 + r.array().square() / c2).rsqrt();
      J.array().colwise() *= sqrt_w.array();
      rw = sqrt_w.cwiseProduct(r);
    }
    const Eigen::Matrix<double, 5, 5> H = J.transpose() * J;
    const Vec5 g = J.transpose() * rw;
    bool improved = false;
    for (int attempt = 0; attempt < 6 && !improved; ++attempt) {
      Eigen::Matrix<double, 5, 5> A = H;
      A.diagonal() *= 1 + lambda;
      const Vec5 d = A.ldlt().solve(-g);
      const SE3 candidate = apply(T, d);
      residuals(candidate, &rc);
      const double rc_cost = cost(rc);
      if (rc_cost < r_cost) {
        improved = true;
        T = candidate;
        r.swap(rc);
        r_cost = rc_cost;
        lambda *= 0.1;
      } else {
        lambda *= 10;
      }
    }
    if (!improved) break;
  }
  if (final_cost) *final_cost = r_cost;
  return T;
}

TwoViewResult estimateTwoViewMotion(const std::vector<Vec2>& xy_a, const std::vector<Vec2>& xy_b,
                                    double focal_px, const TwoViewOptions& options) {
  TwoViewResult out;
  const int n = static_cast<int>(xy_a.size());
  if (n < options.min_inliers) {
    out.reason = "too few correspondences for two-view motion (" + std::to_string(n) + ")";
    return out;
  }
  const EssentialEstimator estimator{xy_a, xy_b, focal_px * focal_px};
  auto r = ransac(estimator, options.ransac);
  if (!r.success) {
    out.reason = "two-view RANSAC found no model";
    return out;
  }
  // Said with the result when too few inliers follow: the samples ran out first.
  const std::string capped = r.capped ? " (RANSAC stopped at its " + std::to_string(options.ransac.max_iterations) +
                                            " samples before its confidence)"
                                      : "";
  // Refinement: the 8-point solution on all inliers, then on the inliers of that while they grow.
  refitOnInliers(estimator, options.ransac, kMaxLocalRefits, &r);
  std::vector<Vec2> a, b;
  const double t2 = options.ransac.max_error * options.ransac.max_error;
  const Mat3 E = r.model;
  // Inliers of E, the (R, t) in front, Levenberg-Marquardt on those inliers; then once more on
  // the inliers of the refined motion.
  auto collectInliers = [&](const Mat3& model) {
    out.inliers.assign(n, 0);
    a.clear();
    b.clear();
    for (int i = 0; i < n; ++i)
      if (estimator.squaredError(model, i) < t2) out.inliers[i] = 1, a.push_back(xy_a[i]), b.push_back(xy_b[i]);
    out.num_inliers = static_cast<int>(a.size());
    return out.num_inliers >= options.min_inliers && out.num_inliers >= options.min_inlier_ratio * n;
  };
  int in_front = 0;
  if (collectInliers(E)) {
    out.T_b_a = refineTwoViewMotion(selectByCheirality(E, a, b, &in_front), a, b, options.refine_iterations);
    if (collectInliers(essentialFromMotion(out.T_b_a))) {
      out.T_b_a = refineTwoViewMotion(out.T_b_a, a, b, options.refine_iterations);
      in_front = countInFront(out.T_b_a, a, b);
    }
  }
  if (out.num_inliers < options.min_inliers || out.num_inliers < options.min_inlier_ratio * n) {
    out.reason =
        "too few two-view inliers (" + std::to_string(out.num_inliers) + " of " + std::to_string(n) + ")" + capped;
    return out;
  }
  // Parallax once the rotation is removed: what the translation alone moved the features.
  std::vector<double> parallax;
  parallax.reserve(a.size());
  for (size_t i = 0; i < a.size(); ++i)
    parallax.push_back(focal_px * ((out.T_b_a.R() * a[i].homogeneous()).hnormalized() - b[i]).norm());
  out.parallax_px = median(parallax);
  if (out.parallax_px < options.min_parallax_px) {
    out.degenerate = true;
    out.reason = "degenerate two-view motion (parallax " + std::to_string(out.parallax_px) + " px: tiny baseline or pure rotation)";
    return out;
  }
  if (options.max_homography_inlier_ratio < 1) {
    const HomographyEstimator homography{a, b, focal_px * focal_px};
    RansacOptions h_options = options.ransac;
    // The transfer error is over 2 dof where the Sampson distance is over 1: at the same
    // probability (95 %) its threshold is sqrt(chi2_2 / chi2_1) = 1.25 times (ORB-SLAM's H and F
    // scores). The views' noise in both images would ask 1.77, but a homography that wide takes
    // a scene in depth with a median parallax of 3-5 px (2-4 m deep, 0.3 px noise) for a plane.
    h_options.max_error *= std::sqrt(chiSquaredQuantile(2, 0.95) / chiSquaredQuantile(1, 0.95));
    // Only a homography with that many inliers matters: the samples that draw one all-inlier
    // sample of it with RANSAC's confidence are enough (14 at 0.8), where a homography that fits
    // few of them (a scene in depth) would run RANSAC to its cap.
    const double trials = ransacTrials(options.max_homography_inlier_ratio, HomographyEstimator::kMinSamples,
                                       h_options.confidence);
    h_options.min_iterations = h_options.max_iterations =
        std::max(1, static_cast<int>(std::min<double>(h_options.max_iterations, trials)));
    auto h = ransac(homography, h_options);
    refitOnInliers(homography, h_options, kMaxLocalRefits, &h);
    if (h.success && h.num_inliers >= options.max_homography_inlier_ratio * out.num_inliers) {
      out.planar = true;
      out.reason = "planar scene, or too little parallax off a plane: a homography explains " +
                   std::to_string(h.num_inliers) + " of the " + std::to_string(out.num_inliers) +
                   " two-view inliers (the essential matrix is not determined)";
      return out;
    }
  }
  if (in_front < 0.9 * out.num_inliers) {
    out.reason = "two-view cheirality ambiguous (" + std::to_string(in_front) + " of " + std::to_string(out.num_inliers) + " in front)";
    return out;
  }
  out.ok = true;
  return out;
}

}  // namespace slamcmp
