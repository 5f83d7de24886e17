#include "geometry/essential_eight_point.h"

#include <cmath>
#include <limits>

#include <Eigen/SVD>

#include "geometry/hartley_normalisation.h"

#include "geometry/triangulation.h"

namespace slamcmp {

Mat3 essentialEightPoint(const std::vector<Vec2>& xy_a, const std::vector<Vec2>& xy_b) {
  const int n = static_cast<int>(xy_a.size());
  const Mat3 Ta = hartleyNormalisation(xy_a), Tb = hartleyNormalisation(xy_b);
  Eigen::Matrix<double, Eigen::Dynamic, 9> V(std::max(n, 9), 9);
  V.setZero();  // with exactly 8 points a zero row keeps the SVD square
  for (int i = 0; i < n; ++i) {
    const Vec3 a = Ta * xy_a[i].homogeneous();
    const Vec3 b = Tb * xy_b[i].homogeneous();
    // eq. 3.32: one row of V e = 0 for b^T E a = 0, e = E row-major.
    V.row(i) << b.x() * a.x(), b.x() * a.y(), b.x(), b.y() * a.x(), b.y() * a.y(), b.y(), a.x(), a.y(), 1;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(V, Eigen::ComputeFullV);
  const Eigen::VectorXd e = svd.matrixV().col(8);  // eq. 3.34
  Mat3 En;
  En << e(0), e(1), e(2), e(3), e(4), e(5), e(6), e(7), e(8);
  const Mat3 E = Tb.transpose() * En * Ta;
  Eigen::JacobiSVD<Mat3> s(E, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return s.matrixU() * Vec3(1, 1, 0).asDiagonal() * s.matrixV().transpose();  // eq. 3.35, forced
}

std::array<SE3, 4> decomposeEssential(const Mat3& E) {
  Eigen::JacobiSVD<Mat3> svd(E, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 U = svd.matrixU(), V = svd.matrixV();
  if (U.determinant() < 0) U = -U;  // E is defined up to sign: keep U, V proper rotations
  if (V.determinant() < 0) V = -V;
  Mat3 W;
  W << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  const Mat3 R1 = U * W * V.transpose(), R2 = U * W.transpose() * V.transpose();  // eq. 3.36
  const Vec3 t = U.col(2);                                                          // eq. 3.37
  return {SE3(R1, t), SE3(R1, -t), SE3(R2, t), SE3(R2, -t)};
}

int countInFront(const SE3& T_b_a, const std::vector<Vec2>& xy_a, const std::vector<Vec2>& xy_b) {
  const SE3 T_a_b = T_b_a.inverse();
  int count = 0;
  for (size_t i = 0; i < xy_a.size(); ++i) {
    const Ray ra{Vec3::Zero(), xy_a[i].homogeneous().normalized()};
    const Ray rb = rayFromObservation(T_a_b, xy_b[i]);
    Vec3 pa, pb;
    if (!closestPointsOfRays(ra, rb, &pa, &pb)) continue;
    const Vec3 p_a = 0.5 * (pa + pb);
    if (p_a.z() > 0 && (T_b_a * p_a).z() > 0) ++count;
  }
  return count;
}

SE3 selectByCheirality(const Mat3& E, const std::vector<Vec2>& xy_a, const std::vector<Vec2>& xy_b,
                       int* in_front) {
  int best = -1;
  SE3 best_pose;
  for (const SE3& candidate : decomposeEssential(E)) {
    const int n = countInFront(candidate, xy_a, xy_b);
    if (n > best) best = n, best_pose = candidate;
  }
  if (in_front) *in_front = best;
  return best_pose;
}

double signedSampsonDistance(const Mat3& E, const Vec2& xy_a, const Vec2& xy_b) {
  const Vec3 a = xy_a.homogeneous(), b = xy_b.homogeneous();
  const Vec3 Ea = E * a, Etb = E.transpose() * b;
  const double d = Ea.x() * Ea.x() + Ea.y() * Ea.y() + Etb.x() * Etb.x() + Etb.y() * Etb.y();
  return d > 0 ? b.dot(Ea) / std::sqrt(d) : std::numeric_limits<double>::quiet_NaN();
}

double sampsonErrorSquared(const Mat3& E, const Vec2& xy_a, const Vec2& xy_b) {
  const double r = signedSampsonDistance(E, xy_a, xy_b);
  return std::isfinite(r) ? r * r : std::numeric_limits<double>::infinity();
}

}  // namespace slamcmp
