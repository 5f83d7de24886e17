#include "ekf/ekf_update.h"

#include <random>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "ekf/rolling_shutter.h"
#include "tests/ekf/plane_render.h"

namespace slamcmp {
namespace {

EkfState uncertainState() {
  EkfState s;
  Eigen::Matrix<double, 13, 13> P = Eigen::Matrix<double, 13, 13>::Identity() * 1e-4;
  s.reset(SE3::fromRotvec(Vec3(0.05, -0.1, 0.02), Vec3(0.1, 0.1, -1.0)), P);
  s.append(Vec3(0.2, 0.1, 0.0), Mat3::Identity() * 1e-3, Eigen::MatrixXd::Zero(3, 13));
  s.append(Vec3(-0.1, 0.3, 0.1), Mat3::Identity() * 2e-3, Eigen::MatrixXd::Zero(3, 16));
  return s;
}

PointObservation observe(const EkfState& s, const CameraModel& camera, int offset, const Vec2& offset_px) {
  PointObservation o;
  o.offset = offset;
  predictMeasurement(camera, s.r(), s.q(), s.x().segment<3>(offset), &o.h);
  o.z = o.h.uv_distorted + offset_px;
  return o;
}

// With the Jacobians held fixed, one batch update equals two sequential updates, the second
// innovation taken against the first update's linearised prediction.
TEST(EkfUpdate, BatchEqualsSequentialForAFixedLinearisation) {
  const CameraModel camera = test::testCamera();
  const EkfState prior = uncertainState();
  const PointObservation a = observe(prior, camera, 13, Vec2(2.0, -1.0));
  const PointObservation b = observe(prior, camera, 16, Vec2(-1.5, 0.5));

  EkfState batch = prior;
  batchUpdate(batch, {a, b}, 1.0);

  EkfState sequential = prior;
  batchUpdate(sequential, {a}, 1.0);
  PointObservation b2 = b;
  // Linearised prediction of b at the updated state (q renormalisation is second order here).
  const Eigen::VectorXd dx = sequential.x() - prior.x();
  b2.h.uv_distorted += b.h.H_r * dx.segment<3>(EkfState::kR) + b.h.H_q * dx.segment<4>(EkfState::kQ) +
                       b.h.H_y * dx.segment<3>(16);
  batchUpdate(sequential, {b2}, 1.0);
  EXPECT_LT((batch.x() - sequential.x()).norm(), 1e-6);
  EXPECT_LT((batch.P() - sequential.P()).norm(), 1e-7);
}

// The block-wise S (one point, or several jointly) and the rank update equal the textbook dense
// formulas with the full H (2m x n): S = H P H^T + R, K = P H^T S^-1, P - K S K^T.
TEST(EkfUpdate, BlockwiseFormulasEqualTheDenseOnes) {
  const CameraModel camera = test::testCamera();
  EkfState prior = uncertainState();
  // Dense correlations between everything, as after some frames of tracking.
  Eigen::MatrixXd A = Eigen::MatrixXd::Random(prior.size(), prior.size()) * 0.01;
  prior.P() += A * A.transpose();
  const std::vector<PointObservation> obs = {observe(prior, camera, 13, Vec2(1.0, -0.5)),
                                             observe(prior, camera, 16, Vec2(-0.5, 2.0))};
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(4, prior.size());
  Eigen::VectorXd nu(4);
  for (int k = 0; k < 2; ++k) {
    H.block<2, 3>(2 * k, EkfState::kR) = obs[k].h.H_r;
    H.block<2, 4>(2 * k, EkfState::kQ) = obs[k].h.H_q;
    H.block<2, 3>(2 * k, obs[k].offset) = obs[k].h.H_y;
    nu.segment<2>(2 * k) = obs[k].z - obs[k].h.uv_distorted;
  }
  const double sigma = 1.5;
  const Eigen::MatrixXd S = H * prior.P() * H.transpose() + sigma * sigma * Eigen::MatrixXd::Identity(4, 4);
  EXPECT_LT((innovationCovariance(prior, obs, sigma) - S).norm(), 1e-9 * S.norm());
  EXPECT_LT((pointInnovationCovariance(prior, obs[1].h, 16, sigma) - S.block<2, 2>(2, 2)).norm(), 1e-9 * S.norm());

  const Eigen::MatrixXd K = prior.P() * H.transpose() * S.inverse();
  EkfState expected = prior;
  expected.x() += K * nu;
  expected.P() -= K * S * K.transpose();
  expected.renormaliseQuaternion();
  EkfState s = prior;
  batchUpdate(s, obs, sigma);
  EXPECT_LT((s.x() - expected.x()).norm(), 1e-12);
  EXPECT_LT((s.P() - expected.P()).norm(), 1e-10 * prior.P().norm());
}

TEST(EkfUpdate, UpdateShrinksUncertaintyAndKeepsSymmetry) {
  const CameraModel camera = test::testCamera();
  EkfState s = uncertainState();
  const Eigen::MatrixXd S = innovationCovariance(s, {observe(s, camera, 13, Vec2::Zero())}, 1.0);
  const double trace_before = s.P().trace();
  batchUpdate(s, {observe(s, camera, 13, Vec2(1, 1)), observe(s, camera, 16, Vec2(0, 0))}, 1.0);
  EXPECT_LT(s.P().trace(), trace_before);
  EXPECT_LT((s.P() - s.P().transpose()).norm(), 1e-15);
  EXPECT_NEAR(s.q().norm(), 1.0, 1e-15);
  EXPECT_GT(S(0, 0), 1.0);  // pixel noise plus the state's share
}

// A covariance broken by round-off (negative variance of a point) gives an S that is not positive
// definite: the update refuses rather than writing NaNs into the state.
TEST(EkfUpdate, RefusesAnInnovationCovarianceThatIsNotPositiveDefinite) {
  const CameraModel camera = test::testCamera();
  EkfState s = uncertainState();
  s.P().block<3, 3>(13, 13) = -Mat3::Identity();
  const EkfState before = s;
  EXPECT_FALSE(batchUpdate(s, {observe(s, camera, 13, Vec2(1, 1))}, 1e-3));
  EXPECT_EQ(s.x(), before.x());
  EXPECT_EQ(s.P(), before.P());
  EXPECT_TRUE(batchUpdate(s, {observe(s, camera, 16, Vec2(1, 1))}, 1.0));  // the other point is fine
}


// A 9x6 board (30 mm squares, z = 0) seen 0.8 m away with 0.05 px noise, and a prior 6 cm and 3
// degrees off with a wide covariance: the board found again after a drift.
struct BoardReturn {
  CameraModel camera = test::testCamera();
  SE3 T_world_camera = SE3::fromRotvec(Vec3(0.1, -0.15, 0.05), Vec3(0.05, 0.02, -0.8));
  std::vector<Vec3> corners;
  std::vector<Vec2> uv;
  EkfState prior;
  double readout = 0;  // s; a rolling shutter's: each corner predicted at its row's time
  BoardReturn() {
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 0.05);
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 9; ++i) {
        corners.emplace_back(0.03 * i, 0.03 * j, 0.0);
        uv.push_back(camera.project(T_world_camera.inverse() * corners.back()) + Vec2(noise(rng), noise(rng)));
      }
    Eigen::Matrix<double, 13, 13> P = Eigen::Matrix<double, 13, 13>::Zero();
    P.diagonal() << Vec3::Constant(0.1 * 0.1), Vec4::Constant(0.05 * 0.05), Vec3::Constant(1.0), Vec3::Constant(1.0);
    prior.reset(T_world_camera * SE3::fromRotvec(Vec3(0.03, -0.04, 0.02), Vec3(0.04, -0.03, 0.03)), P);
  }
  bool predict(const Eigen::VectorXd& x, std::vector<PointObservation>* observations) const {
    for (size_t k = 0; k < corners.size(); ++k)
      if (!predictAtRowTime(camera, readout, x.head<13>(), corners[k], &(*observations)[k].h, 1e-3)) return false;
    return true;
  }
  std::vector<PointObservation> observations() const {
    std::vector<PointObservation> out(corners.size());
    for (size_t k = 0; k < corners.size(); ++k) {
      out[k].offset = kKnownPoint;
      out[k].z = uv[k];
    }
    predict(prior.x(), &out);
    return out;
  }
  // The board's maximum-likelihood pose (OpenCV's iterative PnP, Levenberg-Marquardt).
  Vec3 pnpPosition() const {
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image;
    for (size_t k = 0; k < corners.size(); ++k) {
      object.emplace_back(corners[k].x(), corners[k].y(), corners[k].z());
      image.emplace_back(uv[k].x(), uv[k].y());
    }
    const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
    const std::vector<double> dist(camera.distortion.begin(), camera.distortion.begin() + camera.num_distortion);
    cv::Mat rvec, tvec;
    cv::solvePnP(object, image, K, dist, rvec, tvec, false, cv::SOLVEPNP_ITERATIVE);
    Vec3 rotvec, t;
    cv::cv2eigen(rvec, rotvec);
    cv::cv2eigen(tvec, t);
    return SE3::fromRotvec(rotvec, t).inverse().t();
  }
};

