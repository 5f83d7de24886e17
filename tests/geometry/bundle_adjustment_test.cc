// The n-view refinement's estimators (geometry/bundle_adjustment, geometry/pose_graph): exact
// synthetic data first (tolerance near machine precision), then with noise and outliers.
#include "geometry/bundle_adjustment.h"

#include <random>


#include <gtest/gtest.h>

#include "core/target.h"
#include "geometry/pose_graph.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

constexpr double kFocalPx = 525;

// Eight cameras along a 35 cm path looking at 150 points 1 to 2 m away.
struct Scene {
  std::vector<SE3> T_world_camera;
  std::vector<Vec3> points;
};

Scene makeScene(std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Scene s;
  for (int i = 0; i < 8; ++i)
    s.T_world_camera.push_back(SE3::fromRotvec(Vec3(0.05 * u(*rng), 0.3 * i / 8.0 + 0.02 * u(*rng), 0.02 * u(*rng)),
                                               Vec3(0.05 * i, 0.01 * u(*rng), 0.01 * u(*rng))));
  for (int j = 0; j < 150; ++j) s.points.push_back(Vec3(0.2 + u(*rng), 0.6 * u(*rng), 1.5 + 0.5 * u(*rng)));
  return s;
}

Vec2 project(const SE3& T_world_camera, const Vec3& p_world) {
  const Vec3 p = T_world_camera.inverse() * p_world;
  return p.head<2>() / p.z();
}

SE3 perturbed(const SE3& T, std::mt19937* rng, double rotation, double translation) {
  std::uniform_real_distribution<double> u(-1, 1);
  return SE3::fromRotvec(T.rotvec() + rotation * Vec3(u(*rng), u(*rng), u(*rng)),
                         T.t() + translation * Vec3(u(*rng), u(*rng), u(*rng)));
}

// The scene's eight cameras: the first two fixed where they are (position, orientation and
// scale), the others started `off` (radians and metres per axis, at most) away.
void addCameras(BundleAdjustment* ba, const Scene& s, std::mt19937* rng, double off) {
  for (int i = 0; i < 8; ++i)
    ba->addCamera((i < 2 ? s.T_world_camera[i] : perturbed(s.T_world_camera[i], rng, off, off)).inverse(), i < 2);
}

// Two fixed cameras hold position, orientation and scale; from poses 1 cm / 0.6 degree and points
// 3 cm off, the exact solution is found.
TEST(BundleAdjustment, RecoversExactDataToMachinePrecision) {
  std::mt19937 rng(3);
  const Scene s = makeScene(&rng);
  BundleAdjustment ba;
  addCameras(&ba, s, &rng, 0.01);
  std::uniform_real_distribution<double> u(-1, 1);
  for (size_t j = 0; j < s.points.size(); ++j) {
    const int p = ba.addPoint(s.points[j] + 0.03 * Vec3(u(rng), u(rng), u(rng)), false);
    for (int i = 0; i < 8; ++i) ba.addObservation(i, p, project(s.T_world_camera[i], s.points[j]), 0.3);
  }
  BundleAdjustmentOptions options;
  options.max_iterations = 30;
  const BundleAdjustmentSummary summary = ba.solve(options, kFocalPx);
  EXPECT_LT(summary.final_cost, 1e-16);
  for (int i = 0; i < 8; ++i) {
    EXPECT_LT((ba.camera(i).inverse().t() - s.T_world_camera[i].t()).norm(), 1e-10) << i;
    EXPECT_LT(rotationAngle(ba.camera(i).R() * s.T_world_camera[i].R()), 1e-10) << i;
  }
  for (size_t j = 0; j < s.points.size(); ++j) EXPECT_LT((ba.point(j) - s.points[j]).norm(), 1e-9) << j;
}

