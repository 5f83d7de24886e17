// Umeyama alignment on exact cases with known answers.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "eval/metrics/align_umeyama.h"

namespace slamcmp {
namespace {

std::vector<Vec3> someNonPlanarPoints() {
  return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 2, 0),
          Vec3(0, 0, 3), Vec3(1, 1, 1), Vec3(-2, 0.5, 1)};
}

TEST(AlignUmeyama, RecoversAnExactSimilarity) {
  const Mat3 R = rotationFromRotvec(Vec3(0.3, -1.1, 0.7));
  const Vec3 t(4.0, -2.0, 0.5);
  const double scale = 2.5;
  std::vector<Vec3> p_from = someNonPlanarPoints(), p_to;
  for (const Vec3& p : p_from) p_to.push_back(scale * (R * p) + t);

  const Similarity3 sim3 = alignUmeyama(p_from, p_to, true);
  EXPECT_NEAR(sim3.scale, scale, 1e-12);
  EXPECT_LT((sim3.R - R).norm(), 1e-12);
  EXPECT_LT((sim3.t - t).norm(), 1e-12);

  // Without scale: the rotation is still exact (the centred point sets differ by scale only) and
  // the translation maps the centroid onto the target's.
  const Similarity3 se3 = alignUmeyama(p_from, p_to, false);
  EXPECT_EQ(se3.scale, 1.0);
  EXPECT_LT((se3.R - R).norm(), 1e-12);
  Vec3 mean_from = Vec3::Zero(), mean_to = Vec3::Zero();
  for (size_t i = 0; i < p_from.size(); ++i) {
    mean_from += p_from[i] / p_from.size();
    mean_to += p_to[i] / p_to.size();
  }
  EXPECT_LT((se3 * mean_from - mean_to).norm(), 1e-12);
}

// A closed-form case: a cross stretched 2x along x and 1x along y. The covariance is
// diag(1, 0.5, 0), the source variance 1, so R = I, t = 0 and the least-squares scale is
// trace(D) / sigma^2 = 1.5 (Umeyama eq. 42), not either stretch.
TEST(AlignUmeyama, StretchedCrossClosedForm) {
  const std::vector<Vec3> p_from = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0)};
  const std::vector<Vec3> p_to = {Vec3(2, 0, 0), Vec3(-2, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0)};
  const Similarity3 s = alignUmeyama(p_from, p_to, true);
  EXPECT_NEAR(s.scale, 1.5, 1e-15);
  EXPECT_LT((s.R - Mat3::Identity()).norm(), 1e-15);
  EXPECT_LT(s.t.norm(), 1e-15);
}

// A mirror image has no rotation onto it: the S matrix (eq. 43) must keep det R = +1.
TEST(AlignUmeyama, MirrorImageGivesAProperRotation) {
  std::vector<Vec3> p_from = someNonPlanarPoints(), p_to;
  for (const Vec3& p : p_from) p_to.push_back(Vec3(p.x(), p.y(), -p.z()));
  const Similarity3 s = alignUmeyama(p_from, p_to, true);
  EXPECT_NEAR(s.R.determinant(), 1.0, 1e-12);
  EXPECT_LT((s.R.transpose() * s.R - Mat3::Identity()).norm(), 1e-12);
  EXPECT_GT(s.scale, 0.0);
}

TEST(AlignUmeyama, TooFewOrDegeneratePointsAreRefused) {
  EXPECT_THROW(alignUmeyama({Vec3(0, 0, 0), Vec3(1, 0, 0)}, {Vec3(0, 0, 0), Vec3(1, 0, 0)}, false),
               InputError);
  const std::vector<Vec3> on_a_line = {Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2), Vec3(3, 3, 3)};
  EXPECT_THROW(alignUmeyama(on_a_line, on_a_line, true), InputError);
  const std::vector<Vec3> one_point(5, Vec3(1, 2, 3));
  EXPECT_THROW(alignUmeyama(one_point, one_point, false), InputError);
}

// Four points at +-3 along one axis and +-1 along another, turned and moved: RMS spreads 0,
// sqrt(0.5) and sqrt(4.5) along the principal axes, ascending, wherever the set is.
TEST(AlignUmeyama, PrincipalSpreadOfACross) {
  const SE3 T = SE3::fromRotvec(Vec3(0.3, -0.2, 0.5), Vec3(4, -1, 2));
  const std::vector<Vec3> cross{T * Vec3(3, 0, 0), T * Vec3(-3, 0, 0), T * Vec3(0, 1, 0), T * Vec3(0, -1, 0)};
  const Vec3 spread = principalSpread(cross);
  EXPECT_NEAR(spread[0], 0.0, 1e-6);
  EXPECT_NEAR(spread[1], std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(spread[2], std::sqrt(4.5), 1e-12);
}

}  // namespace
}  // namespace slamcmp