// The iterated update of known points alone forms its gain in 7 x 7 (the push-through identity)
// and writes P's update as a rank-7 product; the batch update keeps S (2m x 2m) and the rank-2m
// one. With a map whose points are correlated with the camera, every row of P is compared.
TEST(EkfUpdate, OneIterationIsTheBatchUpdate) {
  BoardReturn b;
  for (int i = 0; i < 4; ++i) {
    Eigen::MatrixXd cross = Eigen::MatrixXd::Zero(3, b.prior.size());
    cross.leftCols<3>() = 0.5 * 0.1 * 0.1 * Mat3::Identity();  // half the camera position's variance
    b.prior.append(Vec3(0.1 * i, -0.05 * i, 0.5), Mat3::Identity() * 0.02, cross);
  }
  const auto relinearise = [&](const Eigen::VectorXd& x, std::vector<PointObservation>* o) { return b.predict(x, o); };
  EkfState batch = b.prior, iterated = b.prior;
  ASSERT_TRUE(batchUpdate(batch, b.observations(), 0.05));
  std::vector<PointObservation> observations = b.observations();
  ASSERT_TRUE(iteratedUpdate(iterated, &observations, 0.05, relinearise, 1));
  // Both round off: S's 108 x 108 factorisation by 9e-11 of the update, the 7 x 7 gain by 3e-12
  // (against the dense formula in long double, measured once).
  EXPECT_LT((batch.x() - iterated.x()).norm(), 1e-9 * (b.prior.x() - batch.x()).norm());
  // Against the size of the update itself (P's untouched velocity entries would dilute it).
  EXPECT_LT((batch.P() - iterated.P()).norm(), 1e-10 * (b.prior.P() - batch.P()).norm());
  EXPECT_GT((iterated.P().bottomRightCorner<12, 12>() - b.prior.P().bottomRightCorner<12, 12>()).norm(), 1e-3)
      << "the map's block moves with the camera";
}