// Known points (a board's corners, fixed) hold the gauge alone: one free camera among them is
// placed exactly, and a point seen by it and a fixed camera follows.
TEST(BundleAdjustment, FixedPointsHoldTheGauge) {
  const ChessboardTarget board{9, 6, 0.04};
  const SE3 T_world_a = SE3::fromRotvec(Vec3(0.02, -0.1, 0.01), Vec3(0.1, 0.1, -0.8));
  const SE3 T_world_b = SE3::fromRotvec(Vec3(-0.03, 0.12, 0.0), Vec3(0.25, 0.08, -0.75));
  const Vec3 extra(0.3, -0.1, 0.05);
  BundleAdjustment ba;
  const int a = ba.addCamera(T_world_a.inverse(), true);
  const int b = ba.addCamera(SE3::fromRotvec(Vec3(-0.02, 0.1, 0.02), Vec3(0.24, 0.09, -0.74)).inverse(), false);
  for (const Vec3& c : board.cornersWorld()) ba.addObservation(b, ba.addPoint(c, true), project(T_world_b, c), 0.1);
  const int p = ba.addPoint(extra + Vec3(0.01, 0.01, -0.02), false);
  ba.addObservation(a, p, project(T_world_a, extra), 0.3);
  ba.addObservation(b, p, project(T_world_b, extra), 0.3);
  ba.solve(BundleAdjustmentOptions{}, kFocalPx);
  EXPECT_LT((ba.camera(b).inverse().t() - T_world_b.t()).norm(), 1e-9);
  EXPECT_LT((ba.point(p) - extra).norm(), 1e-8);
}

// With 0.3 px noise the cameras land within a millimetre; a few gross outliers (20 px) barely
// move them with the Huber loss, and pull them well away without it.
TEST(BundleAdjustment, HuberLossResistsOutliers) {
  for (const bool robust : {true, false}) {
    std::mt19937 rng(7);
    const Scene s = makeScene(&rng);
    std::normal_distribution<double> noise(0, 0.3 / kFocalPx);
    BundleAdjustment ba;
    addCameras(&ba, s, &rng, 0.005);
    for (size_t j = 0; j < s.points.size(); ++j) {
      const int p = ba.addPoint(s.points[j], false);
      for (int i = 0; i < 8; ++i) {
        Vec2 xy = project(s.T_world_camera[i], s.points[j]) + Vec2(noise(rng), noise(rng));
        if (j % 15 == 0 && i == 7) xy += Vec2(20.0 / kFocalPx, -20.0 / kFocalPx);  // 10 outliers in camera 7
        ba.addObservation(i, p, xy, 0.3);
      }
    }
    BundleAdjustmentOptions options;
    options.max_iterations = 20;
    if (!robust) options.huber_sigmas = 0;
    ba.solve(options, kFocalPx);
    const double error = (ba.camera(7).inverse().t() - s.T_world_camera[7].t()).norm();
    if (robust) {
      EXPECT_LT(error, 0.002);
    } else {
      EXPECT_GT(error, 0.002);
    }
  }
}

