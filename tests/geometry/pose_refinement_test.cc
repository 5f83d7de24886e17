// geometry/pose_refinement: the analytic Jacobian of the reprojection residual (reached through
// reprojectionHessian = J^T J and through refinePose's steps: the Jacobian itself is internal),
// the left perturbation it is taken over, convergence on exact data and the pose's information
// matrix against noise.
#include "geometry/pose_refinement.h"

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "tests/test_util.h"

namespace slamcmp {
namespace {

constexpr double kFocalPx = 525.0;  // the synthetic camera's focal length

// Points in a room-like volume in front of the camera, their exact normalised projections, and
// the pose they were seen from (T_camera_world).
struct Scene {
  SE3 T_camera_world;
  std::vector<Vec3> p_world;
  std::vector<Vec2> xy_normalised;
};

SE3 truePose(int k) {
  const SE3 T_world_camera = SE3::fromRotvec(Vec3(0.3 * std::sin(k), 0.5 * std::cos(1.7 * k), 0.2 * k),
                                             Vec3(0.4 * std::cos(k), -0.2 + 0.1 * k, 0.3 * std::sin(2.0 * k)));
  return T_world_camera.inverse();
}

Scene makeScene(int k, int n = 50) {
  std::mt19937 rng(100 + k);
  std::uniform_real_distribution<double> u(-1, 1);
  Scene s;
  s.T_camera_world = truePose(k);
  const SE3 T_world_camera = s.T_camera_world.inverse();
  for (int i = 0; i < n; ++i) {
    const Vec3 p_camera(1.2 * u(rng), 0.9 * u(rng), 3.5 + 1.5 * u(rng));
    s.p_world.push_back(T_world_camera * p_camera);
    s.xy_normalised.push_back(p_camera.hnormalized());
  }
  return s;
}

// The residual refinePose minimises, for points [first, last): f (pi(T p) - xy), stacked, over the
// left perturbation delta of T (T' = applyPoseDelta(T, delta)).
Eigen::VectorXd residual(const SE3& T_camera_world, const Scene& s, const Eigen::VectorXd& delta, size_t first,
                         size_t last) {
  const SE3 T = applyPoseDelta(T_camera_world, delta);
  Eigen::VectorXd r(2 * (last - first));
  for (size_t i = first; i < last; ++i)
    r.segment<2>(2 * (i - first)) = kFocalPx * ((T * s.p_world[i]).hnormalized() - s.xy_normalised[i]);
  return r;
}

double maxAbs(const Eigen::MatrixXd& M) { return M.cwiseAbs().maxCoeff(); }

class PoseRefinementExact : public ::testing::TestWithParam<int> {};

// The residual above is the one refinePose measures: its norms are reprojectionErrorsPx's.
TEST_P(PoseRefinementExact, TestResidualIsTheProductionResidual) {
  const Scene s = makeScene(GetParam());
  const SE3 T = applyPoseDelta(s.T_camera_world, (Vec6() << 0.01, -0.02, 0.015, 0.03, 0.01, -0.02).finished());
  const std::vector<double> errors = reprojectionErrorsPx(T, s.p_world, s.xy_normalised, kFocalPx);
  const Eigen::VectorXd r = residual(T, s, Vec6::Zero(), 0, s.p_world.size());
  for (size_t i = 0; i < errors.size(); ++i) {
    EXPECT_GT(errors[i], 0.1);  // the perturbation moves every point by pixels
    EXPECT_NEAR(errors[i], r.segment<2>(2 * i).norm(), 1e-9);
  }
}

// Each point's Hessian J_i^T J_i against central differences of its residual, at a pose away from
// the truth (non-zero residuals). Tolerance 1e-7 of the largest entry: central differences with
// step 1e-6 have truncation error ~1e-12 J and roundoff ~f 1e-16 / 1e-6 ~ 1e-8 px per unit, so
// J_numeric is good to ~1e-9 relative; a wrong term is off by O(1).
TEST_P(PoseRefinementExact, PointHessianMatchesNumericJacobian) {
  const Scene s = makeScene(GetParam());
  const SE3 T = applyPoseDelta(s.T_camera_world, (Vec6() << -0.03, 0.02, 0.05, 0.1, -0.05, 0.08).finished());
  for (size_t i = 0; i < s.p_world.size(); ++i) {
    const Eigen::MatrixXd J = test::numericJacobian(
        [&](const Eigen::VectorXd& delta) { return residual(T, s, delta, i, i + 1); }, Vec6::Zero());
    const Mat6 H = reprojectionHessian(T, {s.p_world[i]}, {s.xy_normalised[i]}, kFocalPx);
    const Eigen::MatrixXd expected = J.transpose() * J;
    EXPECT_LT(maxAbs(H - expected), 1e-7 * maxAbs(expected)) << "point " << i << "\nH\n" << H << "\nJ^T J\n" << expected;
  }
}

// At the true pose the residuals vanish, so the Hessian of half the squared reprojection errors
// (from reprojectionErrorsPx) is exactly J^T J: the analytic Hessian is the Jacobian of the
// cost's gradient there. Both derivatives numeric (gradient step 1e-5, Jacobian step 1e-6):
// roundoff reaches ~1e-9 of H's largest entry, so compared relative to it (f scaled) at 1e-6.
TEST_P(PoseRefinementExact, HessianIsTheCostCurvatureAtTheTruth) {
  const Scene s = makeScene(GetParam());
  const Mat6 H = reprojectionHessian(s.T_camera_world, s.p_world, s.xy_normalised, kFocalPx);
  const double scale = maxAbs(H);
  auto cost = [&](const Eigen::VectorXd& delta) {
    double c = 0;
    for (double e : reprojectionErrorsPx(applyPoseDelta(s.T_camera_world, delta), s.p_world, s.xy_normalised, kFocalPx))
      c += 0.5 * e * e;
    return (Eigen::VectorXd(1) << c).finished();
  };
  auto gradient = [&](const Eigen::VectorXd& delta) -> Eigen::VectorXd {
    return test::numericJacobian(cost, delta, 1e-5).transpose() / scale;
  };
  test::expectJacobianMatchesNumeric(gradient, Vec6::Zero(), H / scale, 1e-6);
}

// The perturbation the Hessian is over: poseDifference undoes applyPoseDelta, so d delta' / d delta
// is the identity, and applyPoseDelta(T_from, poseDifference(T_to, T_from)) is T_to.
TEST_P(PoseRefinementExact, PoseDifferenceInvertsApplyPoseDelta) {
  const SE3 T = truePose(GetParam());
  const Vec6 delta0 = (Vec6() << 0.2, -0.1, 0.3, 0.5, -0.4, 0.1).finished();
  test::expectJacobianMatchesNumeric(
      [&](const Eigen::VectorXd& delta) -> Eigen::VectorXd { return poseDifference(applyPoseDelta(T, delta), T); },
      delta0, Mat6::Identity(), 1e-8);
  const SE3 other = truePose(GetParam() + 7);
  const SE3 back = applyPoseDelta(T, poseDifference(other, T));
  EXPECT_LT((back.R() - other.R()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((back.t() - other.t()).norm(), 1e-12);
}

// refinePose's first step from a perturbed start against the Gauss-Newton step of the numeric
// Jacobian, -(J^T J)^-1 J^T r. Levenberg-Marquardt starts with a damping of 1e-4 on the diagonal,
// which moves the step by about 1e-4 times the condition number of the diagonally scaled J^T J
// (asserted under 100 here), so the two agree to 1e-2 relative; a wrong Jacobian term (sign,
// missing product) changes the step by O(1).
TEST_P(PoseRefinementExact, FirstStepIsTheGaussNewtonStepOfTheNumericJacobian) {
  const Scene s = makeScene(GetParam());
  const SE3 start = applyPoseDelta(s.T_camera_world, (Vec6() << 0.01, -0.008, 0.012, -0.02, 0.015, 0.01).finished());
  const auto r_of = [&](const Eigen::VectorXd& delta) { return residual(start, s, delta, 0, s.p_world.size()); };
  const Eigen::MatrixXd J = test::numericJacobian(r_of, Vec6::Zero());
  const Mat6 H = J.transpose() * J;
  const Vec6 step_gn = -H.ldlt().solve(J.transpose() * r_of(Vec6::Zero()));

  const Vec6 d = H.diagonal().cwiseSqrt().cwiseInverse();
  const Mat6 scaled = d.asDiagonal() * H * d.asDiagonal();
  const Vec6 eigen = Eigen::SelfAdjointEigenSolver<Mat6>(scaled).eigenvalues();
  ASSERT_LT(eigen(5) / eigen(0), 100.0);

  PoseRefinementOptions options;
  options.max_iterations = 1;
  const PoseRefinementResult result = refinePose(start, s.p_world, s.xy_normalised, kFocalPx, options);
  ASSERT_EQ(result.iterations, 1);
  const Vec6 step = poseDifference(result.T_camera_world, start);
  EXPECT_LT((step - step_gn).norm(), 1e-2 * step_gn.norm()) << "step " << step.transpose() << "\nGauss-Newton "
                                                            << step_gn.transpose();
}

// Exact data, a start 3 degrees and 8 cm off: the refinement lands on the exact pose to 1e-9
// (rad and m; Gauss-Newton converges quadratically, so the limit is double rounding) with a
// reprojection error under 1e-6 px.
TEST_P(PoseRefinementExact, ConvergesToTheExactPose) {
  const Scene s = makeScene(GetParam());
  const SE3 start = applyPoseDelta(s.T_camera_world, (Vec6() << 0.03, -0.04, 0.02, 0.05, -0.03, 0.06).finished());
  ASSERT_GT(poseDifference(start, s.T_camera_world).norm(), 0.05);
  for (const double huber_px : {0.0, 1.0}) {
    PoseRefinementOptions options;
    options.max_iterations = 20;
    options.huber_px = huber_px;
    const PoseRefinementResult result = refinePose(start, s.p_world, s.xy_normalised, kFocalPx, options);
    EXPECT_LT(poseDifference(result.T_camera_world, s.T_camera_world).norm(), 1e-9) << "huber " << huber_px;
    EXPECT_LT(result.rms_px, 1e-6) << "huber " << huber_px;
    EXPECT_GE(result.iterations, 2) << "huber " << huber_px;
  }
}

INSTANTIATE_TEST_SUITE_P(Poses, PoseRefinementExact, ::testing::Range(0, 6));

// Gaussian pixel noise sigma: the refined pose's error delta has covariance sigma^2 H^-1 (H =
// reprojectionHessian, the information matrix up to sigma^2), so delta^T H delta / sigma^2 is
// chi-square with 6 degrees of freedom: mean 6, standard deviation of the mean over 300 trials
// sqrt(12 / 300) = 0.2. Accepted within 4 of those: [5.2, 6.8].
TEST(PoseRefinementNoise, ErrorMatchesTheInformationMatrix) {
  constexpr double kSigmaPx = 0.5;
  constexpr int kTrials = 300;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, kSigmaPx / kFocalPx);
  double nees_sum = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    Scene s = makeScene(trial % 6);
    const Mat6 H = reprojectionHessian(s.T_camera_world, s.p_world, s.xy_normalised, kFocalPx);
    for (Vec2& xy : s.xy_normalised) xy += Vec2(noise(rng), noise(rng));
    const PoseRefinementResult result = refinePose(s.T_camera_world, s.p_world, s.xy_normalised, kFocalPx, {});
    const Vec6 delta = poseDifference(result.T_camera_world, s.T_camera_world);
    nees_sum += delta.dot(H * delta) / (kSigmaPx * kSigmaPx);
  }
  const double nees = nees_sum / kTrials;
  EXPECT_GT(nees, 5.2);
  EXPECT_LT(nees, 6.8);
}

}  // namespace
}  // namespace slamcmp