// The filter's own P is singular along q (renormaliseQuaternion projects q's length out), and a
// board may show only a few corners (2m < 7: H's rank under 6): the 7 x 7 gain still gives the
// batch update's x and P, and P stays positive semi-definite.
TEST(EkfUpdate, OneIterationIsTheBatchUpdateWithFewCornersAndTheFiltersCovariance) {
  for (const size_t corners : {1, 3, 54}) {
    BoardReturn b;
    b.corners.resize(corners);
    b.uv.resize(corners);
    Eigen::MatrixXd cross = Eigen::MatrixXd::Zero(3, b.prior.size());
    cross.leftCols<3>() = 0.5 * 0.1 * 0.1 * Mat3::Identity();
    b.prior.append(Vec3(0.1, -0.05, 0.5), Mat3::Identity() * 0.02, cross);
    b.prior.P().block<4, 4>(EkfState::kQ, EkfState::kQ) += 1e-4 * Eigen::Matrix4d::Ones();  // correlated q
    b.prior.renormaliseQuaternion();
    const Vec4 q = b.prior.q();
    ASSERT_LT((b.prior.P().block<4, 4>(EkfState::kQ, EkfState::kQ) * q).norm(), 1e-12);
    const auto relinearise = [&](const Eigen::VectorXd& x, std::vector<PointObservation>* o) { return b.predict(x, o); };
    EkfState batch = b.prior, iterated = b.prior;
    ASSERT_TRUE(batchUpdate(batch, b.observations(), 0.05));
    std::vector<PointObservation> observations = b.observations();
    ASSERT_TRUE(iteratedUpdate(iterated, &observations, 0.05, relinearise, 1));
    EXPECT_LT((batch.x() - iterated.x()).norm(), 1e-9 * (b.prior.x() - batch.x()).norm()) << corners << " corners";
    EXPECT_LT((batch.P() - iterated.P()).norm(), 1e-9 * (b.prior.P() - batch.P()).norm()) << corners << " corners";
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(iterated.P()).eigenvalues().minCoeff(),
              -1e-12 * iterated.P().norm())
        << corners << " corners";
  }
}