// A point on a ray (inverse depth): its depth is found exactly where the data fix it, and a
// point at infinity (seen without parallax) still holds the rotation of a camera that turns.
TEST(BundleAdjustment, PointsOnRaysFindTheirDepthAndHoldRotations) {
  std::mt19937 rng(11);
  const Scene s = makeScene(&rng);
  BundleAdjustment ba;
  addCameras(&ba, s, &rng, 0.005);
  for (size_t j = 0; j < s.points.size(); ++j) {
    // Through the first camera's observation, starting at twice the depth.
    const Vec3 origin = s.T_world_camera[0].t();
    const Vec3 direction = (s.points[j] - origin).normalized();
    const int p = ba.addPointOnRay(origin, direction, 0.5 / (s.points[j] - origin).norm());
    for (int i = 0; i < 8; ++i) ba.addObservation(i, p, project(s.T_world_camera[i], s.points[j]), 0.3);
  }
  BundleAdjustmentOptions options;
  options.max_iterations = 40;
  ba.solve(options, kFocalPx);
  for (int i = 2; i < 8; ++i) EXPECT_LT((ba.camera(i).inverse().t() - s.T_world_camera[i].t()).norm(), 1e-8) << i;
  for (size_t j = 0; j < s.points.size(); ++j) EXPECT_LT((ba.point(j) - s.points[j]).norm(), 1e-7) << j;

  // A camera turned 10 degrees in place, seeing only very distant points: its rotation is found.
  const SE3 T_world_turned = SE3::fromRotvec(Vec3(0, 0.17, 0), Vec3::Zero());
  BundleAdjustment far;
  far.addCamera(SE3().inverse(), true);
  const int turned = far.addCamera(SE3::fromRotvec(Vec3(0.01, 0.15, -0.01), Vec3::Zero()).inverse(), false);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int j = 0; j < 40; ++j) {
    const Vec3 p_world = 1e4 * Vec3(0.3 * u(rng), 0.2 * u(rng), 1.0);
    const int p = far.addPointOnRay(Vec3::Zero(), p_world.normalized(), 1e-3);
    far.addObservation(0, p, project(SE3(), p_world), 0.3);
    far.addObservation(turned, p, project(T_world_turned, p_world), 0.3);
  }
  far.solve(options, kFocalPx);
  EXPECT_LT(rotationAngle(far.camera(turned).R() * T_world_turned.R()), 1e-6);
}

// A prior on a point holds it where earlier data put it: started where the views put it, 10 cm
// off the prior, a tight prior moves it there (the test had started it at the prior, which a solve
// doing nothing passed); a loose one leaves it to the views.
TEST(BundleAdjustment, PointPriorHoldsAPoint) {
  const SE3 T_world_a, T_world_b = SE3::fromRotvec(Vec3(0, 0.05, 0), Vec3(0.1, 0, 0));
  const Vec3 truth(0.1, 0.05, 1.2), prior(0.1, 0.05, 1.3);
  for (const double sigma_m : {1e-6, 10.0}) {
    SCOPED_TRACE(sigma_m);
    BundleAdjustment ba;
    ba.addCamera(T_world_a.inverse(), true);
    ba.addCamera(T_world_b.inverse(), true);
    const int p = ba.addPoint(truth, false);
    ba.addObservation(0, p, project(T_world_a, truth), 1.0);
    ba.addObservation(1, p, project(T_world_b, truth), 1.0);
    ba.addPointPrior(p, prior, sigma_m);
    ba.solve(BundleAdjustmentOptions{}, kFocalPx);
    EXPECT_LT((ba.point(p) - (sigma_m < 1 ? prior : truth)).norm(), 1e-4);
  }
}

