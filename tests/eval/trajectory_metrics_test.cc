// ATE and RPE on cases computed by hand.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "eval/metrics/run_errors.h"
#include "eval/metrics/trajectory_metrics.h"

namespace slamcmp {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A curved, turning, non-planar path: 40 poses at 10 Hz.
Trajectory wigglyTrajectory() {
  Trajectory t;
  for (int i = 0; i < 40; ++i) {
    const double a = 0.15 * i;
    t.push_back({1000.0 + 0.1 * i,
                 SE3::fromRotvec(Vec3(0.1 * std::sin(a), 0.05 * a, 0.2 * std::cos(0.7 * a)),
                                 Vec3(2.0 * std::cos(a), 1.5 * std::sin(a), 0.3 * a))});
  }
  return t;
}

EvalOptions withAlign(const std::string& align, int delta = 1) {
  EvalOptions o;
  o.align = align;
  o.delta = delta;
  return o;
}

TEST(TrajectoryMetrics, TrajectoryAgainstItselfHasNoError) {
  const Trajectory t = wigglyTrajectory();
  for (const char* align : {"none", "se3", "sim3", "origin"}) {
    const TrajectoryEvaluation e = evaluateTrajectory(t, t, withAlign(align));
    EXPECT_EQ(e.pairs.size(), t.size()) << align;
    EXPECT_LT(e.ate_trans_stats.max, 1e-12) << align;
    EXPECT_LT(e.ate_rot_deg_stats.max, 1e-9) << align;
    EXPECT_LT(e.rpe_trans_stats.max, 1e-12) << align;
    EXPECT_LT(e.rpe_rot_deg_stats.max, 1e-9) << align;
    EXPECT_NEAR(e.T_gt_estimate.scale, 1.0, 1e-12) << align;
    EXPECT_EQ(e.rpe_trans.size(), t.size() - 1) << align;
  }
}

// The estimate is the ground truth moved by a constant world offset: every ATE translation error
// is |offset|, per axis |offset_k|; rotations and relative motions are untouched; se3 alignment
// removes the offset.
TEST(TrajectoryMetrics, KnownOffsetGivesExactAte) {
  const Trajectory gt = wigglyTrajectory();
  const Vec3 offset(0.1, -0.2, 0.3);
  Trajectory est = gt;
  for (auto& p : est) p.T_world_camera = SE3(p.T_world_camera.R(), p.T_world_camera.t() + offset);

  const TrajectoryEvaluation e = evaluateTrajectory(gt, est, withAlign("none"));
  EXPECT_NEAR(e.ate_trans_stats.rmse, offset.norm(), 1e-12);
  EXPECT_NEAR(e.ate_trans_stats.min, offset.norm(), 1e-12);
  EXPECT_NEAR(e.ate_trans_stats.max, offset.norm(), 1e-12);
  EXPECT_NEAR(e.ate_trans_stats.std, 0.0, 1e-12);
  EXPECT_LT((e.ate_axis_rmse - offset.cwiseAbs()).norm(), 1e-12);
  EXPECT_LT(e.ate_rot_deg_stats.max, 1e-9);
  EXPECT_LT(e.rpe_trans_stats.max, 1e-12);

  const TrajectoryEvaluation aligned = evaluateTrajectory(gt, est, withAlign("se3"));
  EXPECT_LT(aligned.ate_trans_stats.max, 1e-12);
}

// The estimate is the ground truth seen through a similarity (as a monocular SLAM's arbitrary
// world frame and scale): sim3 recovers the scale and removes the error; se3 cannot.
TEST(TrajectoryMetrics, Sim3RecoversAKnownSimilarity) {
  const Trajectory gt = wigglyTrajectory();
  const Mat3 R_gt_est = rotationFromRotvec(Vec3(0.4, -0.2, 1.3));
  const Vec3 t_gt_est(3.0, -1.0, 2.0);
  const double scale = 0.37;  // p_gt = scale * R * p_est + t
  Trajectory est = gt;
  for (auto& p : est)
    p.T_world_camera = SE3(R_gt_est.transpose() * p.T_world_camera.R(),
                           R_gt_est.transpose() * (p.T_world_camera.t() - t_gt_est) / scale);

  const TrajectoryEvaluation e = evaluateTrajectory(gt, est, withAlign("sim3"));
  EXPECT_NEAR(e.T_gt_estimate.scale, scale, 1e-12);
  EXPECT_LT((e.T_gt_estimate.R - R_gt_est).norm(), 1e-12);
  EXPECT_LT(e.ate_trans_stats.max, 1e-12);
  EXPECT_LT(e.ate_rot_deg_stats.max, 1e-9);
  EXPECT_LT(e.rpe_trans_stats.max, 1e-12);
  EXPECT_LT(e.rpe_rot_deg_stats.max, 1e-9);

  const TrajectoryEvaluation rigid = evaluateTrajectory(gt, est, withAlign("se3"));
  EXPECT_EQ(rigid.T_gt_estimate.scale, 1.0);
  EXPECT_GT(rigid.ate_trans_stats.rmse, 0.1);
  EXPECT_LT(rigid.ate_rot_deg_stats.max, 1e-9);  // the rotation is still found exactly
}

// The estimate lives in another world frame (G on the left of every pose, as a run whose world is
// its first camera) and from pose 1 on is off by a known turn a_k and a known step d_k in its own
// camera frame: est_k = G gt_k (Rx(a_k), d_k). Origin alignment (evo's --align_origin) undoes G
// exactly, since the first pose is unperturbed: every rotation error is a_k and every position
// error |d_k|. An se3 fit of the positions would spread the steps over every pose instead; "none"
// leaves G's error.
TEST(TrajectoryMetrics, OriginAlignmentLeavesEachPoseRelativeToTheFirst) {
  const Trajectory gt = wigglyTrajectory();
  const SE3 G = SE3::fromRotvec(Vec3(0.3, -1.1, 0.6), Vec3(-2.0, 0.5, 4.0));
  Trajectory est = gt;
  std::vector<double> turn_deg(gt.size()), step(gt.size());
  for (size_t k = 0; k < est.size(); ++k) {
    const double i = static_cast<double>(k);  // 0 at the first pose
    turn_deg[k] = 0.25 * i;
    const Vec3 d_camera(0.002 * i, -0.001 * i * i / 40, 0.003 * std::sin(0.3 * i));
    step[k] = d_camera.norm();
    est[k].T_world_camera =
        G * gt[k].T_world_camera * SE3::fromRotvec(Vec3(turn_deg[k] * kPi / 180, 0, 0), d_camera);
  }
  const TrajectoryEvaluation e = evaluateTrajectory(gt, est, withAlign("origin"));
  ASSERT_EQ(e.ate_rot_deg.size(), gt.size());
  for (size_t k = 0; k < gt.size(); ++k) {
    EXPECT_NEAR(e.ate_rot_deg[k], turn_deg[k], 1e-9) << k;
    EXPECT_NEAR(e.ate_trans[k], step[k], 1e-12) << k;
  }
  EXPECT_GT(evaluateTrajectory(gt, est, withAlign("se3")).ate_trans.front(), 1e-3);
  EXPECT_EQ(e.T_gt_estimate.scale, 1.0);
  EXPECT_LT((e.T_gt_estimate.R - G.inverse().R()).norm(), 1e-12);
  EXPECT_EQ(evaluationToJson(e, withAlign("origin"))["align"], "origin");
  EXPECT_GT(evaluateTrajectory(gt, est, withAlign("none")).ate_trans_stats.min, 1.0);
}

// Four poses along x, 1 m apart; the estimate's third pose is off by 0.1 m in y and turned 90
// degrees about z. By hand, with E = (gt_i^-1 gt_j)^-1 (est_i^-1 est_j):
//   (0,1): identity;  (1,2): (Rz(90), (0, 0.1, 0));
//   (2,3): (Rz(-90), Rz(-90) (1, -0.1, 0) - (1, 0, 0)) = (Rz(-90), (-1.1, -1, 0)).
// With delta 2 the only pair is (0,2): (Rz(90), (0, 0.1, 0)).
TEST(TrajectoryMetrics, RpeByHandOnFourPoses) {
  Trajectory gt, est;
  for (int i = 0; i < 4; ++i) gt.push_back({double(i), SE3(Mat3::Identity(), Vec3(i, 0, 0))});
  est = gt;
  est[2].T_world_camera = SE3::fromRotvec(Vec3(0, 0, kPi / 2), Vec3(2, 0.1, 0));

  const TrajectoryEvaluation e = evaluateTrajectory(gt, est, withAlign("none", 1));
  ASSERT_EQ(e.rpe_trans.size(), 3u);
  EXPECT_NEAR(e.rpe_trans[0], 0.0, 1e-15);
  EXPECT_NEAR(e.rpe_trans[1], 0.1, 1e-15);
  EXPECT_NEAR(e.rpe_trans[2], std::sqrt(1.1 * 1.1 + 1.0), 1e-14);
  EXPECT_NEAR(e.rpe_rot_deg[0], 0.0, 1e-12);
  EXPECT_NEAR(e.rpe_rot_deg[1], 90.0, 1e-12);
  EXPECT_NEAR(e.rpe_rot_deg[2], 90.0, 1e-12);
  EXPECT_NEAR(e.rpe_trans_stats.rmse, std::sqrt((0.01 + 2.21) / 3.0), 1e-14);
  EXPECT_NEAR(e.rpe_axis_rmse.x(), std::sqrt(1.21 / 3.0), 1e-14);
  EXPECT_NEAR(e.rpe_axis_rmse.y(), std::sqrt(1.01 / 3.0), 1e-14);
  // ATE: only pose 2 is off, by 0.1 m and 90 degrees.
  EXPECT_NEAR(e.ate_trans_stats.max, 0.1, 1e-15);
  EXPECT_NEAR(e.ate_trans_stats.mean, 0.025, 1e-15);
  EXPECT_NEAR(e.ate_rot_deg_stats.max, 90.0, 1e-12);

  const TrajectoryEvaluation e2 = evaluateTrajectory(gt, est, withAlign("none", 2));
  ASSERT_EQ(e2.rpe_trans.size(), 1u);
  EXPECT_NEAR(e2.rpe_trans[0], 0.1, 1e-15);
  EXPECT_NEAR(e2.rpe_rot_deg[0], 90.0, 1e-12);

  // evo_rpe --all_pairs: (0,2) as above and (1,3): gt_1^-1 gt_3 = (I, (2, 0, 0)), est_1^-1 est_3 =
  // (I, (2, 0, 0)): no error.
  EvalOptions all = withAlign("none", 2);
  all.all_pairs = true;
  const TrajectoryEvaluation e3 = evaluateTrajectory(gt, est, all);
  ASSERT_EQ(e3.rpe_trans.size(), 2u);
  EXPECT_NEAR(e3.rpe_trans[0], 0.1, 1e-15);
  EXPECT_NEAR(e3.rpe_trans[1], 0.0, 1e-15);
  EXPECT_NEAR(e3.rpe_rot_deg[1], 0.0, 1e-12);
  EXPECT_EQ(evaluationToJson(e3, all)["rpe"]["all_pairs"], true);
  all.delta = 1;  // with delta 1 every pair is a consecutive one
  EXPECT_EQ(evaluateTrajectory(gt, est, all).rpe_trans, e.rpe_trans);
}

TEST(TrajectoryMetrics, TooFewPairsAreRefused) {
  Trajectory gt, est;
  for (int i = 0; i < 2; ++i) gt.push_back({double(i), SE3(Mat3::Identity(), Vec3(i, 0, 0))});
  est = gt;
  EXPECT_THROW(evaluateTrajectory(gt, est, withAlign("se3")), InputError);      // < 3 for Umeyama
  EXPECT_THROW(evaluateTrajectory(gt, est, withAlign("none", 2)), InputError);  // no RPE pair
  EXPECT_NO_THROW(evaluateTrajectory(gt, est, withAlign("none", 1)));
}

// A camera stamped 37 ms late (on arrival): no pose is within --max-diff of the ground truth's;
// an offset the wrong way pairs each pose with the ground truth's next (the error of one 0.1 s
// step, 0.3 m); --t-offset -0.037 pairs every pose with its own.
TEST(TrajectoryMetrics, ClockOffsetOfTheEstimateIsTakenOut) {
  const Trajectory gt = wigglyTrajectory();
  Trajectory late = gt;
  for (StampedPose& pose : late) pose.timestamp += 0.037;
  EXPECT_THROW(evaluateTrajectory(gt, late, withAlign("none")), InputError);
  EvalOptions options = withAlign("none");
  options.t_offset = 0.5;  // far the wrong way: no pair, and the error says the times are shifted
  try {
    evaluateTrajectory(gt, late, options);
    ADD_FAILURE() << "no pose pair, yet no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("after --t-offset 0.5"), std::string::npos) << e.what();
  }
  options.t_offset = 0.063;  // the wrong way: now 0.1 s late, a whole step
  const TrajectoryEvaluation wrong = evaluateTrajectory(gt, late, options);
  EXPECT_EQ(wrong.pairs.size(), gt.size() - 1);
  EXPECT_GT(wrong.ate_trans_stats.min, 0.1);
  options.t_offset = -0.037;
  const TrajectoryEvaluation e = evaluateTrajectory(gt, late, options);
  EXPECT_EQ(e.pairs.size(), gt.size());
  EXPECT_LT(e.ate_trans_stats.max, 1e-12);
  EXPECT_EQ(evaluationToJson(e, options)["t_offset"], -0.037);
}

// A board-started run in a world scaled or turned against its ground truth (a board described
// wrong) is told; one that drifted away, or an exact one, is not.
TEST(TrajectoryMetrics, ABoardWorldScaledOrTurnedIsTold) {
  const Trajectory truth = wigglyTrajectory();
  const auto moved = [&](double scale, const Mat3& R) {
    Trajectory t = truth;
    for (StampedPose& p : t) p.T_world_camera = SE3(R * p.T_world_camera.R(), scale * (R * p.T_world_camera.t()));
    return t;
  };
  const auto ate = [&](const Trajectory& estimate) { return evaluateRun(truth, estimate)->ate_trans_rmse; };
  const Trajectory halved = moved(0.5, Mat3::Identity());
  EXPECT_NE(boardWorldMismatch(truth, halved, ate(halved)).find("a scale of 2.000"), std::string::npos);
  const Trajectory turned = moved(1.0, SE3::fromRotvec(Vec3(0, 0, kPi / 2), Vec3::Zero()).R());
  EXPECT_NE(boardWorldMismatch(truth, turned, ate(turned)).find("a 90.0 degree turn"), std::string::npos);
  EXPECT_EQ(boardWorldMismatch(truth, truth, 0.0), "");
  // A short slow path (tv1's 60 frames, 0.1 m), exact for half the run, then 2 cm more astray
  // every frame: a Sim(3) shrinks it onto the truth's middle and fits 5 times better, but not to
  // within a tenth of the truth's spread.
  Trajectory slow, astray;
  for (int i = 0; i < 60; ++i) {
    const Vec3 p_world(0.0017 * i, 0.01 * std::sin(0.2 * i), -0.8);
    slow.push_back({1000.0 + 0.1 * i, SE3(Mat3::Identity(), p_world)});
    astray.push_back({1000.0 + 0.1 * i, SE3(Mat3::Identity(), p_world + Vec3(0.02 * std::max(0, i - 29), 0, 0))});
  }
  const auto without = evaluateRun(slow, astray), with = evaluateRun(slow, astray, "sim3");
  ASSERT_GT(without->ate_trans_rmse, 5 * with->ate_trans_rmse);  // the fit's gain alone would tell
  EXPECT_EQ(boardWorldMismatch(slow, astray, without->ate_trans_rmse), "");
}

TEST(TrajectoryMetrics, BadOptionsAreRefused) {
  const Trajectory t = wigglyTrajectory();
  EXPECT_THROW(evaluateTrajectory(t, t, withAlign("sim2")), InputError);
  EXPECT_THROW(evaluateTrajectory(t, t, withAlign("none", 0)), InputError);
  EvalOptions negative;
  negative.max_diff = -1.0;
  EXPECT_THROW(evaluateTrajectory(t, t, negative), InputError);
  EvalOptions not_a_number;
  not_a_number.t_offset = std::nan("");
  EXPECT_THROW(evaluateTrajectory(t, t, not_a_number), InputError);
}

}  // namespace
}  // namespace slamcmp