// Corners seen at their rows' times depend on the velocities too: S over all 13 camera entries, and
// the iterated update's first step, are the dense formulas' with the full H, and the velocities
// learn from the corners.
TEST(EkfUpdate, CornersAtTheirRowsTimesUpdateTheVelocitiesAsTheDenseFormula) {
  BoardReturn b;
  b.readout = 0.03;
  b.prior.x().segment<3>(EkfState::kV) = Vec3(0.1, -0.2, 0.05);
  b.prior.x().segment<3>(EkfState::kW) = Vec3(0.5, 1.0, -0.3);
  // After a prediction: the velocities 0.1 m/s and 0.2 rad/s uncertain, correlated with the pose.
  b.prior.P().diagonal().segment<3>(EkfState::kV).setConstant(0.01);
  b.prior.P().diagonal().segment<3>(EkfState::kW).setConstant(0.04);
  const Eigen::MatrixXd A = Eigen::MatrixXd::Random(13, 13) * 0.01;
  b.prior.P() += A * A.transpose();
  b.prior.renormaliseQuaternion();
  Eigen::MatrixXd cross = Eigen::MatrixXd::Zero(3, b.prior.size());
  cross.leftCols<3>() = 0.5 * 0.1 * 0.1 * Mat3::Identity();
  b.prior.append(Vec3(0.1, -0.05, 0.5), Mat3::Identity() * 0.02, cross);
  const std::vector<PointObservation> obs = b.observations();
  ASSERT_TRUE(obs[0].h.row_timed);
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(2 * obs.size(), b.prior.size());
  Eigen::VectorXd nu(H.rows());
  for (size_t k = 0; k < obs.size(); ++k) {
    H.block<2, 13>(2 * k, 0) << obs[k].h.H_r, obs[k].h.H_q, obs[k].h.H_v, obs[k].h.H_w;
    nu.segment<2>(2 * k) = obs[k].z - obs[k].h.uv_distorted;
  }
  const double sigma = 0.05;
  const Eigen::MatrixXd S = H * b.prior.P() * H.transpose() + sigma * sigma * Eigen::MatrixXd::Identity(H.rows(), H.rows());
  EXPECT_LT((innovationCovariance(b.prior, obs, sigma) - S).norm(), 1e-9 * S.norm());
  EXPECT_LT((pointInnovationCovariance(b.prior, obs[5].h, kKnownPoint, sigma) - S.block<2, 2>(10, 10)).norm(),
            1e-9 * S.norm());
  const Eigen::MatrixXd K = b.prior.P() * H.transpose() * S.inverse();
  const Eigen::VectorXd step = K * nu;

  const auto relinearise = [&](const Eigen::VectorXd& x, std::vector<PointObservation>* o) { return b.predict(x, o); };
  EkfState iterated = b.prior;
  std::vector<PointObservation> observations = obs;
  ASSERT_TRUE(iteratedUpdate(iterated, &observations, sigma, relinearise, 1));
  // S (108 x 108) spans 1e-5 to 1e4 px^2: both factorisations round to about 1e-4 of the step.
  EXPECT_LT((iterated.x() - b.prior.x() - step).norm(), 1e-3 * step.norm());
  EXPECT_LT((iterated.P() - (b.prior.P() - K * S * K.transpose())).norm(), 1e-3 * (K * S * K.transpose()).norm());
  EXPECT_GT((iterated.w() - b.prior.w()).norm(), 1e-3) << "the angular velocity moves";
}

