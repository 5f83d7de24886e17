#include "eval/metrics/align_umeyama.h"

#include <cassert>
#include <limits>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "core/error.h"

namespace slamcmp {

Similarity3 alignUmeyama(const std::vector<Vec3>& p_from, const std::vector<Vec3>& p_to,
                         bool with_scale) {
  assert(p_from.size() == p_to.size());
  const size_t n = p_from.size();
  if (n < 3)
    throw InputError("--align", "needs at least 3 matched poses, got " + std::to_string(n));

  // Eqs. 34, 35: the centroids.
  Vec3 mean_from = Vec3::Zero(), mean_to = Vec3::Zero();
  for (size_t i = 0; i < n; ++i) {
    mean_from += p_from[i];
    mean_to += p_to[i];
  }
  mean_from /= static_cast<double>(n);
  mean_to /= static_cast<double>(n);

  // Eq. 36: the variance of the source points; eq. 38: the covariance.
  double sigma_from = 0.0;
  Mat3 covariance = Mat3::Zero();
  for (size_t i = 0; i < n; ++i) {
    const Vec3 d_from = p_from[i] - mean_from;
    sigma_from += d_from.squaredNorm();
    covariance += (p_to[i] - mean_to) * d_from.transpose();
  }
  sigma_from /= static_cast<double>(n);
  covariance /= static_cast<double>(n);

  const Eigen::JacobiSVD<Mat3> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Vec3& d = svd.singularValues();
  int rank = 0;
  for (int k = 0; k < 3; ++k) rank += d[k] > std::numeric_limits<double>::epsilon() ? 1 : 0;
  if (rank < 2)
    throw InputError("--align",
                     "the matched positions are degenerate (all at one point or on one "
                     "line): the alignment is undetermined");

  // Eq. 43: S = diag(1, 1, -1) when U V^T would be a reflection.
  Vec3 s = Vec3::Ones();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) s[2] = -1.0;

  Similarity3 out;
  out.R = svd.matrixU() * s.asDiagonal() * svd.matrixV().transpose();  // eq. 40
  out.scale = with_scale ? d.dot(s) / sigma_from : 1.0;                // eq. 42
  out.t = mean_to - out.scale * (out.R * mean_from);                   // eq. 41
  return out;
}

Vec3 principalSpread(const std::vector<Vec3>& positions) {
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : positions) mean += p;
  mean /= static_cast<double>(positions.size());
  Mat3 covariance = Mat3::Zero();
  for (const Vec3& p : positions) covariance += (p - mean) * (p - mean).transpose();
  covariance /= static_cast<double>(positions.size());
  return Eigen::SelfAdjointEigenSolver<Mat3>(covariance).eigenvalues().cwiseMax(0).cwiseSqrt();
}

}  // namespace slamcmp