// Bundle adjustment's first step against the Levenberg-Marquardt step of the numeric Jacobian of
// its whitened residuals, -(J^T J + lambda diag(J^T J))^-1 J^T r with its first damping lambda =
// 1e-4, over every kind of unknown it has: free cameras (the left perturbation of applyPoseDelta),
// free points, points on rays (in inverse depth) and a point with a prior, beside fixed cameras and
// fixed points. Plain least squares (no Huber weights). Central differences (step 1e-6) put the
// numeric step within about 1e-8 of it (2e-9 measured); a wrong Jacobian term or Schur complement changes it by
// O(1), no damping (the Gauss-Newton step) by 1.2 per cent here.
TEST(BundleAdjustment, FirstStepIsTheGaussNewtonStepOfTheNumericJacobian) {
  std::mt19937 rng(5);
  const Scene s = makeScene(&rng);
  constexpr int kCameras = 5, kFree = 3, kPoints = 12, kOnRay = 3;
  constexpr double kSigmaPx = 0.5, kPriorSigma = 0.02;
  const ChessboardTarget board{3, 3, 0.1};
  std::vector<Vec3> fixed_points = board.cornersWorld();
  for (Vec3& c : fixed_points) c += Vec3(0.1, -0.1, 1.4);
  // The starts: cameras 1 degree and 1 cm off, free points 2 cm off, rays at 1.3 times the depth.
  std::vector<SE3> T_camera_world;
  for (int i = 0; i < kCameras; ++i)
    T_camera_world.push_back((i < kCameras - kFree ? s.T_world_camera[i] : perturbed(s.T_world_camera[i], &rng, 0.017, 0.01)).inverse());
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec3> start;
  for (int j = 0; j < kPoints; ++j) start.push_back(s.points[j] + 0.02 * Vec3(u(rng), u(rng), u(rng)));
  const Vec3 origin = s.T_world_camera[0].t();
  std::vector<Vec3> direction;
  std::vector<double> rho;
  for (int j = kPoints; j < kPoints + kOnRay; ++j) {
    direction.push_back((s.points[j] - origin).normalized());
    rho.push_back(1.0 / (1.3 * (s.points[j] - origin).norm()));
  }
  const Vec3 prior = s.points[0] + Vec3(0.01, -0.02, 0.015);

  // The unknowns: 6 per free camera, 3 per free point, 1 per point on a ray.
  const int n = 6 * kFree + 3 * kPoints + kOnRay;
  struct State {
    std::vector<SE3> T;
    std::vector<Vec3> points;  // free, on rays, fixed
  };
  const auto state_at = [&](const Eigen::VectorXd& x) {
    State st{T_camera_world, {}};
    for (int i = 0; i < kFree; ++i) st.T[kCameras - kFree + i] = applyPoseDelta(st.T[kCameras - kFree + i], x.segment<6>(6 * i));
    for (int j = 0; j < kPoints; ++j) st.points.push_back(start[j] + x.segment<3>(6 * kFree + 3 * j));
    for (int j = 0; j < kOnRay; ++j) st.points.push_back(origin + direction[j] / (rho[j] + x(6 * kFree + 3 * kPoints + j)));
    st.points.insert(st.points.end(), fixed_points.begin(), fixed_points.end());
    return st;
  };
  // Observations: every camera sees every point, exactly (fixed points only from the free cameras).
  std::vector<std::pair<int, int>> seen;
  std::vector<Vec3> truth(s.points.begin(), s.points.begin() + kPoints + kOnRay);
  truth.insert(truth.end(), fixed_points.begin(), fixed_points.end());
  for (int i = 0; i < kCameras; ++i)
    for (int j = 0; j < static_cast<int>(truth.size()); ++j)
      if (j < kPoints + kOnRay || i >= kCameras - kFree) seen.push_back({i, j});
  const double whiten = kFocalPx / kSigmaPx;
  const auto residuals = [&](const Eigen::VectorXd& x) {
    const State st = state_at(x);
    Eigen::VectorXd r(2 * seen.size() + 3);
    for (size_t k = 0; k < seen.size(); ++k) {
      const Vec3 p = st.T[seen[k].first] * st.points[seen[k].second];
      r.segment<2>(2 * k) = whiten * (p.head<2>() / p.z() - project(s.T_world_camera[seen[k].first], truth[seen[k].second]));
    }
    r.tail<3>() = (st.points[0] - prior) / kPriorSigma;
    return r;
  };
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  const Eigen::MatrixXd J = test::numericJacobian(residuals, zero);
  const Eigen::MatrixXd H = J.transpose() * J;
  Eigen::MatrixXd damped = H;
  damped.diagonal() *= 1 + 1e-4;
  const Eigen::VectorXd step_lm = -damped.ldlt().solve(J.transpose() * residuals(zero));

  BundleAdjustment ba;
  for (int i = 0; i < kCameras; ++i) ba.addCamera(T_camera_world[i], i < kCameras - kFree);
  for (int j = 0; j < kPoints; ++j) ba.addPoint(start[j], false);
  for (int j = 0; j < kOnRay; ++j) ba.addPointOnRay(origin, direction[j], rho[j]);
  for (const Vec3& c : fixed_points) ba.addPoint(c, true);
  for (const auto& [i, j] : seen) ba.addObservation(i, j, project(s.T_world_camera[i], truth[j]), kSigmaPx);
  ba.addPointPrior(0, prior, kPriorSigma);
  BundleAdjustmentOptions options;
  options.max_iterations = 1;
  options.huber_sigmas = 0;
  ASSERT_EQ(ba.solve(options, kFocalPx).iterations, 1);

  Eigen::VectorXd step(n);
  for (int i = 0; i < kFree; ++i)
    step.segment<6>(6 * i) = poseDifference(ba.camera(kCameras - kFree + i), T_camera_world[kCameras - kFree + i]);
  for (int j = 0; j < kPoints; ++j) step.segment<3>(6 * kFree + 3 * j) = ba.point(j) - start[j];
  for (int j = 0; j < kOnRay; ++j)
    step(6 * kFree + 3 * kPoints + j) = 1.0 / (ba.point(kPoints + j) - origin).dot(direction[j]) - rho[j];
  for (size_t j = kPoints + kOnRay; j < truth.size(); ++j) EXPECT_EQ(ba.point(j), fixed_points[j - kPoints - kOnRay]);
  for (int i = 0; i < kCameras - kFree; ++i) EXPECT_LT(poseDifference(ba.camera(i), T_camera_world[i]).norm(), 1e-15);
  EXPECT_LT((step - step_lm).norm(), 1e-6 * step_lm.norm()) << "step " << step.transpose() << "\nLevenberg-Marquardt "
                                                            << step_lm.transpose();
}