// A row-timed point with a block in the state (hybrid's tracked points) batched with a frame-time
// one (zero over v and w): S, one point's S with its cross terms, and the update are the dense
// formulas' with the full H.
TEST(EkfUpdate, RowTimedMapPointBesideAFrameTimeOneIsTheDenseFormula) {
  BoardReturn b;
  b.prior.x().segment<3>(EkfState::kW) = Vec3(0.5, 1.0, -0.3);
  const Eigen::MatrixXd A = Eigen::MatrixXd::Random(13, 13) * 0.01;
  b.prior.P() += A * A.transpose();
  b.prior.renormaliseQuaternion();
  Eigen::MatrixXd cross = Eigen::MatrixXd::Zero(3, b.prior.size());
  cross.leftCols<3>() = 0.5 * 0.1 * 0.1 * Mat3::Identity();
  const int offset = b.prior.append(Vec3(0.1, -0.05, 0.5), Mat3::Identity() * 0.02, cross);
  PointObservation row_timed, frame_time;
  row_timed.offset = offset;
  ASSERT_TRUE(predictAtRowTime(b.camera, 0.03, b.prior.x().head<13>(), Vec3(b.prior.x().segment<3>(offset)),
                               &row_timed.h, 1e-3));
  row_timed.z = row_timed.h.uv_distorted + Vec2(0.8, -0.4);
  frame_time.offset = kKnownPoint;
  ASSERT_TRUE(predictMeasurement(b.camera, b.prior.r(), b.prior.q(), b.corners[10], &frame_time.h));
  frame_time.z = frame_time.h.uv_distorted + Vec2(-0.3, 0.5);
  const std::vector<PointObservation> obs = {row_timed, frame_time};
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(4, b.prior.size());
  H.block<2, 13>(0, 0) << row_timed.h.H_r, row_timed.h.H_q, row_timed.h.H_v, row_timed.h.H_w;
  H.block<2, 3>(0, offset) = row_timed.h.H_y;
  H.block<2, 7>(2, 0) << frame_time.h.H_r, frame_time.h.H_q;
  Eigen::VectorXd nu(4);
  nu << row_timed.z - row_timed.h.uv_distorted, frame_time.z - frame_time.h.uv_distorted;
  const double sigma = 0.5;
  const Eigen::MatrixXd S = H * b.prior.P() * H.transpose() + sigma * sigma * Eigen::MatrixXd::Identity(4, 4);
  EXPECT_LT((innovationCovariance(b.prior, obs, sigma) - S).norm(), 1e-9 * S.norm());
  EXPECT_LT((pointInnovationCovariance(b.prior, row_timed.h, offset, sigma) - S.topLeftCorner<2, 2>()).norm(),
            1e-9 * S.norm());
  const Eigen::MatrixXd K = b.prior.P() * H.transpose() * S.inverse();
  EkfState expected = b.prior;
  expected.x() += K * nu;
  expected.P() -= K * S * K.transpose();
  expected.renormaliseQuaternion();
  EkfState s = b.prior;
  ASSERT_TRUE(batchUpdate(s, obs, sigma));
  EXPECT_LT((s.x() - expected.x()).norm(), 1e-9 * (expected.x() - b.prior.x()).norm());
  EXPECT_LT((s.P() - expected.P()).norm(), 1e-9 * b.prior.P().norm());
}

