// The pose NEES of a scale-free run after its Sim(3) alignment (issue 18): the same poses and
// covariances expressed in an arbitrary frame at an arbitrary scale score exactly as they do in
// the ground truth's frame once the alignment is applied to both.
#include "eval/metrics/nees.h"

#include <random>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include "core/statistics.h"

namespace slamcmp {
namespace {

// Entries uniform in [-scale, scale], from `rng` (Eigen's Random() shares std::rand's state with
// whatever ran before).
Eigen::Matrix<double, 6, 6> randomMatrix(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> uniform(-scale, scale);
  Eigen::Matrix<double, 6, 6> A;
  for (int i = 0; i < 36; ++i) A(i / 6, i % 6) = uniform(rng);
  return A;
}

TEST(Nees, Sim3AlignmentAppliesToPosesAndCovariances) {
  Trajectory groundtruth;
  std::vector<CovariantPose> in_gt_frame, in_own_frame;
  Similarity3 T_gt_estimate;  // estimate frame -> ground-truth frame
  T_gt_estimate.R = rotationFromRotvec(Vec3(0.3, -0.2, 0.9));
  T_gt_estimate.t = Vec3(1.0, -2.0, 0.5);
  T_gt_estimate.scale = 0.25;
  for (int i = 0; i < 20; ++i) {
    const double t = 0.1 * i;
    const SE3 T_world_camera = SE3::fromRotvec(Vec3(0.1 * i, 0.02 * i, -0.05), Vec3(0.1 * i, 0.3, -0.02 * i));
    groundtruth.push_back({t, T_world_camera});
    // The estimate: off by a known error, with a covariance (both in the ground truth's frame).
    const SE3 T_est = SE3(rotationFromRotvec(Vec3(0.01, -0.02, 0.005 * i)) * T_world_camera.R(),
                          T_world_camera.t() + Vec3(0.01, -0.005 * i, 0.02));
    Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Random() * 0.01;
    const PoseCovariance P = A * A.transpose() + 1e-4 * PoseCovariance::Identity();
    in_gt_frame.push_back({t, T_est, P});
    // The same in the estimate's own frame: p = (R^T (p_gt - t)) / s, R_own = R^T R_gt.
    Eigen::Matrix<double, 6, 6> G_inv = Eigen::Matrix<double, 6, 6>::Zero();
    G_inv.topLeftCorner<3, 3>() = T_gt_estimate.R.transpose() / T_gt_estimate.scale;
    G_inv.bottomRightCorner<3, 3>() = T_gt_estimate.R.transpose();
    in_own_frame.push_back({t,
                            SE3(T_gt_estimate.R.transpose() * T_est.R(),
                                T_gt_estimate.R.transpose() * (T_est.t() - T_gt_estimate.t) / T_gt_estimate.scale),
                            G_inv * P * G_inv.transpose()});
  }
  const auto expected = poseNees(groundtruth, in_gt_frame, 0.01);
  const auto aligned = poseNees(groundtruth, in_own_frame, 0.01, T_gt_estimate);
  const auto unaligned = poseNees(groundtruth, in_own_frame, 0.01);
  ASSERT_TRUE(expected && aligned && unaligned);
  EXPECT_EQ(aligned->frames(), 20);
  EXPECT_NEAR(aligned->mean, expected->mean, 1e-9 * expected->mean);
  EXPECT_GT(unaligned->mean, 100 * expected->mean);  // without the alignment the score is meaningless
}


// Errors drawn from each pose's covariance, with the rotation error in the world frame
// (R_true = exp(e) R_estimate, core/tracker.h), average the 6 dof within the 95 % bounds. The
// rotation covariance is thin along one world axis and the cameras turn far: an error taken in
// the camera frame, or with its sign or position/rotation order mixed up, scores far outside.
TEST(Nees, ErrorsDrawnFromTheCovarianceAverageTheDof) {
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  Trajectory groundtruth;
  std::vector<CovariantPose> estimate;
  for (int i = 0; i < 1000; ++i) {
    const double t = 0.1 * i;
    const SE3 T_true = SE3::fromRotvec(Vec3(0.01 * i, 2.0 * std::sin(0.1 * i), 1.5), Vec3(0.1, -0.2, 0.001 * i));
    Eigen::Matrix<double, 6, 6> A = randomMatrix(rng, 0.005);
    A.row(3).setZero();  // rotation about world X known to 1e-4 rad
    PoseCovariance P = A * A.transpose();
    P.diagonal() += (Eigen::Matrix<double, 6, 1>() << 1e-4, 4e-4, 1e-6, 1e-8, 1e-4, 1e-4).finished();
    Eigen::Matrix<double, 6, 1> n;
    for (int k = 0; k < 6; ++k) n(k) = normal(rng);
    const Eigen::Matrix<double, 6, 1> e = Eigen::LLT<PoseCovariance>(P).matrixL() * n;
    // e = (t_true - t_est, log(R_true R_est^T))
    const SE3 T_est(rotationFromRotvec(-e.tail<3>()) * T_true.R(), T_true.t() - e.head<3>());
    groundtruth.push_back({t, T_true});
    estimate.push_back({t, T_est, P});
  }
  const auto nees = poseNees(groundtruth, estimate, 0.01);
  ASSERT_TRUE(nees);
  EXPECT_EQ(nees->frames(), 1000);
  EXPECT_GT(nees->mean, nees->lower);
  EXPECT_LT(nees->mean, nees->upper);
  // Each part over its own block is chi-square with 3 dof too (the covariance couples them).
  for (const NeesMean& part : {nees->position, nees->orientation}) {
    EXPECT_EQ(part.dof, 3);
    EXPECT_GT(part.mean, part.lower);
    EXPECT_LT(part.mean, part.upper);
  }
  EXPECT_NEAR(nees->position.lower, chiSquaredQuantile(3000, 0.025) / 1000, 1e-12);
}

// The parts say which half is off: an orientation error beyond its covariance (a shared bias of
// 3 sigma about one axis) takes the orientation part and the whole NEES out of their bounds and
// leaves the position part inside, where the position's own covariance is independent of it.
TEST(Nees, PartsSeparatePositionFromOrientation) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  Trajectory groundtruth;
  std::vector<CovariantPose> estimate;
  for (int i = 0; i < 300; ++i) {
    const double t = 0.1 * i;
    const SE3 T_true = SE3::fromRotvec(Vec3(0.2, 0.01 * i, -0.3), Vec3(0.05 * i, 0.1, 1.0));
    PoseCovariance P = PoseCovariance::Zero();
    P.diagonal() << 1e-6, 4e-6, 9e-6, 1e-8, 4e-8, 1e-8;
    Eigen::Matrix<double, 6, 1> e;
    for (int k = 0; k < 6; ++k) e(k) = normal(rng) * std::sqrt(P(k, k));
    e(4) += 3 * std::sqrt(P(4, 4));
    const SE3 T_est(rotationFromRotvec(-e.tail<3>()) * T_true.R(), T_true.t() - e.head<3>());
    groundtruth.push_back({t, T_true});
    estimate.push_back({t, T_est, P});
  }
  const auto nees = poseNees(groundtruth, estimate, 0.01);
  ASSERT_TRUE(nees);
  ASSERT_EQ(nees->per_frame_parts.size(), nees->per_frame.size());
  EXPECT_GT(nees->position.mean, nees->position.lower);
  EXPECT_LT(nees->position.mean, nees->position.upper);
  EXPECT_GT(nees->orientation.mean, 3 * nees->orientation.upper);  // about 1 + 1 + 10 = 12 against 3
  EXPECT_GT(nees->mean, nees->upper);
  // With a block-diagonal covariance the whole is the sum of its parts, frame by frame.
  for (size_t k = 0; k < nees->per_frame.size(); ++k)
    EXPECT_NEAR(nees->per_frame[k].nees,
                nees->per_frame_parts[k].position + nees->per_frame_parts[k].orientation,
                1e-9 * nees->per_frame[k].nees);
}


// A board-free filter's world is its first camera, exactly; its covariance grows from there. With
// the gauge at the first pose its errors score the 6 dof; with an alignment fitted over the run,
// a few millimetres and a degree off at that camera, the same run scores far above its bounds.
TEST(Nees, BoardFreeRunScoredInItsGaugeAtTheFirstCamera) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  Similarity3 T_gt_estimate;  // the run's frame -> ground truth's
  T_gt_estimate.R = rotationFromRotvec(Vec3(0.2, 0.4, -0.3));
  T_gt_estimate.t = Vec3(0.3, -0.1, 0.8);
  T_gt_estimate.scale = 0.4;
  Trajectory groundtruth;
  std::vector<CovariantPose> estimate;  // in the run's own frame
  Eigen::Matrix<double, 6, 6> A = randomMatrix(rng, 3e-4);
  const PoseCovariance P_step = A * A.transpose() + 1e-8 * PoseCovariance::Identity();  // ground-truth frame
  Eigen::Matrix<double, 6, 6> G_inv = Eigen::Matrix<double, 6, 6>::Zero();  // ground truth's -> the run's
  G_inv.topLeftCorner<3, 3>() = T_gt_estimate.R.transpose() / T_gt_estimate.scale;
  G_inv.bottomRightCorner<3, 3>() = T_gt_estimate.R.transpose();
  for (int i = 0; i < 300; ++i) {
    const double t = 0.1 * i;
    const SE3 T_true = SE3::fromRotvec(Vec3(0.3, 0.002 * i, 0.1), Vec3(0.001 * i, 0.2, -0.8));
    const PoseCovariance P = static_cast<double>(i) * P_step;  // exact at the first camera
    Eigen::Matrix<double, 6, 1> n;
    for (int k = 0; k < 6; ++k) n(k) = normal(rng);
    const Eigen::Matrix<double, 6, 1> e = i == 0 ? Eigen::Matrix<double, 6, 1>::Zero().eval()
                                                 : (Eigen::LLT<PoseCovariance>(P).matrixL() * n).eval();
    const SE3 T_est(rotationFromRotvec(-e.tail<3>()) * T_true.R(), T_true.t() - e.head<3>());  // ground-truth frame
    groundtruth.push_back({t, T_true});
    estimate.push_back({t,
                        SE3(T_gt_estimate.R.transpose() * T_est.R(),
                            T_gt_estimate.R.transpose() * (T_est.t() - T_gt_estimate.t) / T_gt_estimate.scale),
                        G_inv * P * G_inv.transpose()});
  }
  Similarity3 fitted = T_gt_estimate;  // as a fit over the run leaves it
  fitted.R = rotationFromRotvec(Vec3(0.0, 0.017, 0.0)) * T_gt_estimate.R;
  fitted.t += Vec3(0.003, -0.002, 0.004);
  const auto in_gauge = poseNees(groundtruth, estimate, 0.01, fitted, true);
  const auto fit = poseNees(groundtruth, estimate, 0.01, fitted);
  ASSERT_TRUE(in_gauge && fit);
  EXPECT_EQ(in_gauge->frames(), 299);  // the first camera has no uncertainty to score
  EXPECT_GT(in_gauge->mean, in_gauge->lower);
  EXPECT_LT(in_gauge->mean, in_gauge->upper);
  EXPECT_GT(fit->mean, 10 * fit->upper);
}

}  // namespace
}  // namespace slamcmp