// A chain of poses whose measured motions are consistent with the poses is left alone; one that
// drifted is pulled onto the poses held at both ends, the drift spread along it.
TEST(PoseGraph, SpreadsTheDriftOfAChainHeldAtBothEnds) {
  constexpr int n = 21;
  std::vector<SE3> truth;
  for (int k = 0; k < n; ++k) truth.push_back(SE3::fromRotvec(Vec3(0, 0.05 * k, 0.01 * k), Vec3(0.02 * k, 0.005 * k, 0)));
  std::vector<PoseGraphEdge> edges;
  for (int k = 0; k + 1 < n; ++k) {
    PoseGraphEdge e;
    e.from = k;
    e.to = k + 1;
    e.T_from_to = truth[k].inverse() * truth[k + 1];
    edges.push_back(e);
  }
  std::vector<char> fixed(n, 0);
  fixed.front() = fixed.back() = 1;
  // Consistent: unchanged.
  const std::vector<SE3> same = optimisePoseGraph(truth, fixed, edges);
  for (int k = 0; k < n; ++k) EXPECT_LT((same[k].t() - truth[k].t()).norm(), 1e-9) << k;
  // The odometry drifted: each motion 1 % long and turned 0.05 degrees; the chain's own poses
  // follow it, only the ends are known.
  std::vector<SE3> drifted{truth.front()};
  for (int k = 0; k + 1 < n; ++k) {
    const SE3 motion = truth[k].inverse() * truth[k + 1];
    edges[k].T_from_to = SE3(rotationFromRotvec(Vec3(0, 0.0009, 0)) * motion.R(), 1.01 * motion.t());
    drifted.push_back(drifted.back() * edges[k].T_from_to);
  }
  drifted.back() = truth.back();
  const std::vector<SE3> corrected = optimisePoseGraph(drifted, fixed, edges);
  double before = 0, after = 0;
  for (int k = 1; k + 1 < n; ++k) {
    before = std::max(before, (drifted[k].t() - truth[k].t()).norm());
    after = std::max(after, (corrected[k].t() - truth[k].t()).norm());
  }
  EXPECT_GT(before, 0.003);
  EXPECT_LT(after, 0.25 * before);
  EXPECT_LT((corrected.back().t() - truth.back().t()).norm(), 1e-12);
}

}  // namespace
}  // namespace slamcmp