// A shift every point shares (a motion-blurred frame's, hybrid/exposure_shift.h): one iteration is
// kalmanUpdate's dense formula with R = sigma^2 I + J C J^T (J stacks m 2 x 2 identities), in the
// camera-only form (board corners at the frame's time) and in the dense one (at their rows'
// times). The corners are measured 0.3 px off together, which the shift's noise takes up in part.
TEST(EkfUpdate, ASharedShiftIsTheDenseFormulaWithItsCorrelatedNoise) {
  for (const double readout : {0.0, 0.03}) {
    BoardReturn b;
    b.readout = readout;
    b.prior.x().segment<3>(EkfState::kW) = Vec3(0.5, 1.0, -0.3);
    std::vector<PointObservation> obs = b.observations();
    const int m = static_cast<int>(obs.size());
    ASSERT_EQ(obs[0].h.row_timed, readout > 0);
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(2 * m, b.prior.size());
    Eigen::VectorXd nu(2 * m);
    for (int k = 0; k < m; ++k) {
      obs[k].z += Vec2(0.3, -0.2);
      if (obs[k].h.row_timed) H.block<2, 13>(2 * k, 0) << obs[k].h.H_r, obs[k].h.H_q, obs[k].h.H_v, obs[k].h.H_w;
      else H.block<2, 7>(2 * k, 0) << obs[k].h.H_r, obs[k].h.H_q;
      nu.segment<2>(2 * k) = obs[k].z - obs[k].h.uv_distorted;
    }
    const double sigma = 0.05;
    Mat2 C;
    C << 0.04, 0.01, 0.01, 0.02;  // a shift of 0.1-0.2 px, more than each corner's own noise
    Eigen::MatrixXd S = H * b.prior.P() * H.transpose() + sigma * sigma * Eigen::MatrixXd::Identity(2 * m, 2 * m);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) S.block<2, 2>(2 * i, 2 * j) += C;
    EkfState dense = b.prior;
    ASSERT_TRUE(kalmanUpdate(dense, b.prior.P() * H.transpose(), S, nu));
    const auto relinearise = [&](const Eigen::VectorXd& x, std::vector<PointObservation>* o) { return b.predict(x, o); };
    EkfState shared = b.prior, independent = b.prior;
    std::vector<PointObservation> o1 = obs, o2 = obs;
    ASSERT_TRUE(iteratedUpdate(shared, &o1, PointNoise(sigma, C), relinearise, 1));
    ASSERT_TRUE(iteratedUpdate(independent, &o2, sigma, relinearise, 1));
    const double step = (dense.x() - b.prior.x()).norm(), shrunk = (b.prior.P() - dense.P()).norm();
    // As above, S's spread rounds both factorisations to about 1e-4 of the step.
    EXPECT_LT((shared.x() - dense.x()).norm(), 1e-3 * step) << "readout " << readout;
    EXPECT_LT((shared.P() - dense.P()).norm(), 1e-3 * shrunk) << "readout " << readout;
    // Taken for each corner's own noise, the shift moves the camera (and the velocities) further.
    EXPECT_GT((independent.x() - dense.x()).norm(), 20 * (shared.x() - dense.x()).norm()) << "readout " << readout;
  }
}

// A camera covariance broken by round-off (negative position variances) makes S indefinite: the
// iterated update of known points refuses it as the batch update does, and leaves the state.
TEST(EkfUpdate, IteratedUpdateRefusesAnIndefiniteCameraCovariance) {
  BoardReturn b;
  b.prior.P().topLeftCorner<3, 3>() = -1e-2 * Mat3::Identity();
  const auto relinearise = [&](const Eigen::VectorXd& x, std::vector<PointObservation>* o) { return b.predict(x, o); };
  EkfState batch = b.prior, iterated = b.prior;
  EXPECT_FALSE(batchUpdate(batch, b.observations(), 0.05));
  std::vector<PointObservation> observations = b.observations();
  EXPECT_FALSE(iteratedUpdate(iterated, &observations, 0.05, relinearise));
  EXPECT_EQ(iterated.x(), b.prior.x());
  EXPECT_EQ(iterated.P(), b.prior.P());
}

// From a prior centimetres off, one linearisation lands millimetres from the board's pose; the
// iterations reach OpenCV's PnP solution (the wide prior pulls it by micrometres), and
// the observations leave with the residuals of that solution.
TEST(EkfUpdate, IteratedUpdateReachesThePnpSolutionFromAFarPrior) {
  const BoardReturn b;
  const auto relinearise = [&](const Eigen::VectorXd& x, std::vector<PointObservation>* o) { return b.predict(x, o); };
  const Vec3 pnp = b.pnpPosition();
  ASSERT_LT((pnp - b.T_world_camera.t()).norm(), 3e-3);  // a small board: 0.05 px is about 1 mm

  EkfState batch = b.prior;
  ASSERT_TRUE(batchUpdate(batch, b.observations(), 0.05));
  EkfState iterated = b.prior;
  std::vector<PointObservation> observations = b.observations();
  ASSERT_TRUE(iteratedUpdate(iterated, &observations, 0.05, relinearise));

  EXPECT_GT((batch.r() - pnp).norm(), 5e-3);   // 7 mm
  EXPECT_LT((iterated.r() - pnp).norm(), 2e-5);  // 6 micrometres: the prior's pull
  double squares = 0;
  for (const PointObservation& o : observations) squares += (o.z - o.h.uv_distorted).squaredNorm();
  EXPECT_LT(std::sqrt(squares / (2 * observations.size() - 6)), 0.08);  // the 0.05 px noise, not the prior's miss
}

// The camera alone, its position and the rotation vector of a right perturbation (R = R_0 exp(theta))
// with covariance `pose`, mapped to (r, q) by q = q_0 (1, theta / 2).
EkfState stateWithPoseCovariance(const SE3& T_world_camera, const Eigen::Matrix<double, 6, 6>& pose) {
  EkfState s;
  s.reset(T_world_camera, Eigen::Matrix<double, 13, 13>::Identity() * 1e-6);
  const Vec4 q = s.q();
  Eigen::Matrix<double, 7, 6> G = Eigen::Matrix<double, 7, 6>::Zero();
  G.topLeftCorner<3, 3>().setIdentity();
  G.block<1, 3>(3, 3) = -0.5 * q.tail<3>().transpose();
  G.block<3, 3>(4, 3) = 0.5 * (q(0) * Mat3::Identity() + skew(q.tail<3>()));
  s.P().topLeftCorner<7, 7>() = G * pose * G.transpose();
  return s;
}

// A scalar Kalman update about each axis: the orientation moves by sigma_p^2 / (sigma_p^2 +
// sigma_m^2) of the way to the measurement, its variance shrinks as the formula says, and the
// position moves through its covariance with the turn. A wrong H (sign, frame, factor 2) fails it.
TEST(OrientationUpdate, IsTheScalarKalmanUpdateAboutEachAxis) {
  const SE3 T(rotationFromRotvec(Vec3(0.3, -0.5, 0.2)), Vec3(0.1, -0.2, 0.5));
  const double sp = 0.02, sm = 0.01, c = 0.5 * sp * 0.003;  // rad, rad, cov(r_x, theta_x)
  Eigen::Matrix<double, 6, 6> pose = Eigen::Matrix<double, 6, 6>::Identity() * 1e-6;
  pose.bottomRightCorner<3, 3>() = Mat3::Identity() * sp * sp;
  pose(0, 0) = 0.003 * 0.003;
  pose(0, 3) = pose(3, 0) = c;
  const Vec3 delta(0.004, -0.003, 0.002);  // the measurement's turn from the state, camera frame
  const Mat3 R_measured = T.R() * rotationFromRotvec(delta);
  for (double sign : {1.0, -1.0}) {  // q and -q, one rotation: the same update
    SCOPED_TRACE(sign);
    EkfState s = stateWithPoseCovariance(T, pose);
    s.x().segment<4>(EkfState::kQ) *= sign;  // and its covariance with the rest
    s.P().middleRows<4>(EkfState::kQ) *= sign;
    s.P().middleCols<4>(EkfState::kQ) *= sign;
    ASSERT_TRUE(orientationUpdate(s, R_measured, sm));
    const double gain = sp * sp / (sp * sp + sm * sm);
    const Vec3 moved = rotvecFromRotation(T.R().transpose() * s.T_world_camera().R());
    EXPECT_LT((moved - gain * delta).norm(), 1e-3 * delta.norm());
    EXPECT_NEAR(s.r().x() - T.t().x(), c / (sp * sp + sm * sm) * delta.x(), 1e-3 * c / (sp * sp) * delta.x());
    EXPECT_NEAR(s.r().y(), T.t().y(), 1e-9);
    // Posterior variance about each axis, read back through the same perturbation.
    const double posterior = sp * sp * sm * sm / (sp * sp + sm * sm);
    const Vec4 q = s.q();
    // theta = 2 vec(q_0^-1 q) about the posterior: d theta / d q = 2 [-v, w I - [v]x] for q_0 = (w, v).
    Eigen::Matrix<double, 3, 4> J;
    J.col(0) = -q.tail<3>();
    J.rightCols<3>() = q(0) * Mat3::Identity() - skew(q.tail<3>());
    J *= 2;
    const Mat3 P_theta = J * s.P().block<4, 4>(EkfState::kQ, EkfState::kQ) * J.transpose();
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(P_theta(k, k), posterior, 0.01 * posterior);
  }
}

TEST(OrientationUpdate, RefusesAnIndefiniteCovariance) {
  EkfState s;
  s.reset(SE3(), Eigen::Matrix<double, 13, 13>::Zero());
  s.P()(EkfState::kQ + 1, EkfState::kQ + 1) = -1;
  const Eigen::VectorXd before = s.x();
  const Eigen::MatrixXd P_before = s.P();
  EXPECT_FALSE(orientationUpdate(s, rotationFromRotvec(Vec3(0.01, 0, 0)), 1e-3));
  EXPECT_EQ(s.x(), before);
  EXPECT_EQ(s.P(), P_before);
}

}  // namespace
}  // namespace slamcmp
